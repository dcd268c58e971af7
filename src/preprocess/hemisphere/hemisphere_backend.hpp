// Hemisphere back end: Embree rays along Beckers directions from stratified origins, with mirror chains.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemisphere/embree_scene.hpp"

#include <memory>

namespace hemirad {

/// Each patch casts `origins` x `samples` rays; ray k carries 1/(origins samples) of the patch's
/// power. A ray that hits the front of patch j deposits its weight on F_ij; if s_j > 0 it
/// reflects with weight x s_j (Sillion & Puech 1989 extended form factors) up to maxDepth
/// bounces or until its weight falls below minWeight. Misses and back faces are lost and counted.
class HemisphereBackend final : public FormFactorBackend {
public:
    explicit HemisphereBackend(const BackendOptions& options);
    ~HemisphereBackend() override;

    std::string_view name() const override { return "hemisphere"; }
    void prepare(const Scene& scene) override;
    void computeRows(const std::vector<PatchId>& rows, FormFactorBuilder& builder) override;
    std::map<std::string, std::string> parameters() const override;

    const RayScene& rayScene() const { return *m_rays; }

private:
    struct Workspace;
    template <bool Mirrors> void computeRow(PatchId i, Workspace& ws, RayCounts& counts) const;

    BackendOptions m_options;
    const Scene* m_scene = nullptr;
    std::unique_ptr<RayScene> m_rays;
    std::vector<float> m_directions;  ///< Beckers directions in the patch frame
    std::vector<std::uint32_t> m_rings;  ///< Beckers cumulative counts (for jittered directions)
    std::vector<float> m_normals;     ///< per patch, 3 floats
    bool m_mirrors = false;
};

}  // namespace hemirad
