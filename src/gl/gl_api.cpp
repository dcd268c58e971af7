// The GL entry-point table and its loader.
#include "gl/gl_api.hpp"

#include "engine/error.hpp"

#include <cstdio>
#include <mutex>

namespace hemirad::gl {

#define HEMIRAD_GL_DEFINE(name, type) type name = nullptr;
HEMIRAD_GL_FUNCTIONS(HEMIRAD_GL_DEFINE)
#undef HEMIRAD_GL_DEFINE

namespace {
std::mutex g_loadMutex;
std::string g_loadedApi;
}  // namespace

void loadApi(ProcLoader loader, const char* apiName) {
    std::lock_guard<std::mutex> lock(g_loadMutex);
    if (g_loadedApi == apiName) return;
    if (!g_loadedApi.empty())
        throw Error(std::string("OpenGL: cannot mix ") + apiName + " contexts with the " + g_loadedApi +
                    " contexts already used by this process");
#define HEMIRAD_GL_LOAD(name, type)                                                                     \
    name = reinterpret_cast<type>(loader("gl" #name));                                                  \
    if (!name) throw Error(std::string("OpenGL (") + apiName + "): the driver lacks gl" #name " (GL 4.5 core needed)");
    HEMIRAD_GL_FUNCTIONS(HEMIRAD_GL_LOAD)
#undef HEMIRAD_GL_LOAD
    g_loadedApi = apiName;
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
