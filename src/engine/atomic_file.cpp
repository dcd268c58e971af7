// AtomicFile: exclusive temporary file + fsync + rename, with a signal-safe registry of pending temporaries.
#include "engine/atomic_file.hpp"

#include "engine/error.hpp"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <random>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hemirad {
namespace {

// Fixed-size registry so that a signal handler can unlink pending files without allocating.
constexpr int kMaxPending = 64;
constexpr int kMaxPath = 4096;
char g_pending[kMaxPending][kMaxPath];
std::atomic<bool> g_used[kMaxPending];
/// Non-zero once the process reported its failure (exitQuietlyOnInterrupt): the status to exit with.
std::atomic<int> g_reportedFailure{0};
static_assert(std::atomic<int>::is_always_lock_free, "read in a signal handler");

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

/// The folder of `path` synced, so that a rename in it survives a crash. Best effort: some file
/// systems cannot sync a folder, and the file itself was synced before the rename.
void syncFolder(const std::string& path) {
    std::string folder = std::filesystem::path(path).parent_path().string();
    if (folder.empty()) folder = ".";
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    [[maybe_unused]] const int ignored = ::fsync(fd);
    ::close(fd);
}

/// A random number drawn once per process (with the PID and the host name it tells apart writers
/// that share a folder).
std::uint32_t processNonce() {
    static const std::uint32_t nonce = [] {
        std::uint32_t value = std::uint32_t(std::chrono::steady_clock::now().time_since_epoch().count());
        try {
            value ^= std::random_device()();
        } catch (const std::exception&) {  // no entropy source: the clock alone
        }
        return value;
    }();
    return nonce;
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
    struct stat old {};
    const bool exists = ::stat(m_path.c_str(), &old) == 0;
    // A read-only file stays as it is, as cp leaves it (a rename in a writable folder would not).
    if (exists && ::access(m_path.c_str(), W_OK) != 0)
        throw Error(m_shown, 0, std::string("cannot write: ") + std::strerror(errno));
    // Created exclusively, so that no other writer (another process, another node on a shared folder)
    // ever writes the same temporary file. The replacement of an existing file starts private and
    // takes that file's mode once its owner is set; a new file gets 0666 less the umask.
    for (int attempt = 0;; ++attempt) {
        m_temp = temporaryNameFor(m_path);
        registerPending(m_temp);
        m_descriptor = ::open(m_temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, exists ? 0600 : 0666);
        if (m_descriptor >= 0) break;
        const int err = errno;
        unregisterPending(m_temp);
        m_temp.clear();
        if (err != EEXIST || attempt == 100) throw Error(m_shown, 0, std::string("cannot write: ") + std::strerror(err));
    }
    if (exists) {
        // Owner and group where this process may set them (root; a group it belongs to), then the
        // permission bits, which a change of owner may clear.
        const bool otherOwner = old.st_uid != ::geteuid() || old.st_gid != ::getegid();
        if (otherOwner && ::fchown(m_descriptor, old.st_uid, old.st_gid) != 0) {
            [[maybe_unused]] const int groupOnly = ::fchown(m_descriptor, static_cast<uid_t>(-1), old.st_gid);
        }
        if (::fchmod(m_descriptor, old.st_mode & 07777) != 0) {
            const int err = errno;
            discard();
            throw Error(m_shown, 0, std::string("cannot keep the file's mode: ") + std::strerror(err));
        }
    }
    m_file.open(m_temp, mode);
    if (!m_file) {
        const int err = errno;
        discard();
        throw Error(m_shown, 0, std::string("cannot write: ") + std::strerror(err));
    }
}

std::string AtomicFile::temporaryNameFor(const std::string& target) {
    static std::atomic<unsigned> counter{0};
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) != 0 || host[0] == '\0') std::strcpy(host, "localhost");
    std::string hostName(host);
    if (hostName.size() > 64) hostName.resize(64);
    for (char& c : hostName)
        if (c == '/' || static_cast<unsigned char>(c) < 32) c = '_';
    char unique[32];
    std::snprintf(unique, sizeof unique, "%08x-%u", processNonce(), counter++);
    const std::string tail = ".hemirad-tmp." + hostName + "." + std::to_string(::getpid()) + "." + unique;
    const std::filesystem::path path(target);
    std::string name = path.filename().string();
    // One folder entry holds 255 bytes: a long target name is shortened, never split inside a UTF-8 character.
    const std::size_t room = 255 - 1 - tail.size();
    if (name.size() > room) {
        std::size_t cut = room;
        while (cut > 0 && (static_cast<unsigned char>(name[cut]) & 0xC0) == 0x80) --cut;
        name.resize(cut);
    }
    return (path.parent_path() / ("." + name + tail)).string();
}

void AtomicFile::discard() noexcept {
    if (m_file.is_open()) m_file.close();
    if (m_descriptor >= 0) ::close(m_descriptor);
    m_descriptor = -1;
    if (m_temp.empty()) return;
    std::remove(m_temp.c_str());
    unregisterPending(m_temp);
}

AtomicFile::~AtomicFile() {
    if (m_committed) return;
    if (m_out != &m_file) {
        m_out->flush();  // what was written reaches the reader, as for any target written in place
        return;
    }
    discard();
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
        // The data reaches the disk before the name does: after a crash the name holds the old file
        // or the whole new one, never an empty or partial one.
        if (::fsync(m_descriptor) != 0)
            throw Error(m_shown, 0, std::string("write failed: cannot sync it to disk: ") + std::strerror(errno));
        ::close(m_descriptor);
        m_descriptor = -1;
        if (std::rename(m_temp.c_str(), m_path.c_str()) != 0)
            throw Error(m_shown, 0, std::string("cannot write: ") + std::strerror(errno));
        unregisterPending(m_temp);
        syncFolder(m_path);
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
    // After a failure already reported, the signal is mpirun ending the job's other ranks: not news.
    if (const int status = g_reportedFailure.load()) ::_exit(status);
    const char message[] = "\nhemirad: interrupted; no partial output was written\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, message, sizeof message - 1);
    ::_exit(128 + signal);
}

}  // namespace

void AtomicFile::removePendingFilesOnInterrupt() {
    std::signal(SIGINT, removePendingAndExit);
    std::signal(SIGTERM, removePendingAndExit);
}

void AtomicFile::exitQuietlyOnInterrupt(int status) noexcept { g_reportedFailure.store(status ? status : 1); }

}  // namespace hemirad
