// hemirad-gui's thermal run on a worker thread: every row of F (the missing ones computed first),
// the solar band (on its own F where its mirrors differ), the IR solve and the object exchange
// matrix, all by the library (src/thermal) on copies, so the user may go on editing meanwhile.
#pragma once

#include "ui/thermal_setup.hpp"
#include "ui/worker_job.hpp"
#include "thermal/solar_band.hpp"
#include "thermal/thermal_solver.hpp"

namespace hemirad::ui {

class ThermalJob : public WorkerJob {
public:
    /// Starts at once. `F`: the current F if it may be reused (its missing rows are added), else null
    /// (computed whole with `settings`).
    ThermalJob(Scene scene, std::shared_ptr<const FormFactors> F, ThermalInputs inputs, PipelineSettings settings);
    /// Cancels and joins.
    ~ThermalJob() override;

    ThermalResult result;  ///< after finished(), without an error

private:
    void work() override;

    ThermalInputs m_inputs;
};

}  // namespace hemirad::ui
