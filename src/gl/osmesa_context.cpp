// OSMesa context: Mesa's off-screen API, the fallback where EGL is unavailable. Kept apart from
// gl_api.hpp: osmesa.h brings the legacy GL headers.
#include "engine/error.hpp"
#include "gl/gl_context.hpp"

#include <GL/osmesa.h>

#include <vector>

namespace hemirad {
namespace gl {
using ProcLoader = void* (*)(const char* name);
void loadApi(ProcLoader loader, const char* apiName);
}  // namespace gl

namespace detail {
namespace {

void* osmesaLoader(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

class OsmesaContext final : public GlContext {
public:
    OsmesaContext() {
        const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                                  OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 4,
                                  OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        m_context = OSMesaCreateContextAttribs(attributes, nullptr);
        if (!m_context) throw Error("OSMesa: cannot create an OpenGL 4.5 core context");
    }
    ~OsmesaContext() override { OSMesaDestroyContext(m_context); }
    void makeCurrent() override {
        // OSMesa needs a colour buffer to be current; Hemirad renders into FBOs only.
        if (!OSMesaMakeCurrent(m_context, m_pixel.data(), GL_UNSIGNED_BYTE, 1, 1))
            throw Error("OSMesa: OSMesaMakeCurrent failed");
        gl::loadApi(osmesaLoader, "OSMesa");
    }
    void release() override { OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0); }
    const char* api() const override { return "osmesa"; }

private:
    OSMesaContext m_context = nullptr;
    std::vector<unsigned char> m_pixel = std::vector<unsigned char>(4);
};

}  // namespace

std::unique_ptr<GlContext> createOsmesaContext() { return std::make_unique<OsmesaContext>(); }

}  // namespace detail
}  // namespace hemirad
