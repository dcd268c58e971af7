// Headless OpenGL 4.5 core contexts: EGL surfaceless (Mesa) first, OSMesa as the fallback.
#pragma once

#include <memory>
#include <mutex>
#include <string>

namespace hemirad {

enum class GlApiKind { Auto, Egl, OSMesa };


/// A GL context without a default framebuffer (render into FBOs). One thread at a time may have it
/// current; contexts are independent (no sharing).
class GlContext {
public:
    virtual ~GlContext() = default;
    /// Makes the context current on the calling thread and loads the GL entry points.
    virtual void makeCurrent() = 0;
    /// Detaches the context from the calling thread.
    virtual void release() = 0;
    virtual const char* api() const = 0;
};

/// Creates a GL 4.5 core context. Auto tries EGL (EGL_PLATFORM_SURFACELESS_MESA), then OSMesa.
/// Throws hemirad::Error saying why each API failed.
std::unique_ptr<GlContext> createHeadlessContext(GlApiKind kind);

/// The one lock of this process for a driver whose contexts may not run GL commands at once (Mesa's
/// llvmpipe: a display's contexts share one screen and its rasterizer). Whoever draws on such a driver
/// holds it over each GL command sequence: the workers of one computation and any computations
/// running at once in the same process (two Python threads, say) all take turns.
std::mutex& sharedDriverMutex();

namespace detail {
std::unique_ptr<GlContext> createEglContext();     // egl_context.cpp
std::unique_ptr<GlContext> createOsmesaContext();  // osmesa_context.cpp
}  // namespace detail

}  // namespace hemirad
