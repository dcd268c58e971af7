// A computation for hemirad-gui on a worker thread, on copies of the scene and F, so that the user
// may go on editing meanwhile: its status for the progress bar, cancel, and F with every row (the
// missing rows computed first) for the jobs that need every patch's irradiance (thermal, sun and sky).
#pragma once

#include "pipeline/radiosity_pipeline.hpp"
#include "ui/app_state.hpp"

#include <atomic>
#include <functional>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace hemirad::ui {

class WorkerJob {
public:
    virtual ~WorkerJob();
    WorkerJob(const WorkerJob&) = delete;
    WorkerJob& operator=(const WorkerJob&) = delete;

    JobStatus status() const;
    bool finished() const { return m_finished; }
    /// Stops between rows of F and between stages; the run then ends with error "cancelled".
    void cancel() { m_cancel = true; }
    void wait();

    // After finished(): F with every row (null if it was not changed), the error, the report.
    std::shared_ptr<const FormFactors> newF;
    std::optional<FormFactorStats> stats;
    std::string error;
    std::vector<std::string> messages;
    std::vector<std::pair<std::string, double>> timings;
    const Scene& scene() const { return m_scene; }
    const PipelineSettings& settings() const { return m_settings; }

protected:
    /// `F`: the current F if it may be reused (its missing rows are added), else null; `purpose`
    /// names the job in the form-factor message ("thermal").
    WorkerJob(Scene scene, std::shared_ptr<const FormFactors> F, PipelineSettings settings, std::string purpose);
    /// Starts the thread: the last step of a derived constructor.
    void start();
    /// Cancels and joins: the first step of a derived destructor (its members outlive the thread).
    void stop();
    /// The job's work; throws hemirad::Error (or "cancelled").
    virtual void work() = 0;
    void setStage(const std::string& stage, double progress);
    void checkCancel() const;
    /// F for `scene` with every row, starting from `current` (may be null), with the job's events.
    std::shared_ptr<const FormFactors> completeRows(const Scene& scene, std::shared_ptr<const FormFactors> current, bool keepStats);
    /// Runs `step`, recording its seconds under `stage`.
    template <class Step>
    auto timed(const std::string& stage, Step step) {
        setStage(stage, 0.0);
        const auto begin = std::chrono::steady_clock::now();
        auto value = step();
        timings.emplace_back(stage, std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
        return value;
    }

    Scene m_scene;
    std::shared_ptr<const FormFactors> m_F;
    PipelineSettings m_settings;

private:
    void run();

    std::string m_purpose;
    std::atomic<bool> m_cancel{false}, m_finished{false};
    mutable std::mutex m_mutex;
    JobStatus m_status;
    std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
    std::thread m_thread;
};

/// The pipeline's events as a worker reports them: `cancel` polled, stages timed into `timings`,
/// messages appended to `messages`, each progress step given to `setStage` (stage, 0..1). The
/// callbacks keep references: the vectors must outlive the pipeline.
PipelineEvents workerEvents(std::atomic<bool>* cancel, std::vector<std::pair<std::string, double>>& timings,
                            std::vector<std::string>& messages, std::function<void(const std::string&, double)> setStage);

/// A number for the job's messages, to `digits` significant digits.
std::string jobFigure(double v, int digits = 6);

}  // namespace hemirad::ui
