// AtomicFile: temporary file + rename, with a signal-safe registry of pending temporaries.
#include "engine/atomic_file.hpp"

#include "engine/error.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
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

AtomicFile::AtomicFile(std::string path, bool binary) : m_path(std::move(path)) {
    static std::atomic<unsigned> counter{0};
    m_temp = m_path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
    registerPending(m_temp);
    m_out.open(m_temp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
    if (!m_out) {
        const int err = errno;
        unregisterPending(m_temp);
        throw Error(m_path, 0, std::string("cannot write: ") + std::strerror(err));
    }
}

AtomicFile::~AtomicFile() {
    if (m_committed) return;
    m_out.close();
    std::remove(m_temp.c_str());
    unregisterPending(m_temp);
}

void AtomicFile::commit() {
    m_out.flush();
    const bool ok = static_cast<bool>(m_out);
    m_out.close();
    if (!ok || m_out.fail()) throw Error(m_path, 0, "write failed (disk full?)");
    if (std::rename(m_temp.c_str(), m_path.c_str()) != 0)
        throw Error(m_path, 0, std::string("cannot replace: ") + std::strerror(errno));
    unregisterPending(m_temp);
    m_committed = true;
}

void AtomicFile::removePendingFiles() noexcept {
    for (int k = 0; k < kMaxPending; ++k)
        if (g_used[k].load()) ::unlink(g_pending[k]);
}

}  // namespace hemirad
