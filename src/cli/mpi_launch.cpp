// Launcher detection and the MPI module's loading (see mpi_launch.hpp).
#include "cli/mpi_launch.hpp"

#include "engine/console.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <initializer_list>
#include <string>

namespace hemirad::cli {
namespace {

constexpr const char* kModule = "hemirad-mpi.so";

/// The first of these environment variables that is set, or null.
const char* firstSet(std::initializer_list<const char*> names) {
    for (const char* name : names)
        if (const char* value = std::getenv(name)) return value;
    return nullptr;
}

/// "rank R of K: " as the launcher set them ("rank R: " without the size), or "" where it set no rank
/// we know: in front of a message that this rank prints alone, before MPI can gather anything.
std::string rankPrefix() {
    const char* rank = firstSet({"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"});
    if (!rank) return "";
    const char* size = firstSet({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"});
    return "rank " + std::string(rank) + (size ? " of " + std::string(size) : std::string()) + ": ";
}

/// The folder of the running executable (from /proc/self/exe), with a trailing '/'; empty if unknown.
std::string executableFolder() {
    char path[PATH_MAX];
    const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
    if (n <= 0) return "";
    const std::string exe(path, std::size_t(n));
    const std::size_t slash = exe.rfind('/');
    return slash == std::string::npos ? "" : exe.substr(0, slash + 1);
}

}  // namespace

bool launchedByMpiLauncher() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS"})
        if (std::getenv(name)) return true;
    return false;
}

int runMpiModule(int argc, char** argv) {
    const std::string path = executableFolder() + kModule;
    // RTLD_LOCAL: the module's copy of hemirad stays its own (it binds to itself, -Bsymbolic).
    void* module = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    using Entry = int (*)(int, char**);
    Entry entry = module ? reinterpret_cast<Entry>(::dlsym(module, "hemirad_mpi_main")) : nullptr;
    if (!entry) {
        const std::string why = module ? std::string("no hemirad_mpi_main in it") : std::string(::dlerror());
        if (module) ::dlclose(module);
        // Every rank that fails says so: without MPI no rank can tell another, and a rank that loaded
        // the module learns of this one's exit only from mpirun's SIGTERM ("interrupted").
        printError(rankPrefix() + "started by an MPI launcher, but its MPI module " + path + " cannot be used: " +
                   why + " (build with HEMIRAD_WITH_MPI=ON, and keep hemirad-mpi.so next to hemirad)");
        return 1;
    }
    return entry(argc, argv);
}

}  // namespace hemirad::cli
