// Hemisphere back end: Embree rays along Beckers directions from stratified origins, with mirror chains.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemisphere/analytic_estimator.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "preprocess/hemisphere/mirror_images.hpp"
#include "preprocess/hemisphere/ray_estimator.hpp"
#include "rays/ray_scene.hpp"

#include <memory>

namespace hemirad {

/// The two estimators (ray_estimator.hpp, analytic_estimator.hpp) and the mirror terms behind one
/// back end. Each patch casts `origins` x `samples` rays; ray k carries 1/(origins samples) of the patch's
/// power. A ray that hits the front of patch j deposits its weight on F_ij; if s_j > 0 it
/// reflects with weight x s_j (Sillion & Puech 1989 extended form factors) up to maxDepth
/// bounces or until its weight falls below minWeight. Misses and back faces are lost and counted.
///
/// The "analytic" estimator replaces the rays' direct deposits by Lambert's exact factor from each
/// origin to every patch in front of it whose centre (or a random point on it, with jitter) a
/// shadow ray reaches; patches close to the emitter are integrated over a Gauss-Legendre rule on it,
/// and patches on a silhouette (mesh neighbours disagreeing about visibility) are split into pieces.
/// Where a point's factor to a patch exceeds 10^-(pair digits + 1), the patch's visible part is
/// exact instead (shadow polygons of the patches that can obstruct, shadow_polygons.hpp).
/// Its terms through planar mirrors come from virtual images (mirror_images.hpp); with
/// --mirror-estimator rays, or where a mirror is not planar and convex, rays carry only the mirror
/// chains. Where no patch can obstruct another (a convex room), no shadow ray is cast.
class HemisphereBackend final : public FormFactorBackend {
public:
    HemisphereBackend(const HemisphereOptions& options, const CommonOptions& common);
    ~HemisphereBackend() override;

    std::string_view name() const override { return "hemisphere"; }
    void prepare(const Scene& scene) override;
    using FormFactorBackend::computeRows;
    void computeRows(RowSource& rows, FormFactorBuilder& builder) override;
    /// The analytic estimator: emitting patches first (ascending area), so that a row finds most of
    /// its pairs handed over by rows that finished before it (pair_exchange.hpp).
    void orderRows(std::vector<PatchId>& rows) const override;
    FormFactorProvenance provenance() const override;
    /// The analytic estimator: each pair from its emitting row (its silhouette split included).
    bool pairsFromEmitters() const override { return m_analytic; }
    std::map<std::string, std::string> parameters() const override;

    const RayScene& rayScene() const { return *m_rays; }

private:
    HemisphereOptions m_options;
    CommonOptions m_common;
    const Scene* m_scene = nullptr;
    std::unique_ptr<RayScene> m_rays;
    RayEstimator m_rayEstimator;  ///< the ray estimator, and mirror chains by rays for the analytic one
    AnalyticEstimator m_analyticEstimator;
    bool m_mirrors = false;
    bool m_analytic = false;
    std::unique_ptr<MirrorImages> m_images;  ///< analytic estimator with mirrors by images
    std::string m_imagesRefused;  ///< why images were not used although asked for (rays carry the chains)
};

struct BackendDescriptor;
/// The registry entry (hemisphere_descriptor.cpp).
const BackendDescriptor& hemisphereDescriptor();

}  // namespace hemirad
