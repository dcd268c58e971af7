// EGL surfaceless context (Mesa): one display per process, one context per worker.
#include "engine/error.hpp"
#include "gl/gl_api.hpp"
#include "gl/gl_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <mutex>

namespace hemirad::detail {
namespace {

std::string eglErrorText(EGLint code) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "EGL error 0x%04x", code);
    return buffer;
}

EGLDisplay sharedDisplay() {
    static std::once_flag once;
    static EGLDisplay display = EGL_NO_DISPLAY;
    static std::string failure;
    std::call_once(once, [] {
        auto getPlatformDisplay =
            reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (!getPlatformDisplay) {
            failure = "EGL: eglGetPlatformDisplayEXT is missing";
            return;
        }
        EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        EGLint major = 0, minor = 0;
        if (d == EGL_NO_DISPLAY || !eglInitialize(d, &major, &minor)) {
            failure = "EGL: no surfaceless Mesa display (" + eglErrorText(eglGetError()) + ")";
            return;
        }
        display = d;
    });
    if (display == EGL_NO_DISPLAY) throw Error(failure);
    return display;
}

/// Contexts are made, made current, released and destroyed one at a time, whatever the driver's
/// own locking.
std::mutex g_lifetimeMutex;

void* eglLoader(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

class EglContext final : public GlContext {
public:
    EglContext() : m_display(sharedDisplay()) {
        const std::lock_guard<std::mutex> lock(g_lifetimeMutex);
        if (!eglBindAPI(EGL_OPENGL_API)) throw Error("EGL: desktop OpenGL is not available (" + eglErrorText(eglGetError()) + ")");
        const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        if (!eglChooseConfig(m_display, configAttributes, &config, 1, &count) || count == 0) config = nullptr;
        const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                            EGL_NONE};
        m_context = eglCreateContext(m_display, config, EGL_NO_CONTEXT, contextAttributes);
        if (m_context == EGL_NO_CONTEXT)
            throw Error("EGL: cannot create an OpenGL 4.5 core context (" + eglErrorText(eglGetError()) + ")");
    }
    ~EglContext() override {
        const std::lock_guard<std::mutex> lock(g_lifetimeMutex);
        if (eglGetCurrentContext() == m_context) eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(m_display, m_context);
    }
    void makeCurrent() override {
        const std::lock_guard<std::mutex> lock(g_lifetimeMutex);
        eglBindAPI(EGL_OPENGL_API);
        if (!eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context))
            throw Error("EGL: eglMakeCurrent failed (" + eglErrorText(eglGetError()) + ")");
        gl::loadApi(eglLoader, "EGL");
    }
    void release() override {
        const std::lock_guard<std::mutex> lock(g_lifetimeMutex);
        eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    const char* api() const override { return "egl"; }

private:
    EGLDisplay m_display;
    EGLContext m_context = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<GlContext> createEglContext() { return std::make_unique<EglContext>(); }

}  // namespace hemirad::detail
