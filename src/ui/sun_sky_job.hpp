// hemirad-gui's Sky and sun: one hour of sun and sky on the scene as `hemirad irradiance` computes
// it (the sun from a time and place or a direction, its exact sunlit fractions, the isotropic sky's
// exact sky view factors or a sky model's daylight coefficients, the sun and sky reflected by mirrors,
// the inter-reflection through F with every row), on a worker thread.
#pragma once

#include "ui/sun_sky_setup.hpp"
#include "ui/worker_job.hpp"

namespace hemirad::ui {

class SunSkyJob : public WorkerJob {
public:
    /// Starts at once. `F`: the current F if it may be reused (its missing rows are added), else null.
    /// `metres`: metres per scene unit (the powers' unit).
    SunSkyJob(Scene scene, std::shared_ptr<const FormFactors> F, SunSkySetup setup, int upAxis, double metres,
              PipelineSettings settings);
    ~SunSkyJob() override;

    SunSkyResult result;  ///< after finished(), without an error

private:
    void work() override;

    SunSkySetup m_setup;
    int m_upAxis;
    double m_metres;
};

}  // namespace hemirad::ui
