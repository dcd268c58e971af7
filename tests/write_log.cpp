// A probe the tests preload (LD_PRELOAD) to see how a program cuts its output into write(2) calls,
// without ptrace, which CI containers may forbid. Each write or writev call on descriptor 1
// or 2 appends one record to the file named by HEMIRAD_WRITE_LOG, then the call goes on to the real
// function (dlsym(RTLD_NEXT)). A record, length-prefixed so that bytes of any value split exactly:
//
//     "<fd> <length>\n" <length bytes, as the call passed them> "\n"
//
// One writev(2) per record on a file opened with O_APPEND, so processes and MPI ranks can share a log.
// Only calls through the dynamic symbol are seen: glibc's stdio (std::cerr, fprintf) writes through
// its own internal entry, so text printed that way is not logged (see tests/support.hpp).
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/syscall.h>
#include <sys/uio.h>
#include <unistd.h>

namespace {

using WriteFn = ssize_t (*)(int, const void*, size_t);
using WritevFn = ssize_t (*)(int, const iovec*, int);

constexpr int kMaxPieces = 64;  // a writev of more pieces is passed on but not logged

// Set up before main (the constructor) so that a write from a signal handler needs neither getenv
// nor dlsym; resolved on first use where a library writes before the constructor ran.
char g_logPath[PATH_MAX];
WriteFn g_realWrite = nullptr;
WritevFn g_realWritev = nullptr;

__attribute__((constructor)) void setUp() {
    const char* path = std::getenv("HEMIRAD_WRITE_LOG");
    if (path && std::strlen(path) < sizeof g_logPath) std::strcpy(g_logPath, path);
    g_realWrite = reinterpret_cast<WriteFn>(::dlsym(RTLD_NEXT, "write"));
    g_realWritev = reinterpret_cast<WritevFn>(::dlsym(RTLD_NEXT, "writev"));
}

/// Writes `value` in decimal at `out` (room for 20 digits); returns the digits' count. Unlike
/// snprintf, safe in a signal handler.
int decimal(char* out, unsigned long long value) {
    char digits[20];
    int n = 0;
    do digits[n++] = char('0' + value % 10);
    while ((value /= 10) != 0);
    for (int i = 0; i < n; ++i) out[i] = digits[n - 1 - i];
    return n;
}

/// Appends one record of `count` pieces (whose lengths add up to `length`) for descriptor `fd`. The
/// log is written with raw system calls, so that it never comes back here; errno is kept.
void record(int fd, const iovec* pieces, int count, size_t length) {
    if ((fd != STDOUT_FILENO && fd != STDERR_FILENO) || g_logPath[0] == '\0' || count < 0 || count > kMaxPieces)
        return;
    const int savedErrno = errno;
    const int log = int(::syscall(SYS_openat, AT_FDCWD, g_logPath, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644));
    if (log >= 0) {
        char header[48];
        int headerLength = decimal(header, unsigned(fd));
        header[headerLength++] = ' ';
        headerLength += decimal(header + headerLength, length);
        header[headerLength++] = '\n';
        iovec all[kMaxPieces + 2];
        all[0] = {header, size_t(headerLength)};
        for (int i = 0; i < count; ++i) all[i + 1] = pieces[i];
        all[count + 1] = {const_cast<char*>("\n"), 1};
        ::syscall(SYS_writev, log, all, count + 2);
        ::syscall(SYS_close, log);
    }
    errno = savedErrno;
}

}  // namespace

extern "C" ssize_t write(int fd, const void* data, size_t length) {
    if (!g_realWrite) g_realWrite = reinterpret_cast<WriteFn>(::dlsym(RTLD_NEXT, "write"));
    const ssize_t n = g_realWrite(fd, data, length);
    const iovec piece = {const_cast<void*>(data), length};
    record(fd, &piece, 1, length);
    return n;
}

extern "C" ssize_t writev(int fd, const iovec* pieces, int count) {
    if (!g_realWritev) g_realWritev = reinterpret_cast<WritevFn>(::dlsym(RTLD_NEXT, "writev"));
    const ssize_t n = g_realWritev(fd, pieces, count);
    size_t length = 0;
    for (int i = 0; i < count; ++i) length += pieces[i].iov_len;
    record(fd, pieces, count, length);
    return n;
}
