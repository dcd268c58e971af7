// The hemisphere back end's ray estimator: Beckers directions from stratified origins over the
// patch, each ray depositing its weight on the patch it hits and reflecting off mirrors (Sillion &
// Puech 1989 extended form factors). The analytic estimator uses it for mirror chains alone.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "preprocess/row_accumulator.hpp"
#include "rays/ray_scene.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

class RayEstimator {
public:
    /// One thread's scratch: an origin's rotated (and jittered) directions and their hits.
    struct Workspace {
        std::vector<float> jittered, dirs;
        std::vector<PatchId> hits;
        std::vector<float> distances;
    };
    /// What a row's rays deposit: everything they hit, or only what they reach through mirrors
    /// (the analytic estimator has the direct factors).
    enum class Deposit { All, MirrorChainsOnly };

    RayEstimator(const HemisphereOptions& options, const CommonOptions& common);
    void prepare(const Scene& scene, const RayScene& rays);
    Workspace workspace() const;
    /// Row i's rays into `row` (ray units: weights with mirrors or Deposit::MirrorChainsOnly, else counts).
    void addRow(PatchId i, Deposit deposit, RowAccumulator& row, Workspace& ws, RayCounts& counts) const;

private:
    template <bool Mirrors, bool Direct>
    void castRays(PatchId i, RowAccumulator& row, Workspace& ws, RayCounts& counts) const;

    HemisphereOptions m_options;
    CommonOptions m_common;
    const Scene* m_scene = nullptr;
    const RayScene* m_rays = nullptr;
    std::vector<float> m_directions;     ///< Beckers directions in the patch frame
    std::vector<std::uint32_t> m_rings;  ///< Beckers cumulative counts (for jittered directions)
    std::vector<float> m_normals;        ///< per patch, 3 floats
    bool m_mirrors = false;
};

}  // namespace hemirad
