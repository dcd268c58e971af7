// The first exception of an OpenMP region's threads, kept and rethrown after the region: an exception
// may not leave a region (it would end in std::terminate), so each thread runs its work through
// run(), which keeps what it throws (an out-of-memory in a per-thread buffer included).
#pragma once

#include <atomic>
#include <exception>
#include <mutex>

namespace hemirad {

class ParallelFailure {
public:
    /// Runs `work`; an exception it throws is kept (the first of all threads) instead of leaving.
    /// Thread-safe.
    template <class Work>
    void run(Work&& work) noexcept {
        try {
            work();
        } catch (...) {
            keep(std::current_exception());
        }
    }
    /// Whether some thread failed: the others stop taking work.
    bool failed() const { return m_failed.load(std::memory_order_relaxed); }
    /// After the region: rethrows the first exception kept, if any.
    void rethrowIfFailed() const {
        if (m_failure) std::rethrow_exception(m_failure);
    }

private:
    void keep(std::exception_ptr failure) noexcept {
        const std::lock_guard<std::mutex> lock(m_mutex);
        if (!m_failure) m_failure = std::move(failure);
        m_failed.store(true, std::memory_order_relaxed);
    }

    std::mutex m_mutex;
    std::exception_ptr m_failure;
    std::atomic<bool> m_failed{false};
};

}  // namespace hemirad
