// hemirad-gui's thermal run on a worker thread: every row of F (the missing ones computed first),
// the solar band (on its own F where its mirrors differ), the IR solve and the object exchange
// matrix, all by the library (src/thermal) on copies, so the user may go on editing meanwhile.
#pragma once

#include "ui/app_state.hpp"
#include "ui/thermal_setup.hpp"
#include "thermal/solar_band.hpp"
#include "thermal/thermal_solver.hpp"

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace hemirad::ui {

class ThermalJob {
public:
    /// Starts at once. `F`: the current F if it may be reused (its missing rows are added), else null
    /// (computed whole with `settings`).
    ThermalJob(Scene scene, std::shared_ptr<const FormFactors> F, ThermalInputs inputs, PipelineSettings settings);
    /// Cancels and joins.
    ~ThermalJob();
    ThermalJob(const ThermalJob&) = delete;
    ThermalJob& operator=(const ThermalJob&) = delete;

    JobStatus status() const;
    bool finished() const { return m_finished; }
    /// Stops between rows of F and between stages; the run then ends with error "cancelled".
    void cancel() { m_cancel = true; }
    void wait();

    // After finished(): F with every row (null if it was not changed), the result or the error.
    std::shared_ptr<const FormFactors> newF;
    std::optional<FormFactorStats> stats;
    ThermalResult result;
    std::string error;
    std::vector<std::string> messages;
    std::vector<std::pair<std::string, double>> timings;
    const Scene& scene() const { return m_scene; }
    const PipelineSettings& settings() const { return m_settings; }

private:
    void run();
    void setStage(const std::string& stage, double progress);
    /// F for `scene` with every row, starting from `current` (may be null), with the job's events.
    std::shared_ptr<const FormFactors> completeRows(const Scene& scene, std::shared_ptr<const FormFactors> current, bool keepStats);
    void checkCancel() const;

    Scene m_scene;
    std::shared_ptr<const FormFactors> m_F;
    ThermalInputs m_inputs;
    PipelineSettings m_settings;
    std::atomic<bool> m_cancel{false}, m_finished{false};
    mutable std::mutex m_mutex;
    JobStatus m_status;
    std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
    std::thread m_thread;
};

}  // namespace hemirad::ui
