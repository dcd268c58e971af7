// CPU threads that turn finished hemicube passes into rows of F beside the GL thread.
#pragma once

#include "preprocess/hemicube/hemicube_renderer.hpp"
#include "preprocess/row_accumulator.hpp"

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hemirad {

/// A GPU draws and reduces a pass of hundreds of hemicubes in well under a millisecond; copying
/// its rows into F (tens of microseconds a row) would then keep the one GL thread busy for most of
/// the run. These threads do it instead, each with its own row accumulator and stage times.
class HemicubeRowPool {
public:
    /// Sums one row of a finished pass into `row` and returns the row's patch.
    using Job = std::function<PatchId(RowAccumulator& row, HemicubeStats& stats)>;
    /// Called on a pool thread after each job with the row it summed (take it there).
    using RowDone = std::function<void(PatchId, RowAccumulator&, HemicubeStats&)>;

    HemicubeRowPool(std::size_t threads, std::size_t patches, RowDone rowDone);
    /// Drops the jobs not started, joins the threads.
    ~HemicubeRowPool();
    HemicubeRowPool(const HemicubeRowPool&) = delete;
    HemicubeRowPool& operator=(const HemicubeRowPool&) = delete;

    void post(Job job);
    /// Blocks until `ready()` holds (checked after every job); rethrows a job's failure.
    void waitFor(const std::function<bool()>& ready);
    /// Blocks until every posted job has run; rethrows the first job's failure.
    void drain();
    /// The threads' stage times and counts, summed (complete after drain()).
    HemicubeStats stats() const;

private:
    void run(std::size_t t);

    RowDone m_rowDone;
    mutable std::mutex m_mutex;
    std::condition_variable m_work, m_progress;
    std::deque<Job> m_jobs;
    std::size_t m_running = 0;
    bool m_stop = false;
    std::exception_ptr m_failure;
    std::vector<RowAccumulator> m_rows;
    std::vector<HemicubeStats> m_stats;
    std::vector<std::thread> m_threads;
};

}  // namespace hemirad
