// A fault for the MPI tests, preloaded into one rank (LD_PRELOAD): when the rank renames a file onto
// a path whose file name is HEMIRAD_TEST_INTERRUPT_AT (a sharded F's manifest, which rank 0 writes
// once every rank has renamed its shard into place), the job is interrupted right there, as by Ctrl-C:
// SIGINT to the rank's parent (mpirun, which ends the job's ranks with SIGTERM), and the rename waits
// for that signal instead of happening. It says when it interrupts, so that a test can tell the fault
// was in place.
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>

#include <dlfcn.h>
#include <unistd.h>

namespace {

using RenameFn = int (*)(const char*, const char*);

void say(const char* text, std::size_t length) { [[maybe_unused]] auto n = ::write(STDERR_FILENO, text, length); }

const char* fileName(const char* path) {
    const char* slash = std::strrchr(path, '/');
    return slash ? slash + 1 : path;
}

}  // namespace

extern "C" int rename(const char* from, const char* to) {
    const char* at = std::getenv("HEMIRAD_TEST_INTERRUPT_AT");
    if (at && to && std::strcmp(fileName(to), at) == 0) {
        const char interrupting[] = "interrupt_at_rename: interrupting\n";
        say(interrupting, sizeof interrupting - 1);
        ::kill(::getppid(), SIGINT);
        for (;;) ::pause();  // mpirun's SIGTERM ends the rank here
    }
    static const auto real = reinterpret_cast<RenameFn>(::dlsym(RTLD_NEXT, "rename"));
    if (!real) {
        errno = ENOSYS;
        return -1;
    }
    return real(from, to);
}
