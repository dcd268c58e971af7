// The GL entry-point table and its loader.
#include "gl/gl_api.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

namespace hemirad::gl {

#define HEMIRAD_GL_DEFINE(name, type) type name = nullptr;
HEMIRAD_GL_FUNCTIONS(HEMIRAD_GL_DEFINE)
#undef HEMIRAD_GL_DEFINE

namespace {
std::mutex g_loadMutex;
std::vector<std::string> g_loadedApis;  // the first loaded the table; the rest matched it
}  // namespace

void loadApi(ProcLoader loader, const char* apiName) {
    std::lock_guard<std::mutex> lock(g_loadMutex);
    if (std::find(g_loadedApis.begin(), g_loadedApis.end(), apiName) != g_loadedApis.end()) return;
    if (!g_loadedApis.empty()) {
        // A second window-system API may share the table only if it resolves to the very same
        // entry points: true for EGL next to GLFW under glvnd (both hand out libGLdispatch's
        // context-independent stubs), false for OSMesa next to either.
#define HEMIRAD_GL_COMPARE(name, type)                                                                  \
    if (reinterpret_cast<type>(loader("gl" #name)) != name)                                             \
        throw Error(std::string("OpenGL: cannot mix ") + apiName + " contexts with the " + g_loadedApis[0] + \
                    " contexts already used by this process (gl" #name " resolves differently)");
        HEMIRAD_GL_FUNCTIONS(HEMIRAD_GL_COMPARE)
#undef HEMIRAD_GL_COMPARE
        g_loadedApis.emplace_back(apiName);
        return;
    }
#define HEMIRAD_GL_LOAD(name, type)                                                                     \
    name = reinterpret_cast<type>(loader("gl" #name));                                                  \
    if (!name) throw Error(std::string("OpenGL (") + apiName + "): the driver lacks gl" #name " (GL 4.5 core needed)");
    HEMIRAD_GL_FUNCTIONS(HEMIRAD_GL_LOAD)
#undef HEMIRAD_GL_LOAD
    g_loadedApis.emplace_back(apiName);
}

void check(const char* what) {
    const GLenum error = GetError();
    if (error == GL_NO_ERROR) return;
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", error);
    while (GetError() != GL_NO_ERROR) {
    }
    throw Error(std::string("OpenGL: ") + what + " failed with GL error " + code);
}

std::string describeContext() {
    const auto* version = reinterpret_cast<const char*>(GetString(GL_VERSION));
    const auto* renderer = reinterpret_cast<const char*>(GetString(GL_RENDERER));
    return std::string(version ? version : "?") + " | " + (renderer ? renderer : "?");
}

}  // namespace hemirad::gl
