// OSMesa context: Mesa's off-screen API, the fallback where EGL is unavailable. Kept apart from
// gl_api.hpp: osmesa.h brings the legacy GL headers. libOSMesa is loaded with dlopen when a context
// is first asked for, so the binary runs where it is missing (GPU machines use EGL).
#include "engine/error.hpp"
#include "gl/gl_context.hpp"

#include <GL/osmesa.h>
#include <dlfcn.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace hemirad {
namespace gl {
using ProcLoader = void* (*)(const char* name);
void loadApi(ProcLoader loader, const char* apiName);
}  // namespace gl

namespace detail {
namespace {

/// The OSMesa entry points Hemirad calls, from the library named by HEMIRAD_OSMESA_LIBRARY, else
/// libOSMesa.so.8 (Debian's libosmesa6), else libOSMesa.so. Loaded once; the handle stays open.
struct OsmesaLibrary {
    decltype(&OSMesaCreateContextAttribs) createContextAttribs = nullptr;
    decltype(&OSMesaDestroyContext) destroyContext = nullptr;
    decltype(&OSMesaMakeCurrent) makeCurrent = nullptr;
    decltype(&OSMesaGetProcAddress) getProcAddress = nullptr;
    std::string error;  ///< why it could not be loaded; empty when it was

    OsmesaLibrary() {
        const char* named = std::getenv("HEMIRAD_OSMESA_LIBRARY");
        std::vector<std::string> names;
        if (named && *named) names = {named};
        else names = {"libOSMesa.so.8", "libOSMesa.so"};
        void* handle = nullptr;
        for (const std::string& name : names) {
            if ((handle = ::dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL))) break;
            const char* why = ::dlerror();
            error += (error.empty() ? "" : "; ") + std::string(why ? why : name + ": not found");
        }
        if (!handle) return;
        auto symbol = [&](const char* name) {
            void* p = ::dlsym(handle, name);
            if (!p && error.empty()) error = std::string("the library lacks ") + name;
            return p;
        };
        error.clear();
        createContextAttribs = reinterpret_cast<decltype(createContextAttribs)>(symbol("OSMesaCreateContextAttribs"));
        destroyContext = reinterpret_cast<decltype(destroyContext)>(symbol("OSMesaDestroyContext"));
        makeCurrent = reinterpret_cast<decltype(makeCurrent)>(symbol("OSMesaMakeCurrent"));
        getProcAddress = reinterpret_cast<decltype(getProcAddress)>(symbol("OSMesaGetProcAddress"));
    }
};

const OsmesaLibrary& osmesa() {
    static const OsmesaLibrary library;
    if (!library.error.empty())
        throw Error("OSMesa: cannot load libOSMesa (" + library.error +
                    "); install libosmesa6 (scripts/install-deps.sh), set HEMIRAD_OSMESA_LIBRARY to its path, or use "
                    "--gl egl");
    return library;
}

void* osmesaLoader(const char* name) { return reinterpret_cast<void*>(osmesa().getProcAddress(name)); }

class OsmesaContext final : public GlContext {
public:
    OsmesaContext() {
        const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                                  OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                                  OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        m_context = osmesa().createContextAttribs(attributes, nullptr);
        if (!m_context) throw Error("OSMesa: cannot create an OpenGL 4.5 core context");
    }
    ~OsmesaContext() override { osmesa().destroyContext(m_context); }
    void makeCurrent() override {
        // OSMesa needs a colour buffer to be current; Hemirad renders into FBOs only.
        if (!osmesa().makeCurrent(m_context, m_pixel.data(), GL_UNSIGNED_BYTE, 1, 1))
            throw Error("OSMesa: OSMesaMakeCurrent failed");
        gl::loadApi(osmesaLoader, "OSMesa");
    }
    void release() override { osmesa().makeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0); }
    const char* api() const override { return "osmesa"; }

private:
    OSMesaContext m_context = nullptr;
    std::vector<unsigned char> m_pixel = std::vector<unsigned char>(4);
};

}  // namespace

std::unique_ptr<GlContext> createOsmesaContext() { return std::make_unique<OsmesaContext>(); }

}  // namespace detail
}  // namespace hemirad
