// A probe the tests preload (LD_PRELOAD) to give a program another /proc/meminfo, so that the memory
// it sees available (engine/memory.cpp: MemAvailable, read through std::ifstream, whose fopen64 is
// the dynamic symbol) is the test's: fopen or fopen64 of /proc/meminfo opens the file named by
// HEMIRAD_TEST_MEMINFO instead, every other path the real function (dlsym(RTLD_NEXT)) opens.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <dlfcn.h>

namespace {

using OpenFn = FILE* (*)(const char*, const char*);

const char* redirected(const char* path) {
    const char* fake = std::getenv("HEMIRAD_TEST_MEMINFO");
    return fake && path && std::strcmp(path, "/proc/meminfo") == 0 ? fake : path;
}

}  // namespace

extern "C" FILE* fopen(const char* path, const char* mode) {
    static const auto real = reinterpret_cast<OpenFn>(::dlsym(RTLD_NEXT, "fopen"));
    return real(redirected(path), mode);
}

extern "C" FILE* fopen64(const char* path, const char* mode) {
    static const auto real = reinterpret_cast<OpenFn>(::dlsym(RTLD_NEXT, "fopen64"));
    return real(redirected(path), mode);
}
