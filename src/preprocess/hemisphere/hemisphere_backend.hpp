// Hemisphere back end: Embree rays along Beckers directions from stratified origins, with mirror chains.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "rays/ray_scene.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "preprocess/hemisphere/mirror_images.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/patch_sampler.hpp"

#include <memory>

namespace hemirad {

/// Each patch casts `origins` x `samples` rays; ray k carries 1/(origins samples) of the patch's
/// power. A ray that hits the front of patch j deposits its weight on F_ij; if s_j > 0 it
/// reflects with weight x s_j (Sillion & Puech 1989 extended form factors) up to maxDepth
/// bounces or until its weight falls below minWeight. Misses and back faces are lost and counted.
///
/// The "analytic" estimator replaces the rays' direct deposits by Lambert's exact factor from each
/// origin to every patch in front of it whose centre (or a random point on it, with jitter) a
/// shadow ray reaches; patches close to the emitter are integrated over a Gauss-Legendre rule on it,
/// and patches on a silhouette (mesh neighbours disagreeing about visibility) are split into pieces.
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
    FormFactorProvenance provenance() const override;
    std::map<std::string, std::string> parameters() const override;

    const RayScene& rayScene() const { return *m_rays; }

private:
    struct Workspace;
    /// Rays from the row's origins; Direct = false leaves direct factors to the analytic estimator.
    template <bool Mirrors, bool Direct> void castRays(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// Analytic direct factors of row i added to ws.row in ray units; returns their sum (row fraction).
    double addAnalyticRow(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// Factors from point x on patch i to the `candidates` (all patches when null), scaled by `weight`.
    double addAnalyticFrom(PatchId i, const Vec3& x, const std::vector<PatchId>* candidates, double weight,
                           Random& random, Workspace& ws, RayCounts& counts) const;

    /// Patch j's polygon, clipped to the half-space above (x, n) into `buffer` when it straddles
    /// the plane; returns the corner count (0 when nothing lies above).
    std::size_t polygonAbove(PatchId j, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer,
                             const Vec3*& polygon) const;
    /// Where a shadow ray to a polygon aims: its centre, or a random point with jitter.
    Vec3 aimPoint(const Vec3* polygon, std::size_t corners, Random& random) const;
    void buildNeighbours(const Scene& scene);

    HemisphereOptions m_options;
    CommonOptions m_common;
    const Scene* m_scene = nullptr;
    std::unique_ptr<RayScene> m_rays;
    std::vector<float> m_directions;  ///< Beckers directions in the patch frame
    std::vector<std::uint32_t> m_rings;  ///< Beckers cumulative counts (for jittered directions)
    std::vector<float> m_normals;     ///< per patch, 3 floats
    bool m_mirrors = false;
    bool m_analytic = false;
    std::unique_ptr<MirrorImages> m_images;  ///< analytic estimator with mirrors by images
    std::string m_imagesRefused;  ///< why images were not used although asked for (rays carry the chains)
    bool m_visibility = true;  ///< analytic estimator: some patch can obstruct (somePatchCanObstruct)
    PatchGeometry m_geometry;  ///< analytic estimator only
    std::vector<double> m_gaussNodes, m_gaussWeights;  ///< the near-field rule on [0, 1]
    std::vector<double> m_originNodes, m_originWeights;  ///< the far-field rule (empty: the centroid)
    int m_splitLevels = 1;  ///< silhouette patches: 1 = split once (4 pieces of a quad), 2 = twice
};

struct BackendDescriptor;
/// The registry entry (hemisphere_descriptor.cpp).
const BackendDescriptor& hemisphereDescriptor();

}  // namespace hemirad
