// AtomicFile: temporary file + rename, with a signal-safe registry of pending temporaries.
#include "engine/atomic_file.hpp"

#include "engine/error.hpp"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sys/stat.h>
#include <unistd.h>

namespace hemirad {
namespace {

// Fixed-size registry so that a signal handler can unlink pending files without allocating.
constexpr int kMaxPending = 64;
constexpr int kMaxPath = 4096;
char g_pending[kMaxPending][kMaxPath];
std::atomic<bool> g_used[kMaxPending];

int registerPending(const std::string& path) {
    if (path.size() >= kMaxPath) return -1;
    for (int k = 0; k < kMaxPending; ++k) {
        bool expected = false;
        if (g_used[k].compare_exchange_strong(expected, true)) {
            std::memcpy(g_pending[k], path.c_str(), path.size() + 1);
            return k;
        }
    }
    return -1;
}

void unregisterPending(const std::string& path) {
    for (int k = 0; k < kMaxPending; ++k)
        if (g_used[k].load() && path == g_pending[k]) g_used[k].store(false);
}

}  // namespace

void requireBinaryStandardOutput() {
    if (::isatty(STDOUT_FILENO) == 1)
        throw Error("cannot write binary data to standard output: it is a terminal; redirect it "
                    "(> FILE or | PROGRAM) or give a file name");
}

WriteMode writeModeFor(bool exists, mode_t mode) {
    if (!exists || S_ISREG(mode)) return WriteMode::Replace;
    if (S_ISDIR(mode)) return WriteMode::Refuse;
    return WriteMode::Direct;  // FIFO, character or block device, socket
}

std::string resolveWriteTarget(const std::string& path) {
    namespace fs = std::filesystem;
    fs::path target(path);
    for (int hops = 0; hops < 40; ++hops) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(target, ec))) return target.string();
        const fs::path next = fs::read_symlink(target, ec);
        if (ec) throw Error(path, 0, "cannot read the symbolic link " + target.string() + ": " + ec.message());
        target = next.is_absolute() ? next : target.parent_path() / next;
    }
    throw Error(path, 0, "too many levels of symbolic links");
}

bool writesInPlace(const std::string& path) {
    if (isStandardOutput(path)) return true;
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 && writeModeFor(true, st.st_mode) == WriteMode::Direct;
}

AtomicFile::AtomicFile(std::string path, bool binary) : m_shown(std::move(path)) {
    if (isStandardOutput(m_shown)) {
        if (binary) requireBinaryStandardOutput();
        m_out = &std::cout;
        return;
    }
    // stat() follows every link, the kernel's own too (/dev/stdout is /proc/self/fd/1, whose "target"
    // may be a pipe with no path): what it finds decides, and only a regular file's links are resolved.
    struct stat st {};
    const bool found = ::stat(m_shown.c_str(), &st) == 0;
    const std::ios::openmode mode = binary ? std::ios::binary | std::ios::trunc : std::ios::trunc;
    switch (writeModeFor(found, st.st_mode)) {
    case WriteMode::Refuse:
        throw Error(m_shown, 0, "is a directory; give a file name to write");
    case WriteMode::Direct:
        // Never replaced: a FIFO's reader, a device, a socket stay what they are. Opening a FIFO waits
        // for its reader, as a shell redirection does.
        m_file.open(m_shown, mode);
        if (!m_file) throw Error(m_shown, 0, std::string("cannot write: ") + std::strerror(errno));
        return;
    case WriteMode::Replace:
        break;
    }
    m_path = resolveWriteTarget(m_shown);
    const bool exists = ::access(m_path.c_str(), F_OK) == 0;
    // A read-only file stays as it is, as cp leaves it (a rename in a writable folder would not).
    if (exists && ::access(m_path.c_str(), W_OK) != 0)
        throw Error(m_shown, 0, std::string("cannot write: ") + std::strerror(errno));
    // A short hidden name beside the target: any name the target may have leaves room for it.
    static std::atomic<unsigned> counter{0};
    const std::filesystem::path folder = std::filesystem::path(m_path).parent_path();
    m_temp = (folder / (".hemirad-tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++))).string();
    registerPending(m_temp);
    m_file.open(m_temp, mode);
    if (!m_file) {
        const int err = errno;
        unregisterPending(m_temp);
        throw Error(m_shown, 0, std::string("cannot write: ") + std::strerror(err));
    }
}

AtomicFile::~AtomicFile() {
    if (m_committed) return;
    if (m_out != &m_file) {
        m_out->flush();  // what was written reaches the reader, as for any target written in place
        return;
    }
    m_file.close();
    if (m_temp.empty()) return;
    std::remove(m_temp.c_str());
    unregisterPending(m_temp);
}

void AtomicFile::commit() {
    m_out->flush();
    if (m_out != &m_file) {
        if (!*m_out) throw Error("writing to standard output failed");
        m_committed = true;
        return;
    }
    const bool ok = static_cast<bool>(m_file);
    m_file.close();
    if (!ok || m_file.fail()) throw Error(m_shown, 0, "write failed (disk full?)");
    if (!m_temp.empty()) {
        if (std::rename(m_temp.c_str(), m_path.c_str()) != 0)
            throw Error(m_shown, 0, std::string("cannot write: ") + std::strerror(errno));
        unregisterPending(m_temp);
    }
    m_committed = true;
}

void AtomicFile::removePendingFiles() noexcept {
    for (int k = 0; k < kMaxPending; ++k)
        if (g_used[k].load()) ::unlink(g_pending[k]);
}

namespace {

extern "C" void removePendingAndExit(int signal) {
    // No partial output: temporaries are removed, finished files were renamed atomically.
    AtomicFile::removePendingFiles();
    const char message[] = "\nhemirad: interrupted; no partial output was written\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, message, sizeof message - 1);
    ::_exit(128 + signal);
}

}  // namespace

void AtomicFile::removePendingFilesOnInterrupt() {
    std::signal(SIGINT, removePendingAndExit);
    std::signal(SIGTERM, removePendingAndExit);
}

}  // namespace hemirad
