// Choosing a headless context API.
#include "gl/gl_context.hpp"

#include "engine/error.hpp"

namespace hemirad {

std::mutex& sharedDriverMutex() {
    static std::mutex driver;
    return driver;
}

std::unique_ptr<GlContext> createHeadlessContext(GlApiKind kind) {
    if (kind == GlApiKind::Egl) return detail::createEglContext();
    if (kind == GlApiKind::OSMesa) return detail::createOsmesaContext();
    std::string eglFailure;
    try {
        return detail::createEglContext();
    } catch (const Error& e) {
        eglFailure = e.what();
    }
    try {
        return detail::createOsmesaContext();
    } catch (const Error& e) {
        throw Error("no OpenGL 4.5 context: " + eglFailure + "; " + e.what() +
                    " (install libegl-mesa0 or libosmesa6; see scripts/install-deps.sh)");
    }
}

}  // namespace hemirad
