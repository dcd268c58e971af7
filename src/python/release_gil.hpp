// Running a long computation for Python: on a worker thread with the GIL released, while the calling
// thread reports progress, watches for Ctrl-C and stops the work cleanly when either raises.
#pragma once

#include "preprocess/form_factor_job.hpp"

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace hemirad::python {

/// What the worker shares with the calling thread: the latest progress and the request to stop.
class WorkerLink {
public:
    /// For computeFormFactors and friends: stores (done, total, seconds) for the calling thread.
    ProgressCallback progress() {
        return [this](std::size_t done, std::size_t total, double seconds) {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_done = done;
            m_total = total;
            m_seconds = seconds;
            m_fresh = true;
        };
    }
    const std::atomic<bool>* cancelFlag() const { return &m_cancel; }
    bool cancelled() const { return m_cancel.load(); }

    /// Runs `work` on a worker thread with the GIL released. Every 50 ms the calling thread takes
    /// the GIL back, checks for signals (Ctrl-C raises KeyboardInterrupt) and calls `callback(done,
    /// total, seconds)` when there is news. When either raises, the work is asked to stop, the worker
    /// is joined and the Python exception propagates; a C++ exception of the work is rethrown here.
    template <class Result>
    Result run(const std::function<Result()>& work, const pybind11::object& callback) {
        namespace py = pybind11;
        std::optional<Result> result;
        std::exception_ptr failure;
        bool finished = false;
        std::thread worker([&] {
            try {
                result.emplace(work());
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(m_mutex);
            finished = true;
            m_wake.notify_all();
        });
        std::optional<py::error_already_set> raised;
        for (bool done = false; !done;) {
            {
                py::gil_scoped_release release;
                std::unique_lock<std::mutex> lock(m_mutex);
                m_wake.wait_for(lock, std::chrono::milliseconds(50), [&] { return finished; });
                done = finished;
            }
            if (raised) continue;  // stopping: wait for the worker to notice
            try {
                if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                report(callback);
            } catch (py::error_already_set& e) {
                raised.emplace(std::move(e));
                m_cancel.store(true);
            }
        }
        worker.join();
        if (raised) throw *raised;
        if (failure) std::rethrow_exception(failure);
        return std::move(*result);
    }

private:
    void report(const pybind11::object& callback) {
        if (callback.is_none()) return;
        std::size_t done, total;
        double seconds;
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            if (!m_fresh) return;
            m_fresh = false;
            done = m_done;
            total = m_total;
            seconds = m_seconds;
        }
        callback(done, total, seconds);
    }

    std::mutex m_mutex;
    std::condition_variable m_wake;
    std::size_t m_done = 0, m_total = 0;
    double m_seconds = 0;
    bool m_fresh = false;
    std::atomic<bool> m_cancel{false};
};

}  // namespace hemirad::python
