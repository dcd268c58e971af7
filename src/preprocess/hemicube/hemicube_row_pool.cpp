// CPU threads that turn finished hemicube passes into rows of F beside the GL thread.
#include "preprocess/hemicube/hemicube_row_pool.hpp"

namespace hemirad {

HemicubeRowPool::HemicubeRowPool(std::size_t threads, std::size_t patches, RowDone rowDone)
    : m_rowDone(std::move(rowDone)), m_stats(threads) {
    m_rows.reserve(threads);
    for (std::size_t t = 0; t < threads; ++t) m_rows.emplace_back(patches, RowAccumulator::Mode::Weights);
    try {
        for (std::size_t t = 0; t < threads; ++t) m_threads.emplace_back([this, t] { run(t); });
    } catch (...) {
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_stop = true;
        }
        m_work.notify_all();
        for (std::thread& t : m_threads) t.join();
        throw;
    }
}

HemicubeRowPool::~HemicubeRowPool() {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
        m_jobs.clear();
    }
    m_work.notify_all();
    for (std::thread& t : m_threads) t.join();
}

void HemicubeRowPool::post(Job job) {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_jobs.push_back(std::move(job));
    }
    m_work.notify_one();
}

void HemicubeRowPool::waitFor(const std::function<bool()>& ready) {
    std::unique_lock<std::mutex> lock(m_mutex);
    m_progress.wait(lock, [&] { return m_failure || ready(); });
    if (m_failure) std::rethrow_exception(m_failure);
}

void HemicubeRowPool::drain() {
    waitFor([this] { return m_jobs.empty() && m_running == 0; });
}

HemicubeStats HemicubeRowPool::stats() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    HemicubeStats total;
    for (const HemicubeStats& s : m_stats) total += s;
    return total;
}

void HemicubeRowPool::run(std::size_t t) {
    std::unique_lock<std::mutex> lock(m_mutex);
    for (;;) {
        m_work.wait(lock, [this] { return m_stop || !m_jobs.empty(); });
        if (m_stop) return;
        Job job = std::move(m_jobs.front());
        m_jobs.pop_front();
        ++m_running;
        lock.unlock();
        try {
            const PatchId patch = job(m_rows[t], m_stats[t]);
            m_rowDone(patch, m_rows[t], m_stats[t]);
        } catch (...) {
            lock.lock();
            if (!m_failure) m_failure = std::current_exception();
            lock.unlock();
        }
        lock.lock();
        --m_running;
        m_progress.notify_all();
    }
}

}  // namespace hemirad
