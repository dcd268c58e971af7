// Hemisphere back end: Embree rays along Beckers directions from stratified origins, with mirror chains.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "rays/ray_scene.hpp"
#include "preprocess/hemisphere/contact_pairs.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"
#include "preprocess/hemisphere/far_rule.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "preprocess/hemisphere/mirror_images.hpp"
#include "preprocess/hemisphere/pair_exchange.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/patch_sampler.hpp"
#include "preprocess/hemisphere/shadow_polygons.hpp"

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
    struct Workspace;
    /// Rays from the row's origins; Direct = false leaves direct factors to the analytic estimator.
    template <bool Mirrors, bool Direct> void castRays(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// Analytic direct factors of row i added to ws.row in ray units; returns their sum (row fraction).
    double addAnalyticRow(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// Factors from point `point` x of patch i's rule to the `candidates` (all patches when null) that
    /// i emits for, scaled by `weight`.
    double addAnalyticFrom(PatchId i, const Vec3& x, std::uint32_t point, const std::vector<PatchId>* candidates,
                           double weight, Workspace& ws, RayCounts& counts) const;
    /// Row i's entries for the patches that emit for i: the terms each of their rows sums for i
    /// (handed over by the exchange or recomputed), scaled by A_j / A_i; sets their visibility
    /// status. Returns their sum (row fraction).
    double addReversedPairs(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// The terms row j sums for receiver i, appended to ws's term arrays (with `rays`, a shadow ray
    /// per ray term into ws.origins/targets); false when j has no term for i.
    bool reversedTerms(PatchId j, PatchId i, bool rays, Workspace& ws, RayCounts& counts) const;
    /// Of those, the emitters on a silhouette seen from i (a mesh neighbour's status differs): their
    /// ray terms again with i split into pieces, each with its own shadow ray, into ws.reversedTerm.
    void splitReversedSilhouettes(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// A silhouette receiver's polygon (as seen from one point) in pieces of 4 corners, into
    /// ws.pieces: one split, two with --jitter. Both rows of a pair split alike.
    void piecesOf(const Vec3* polygon, std::size_t corners, Workspace& ws) const;

    /// Which patch of a pair integrates the pair's factor over its points (the other is exact): the
    /// smaller one, the lower id on a tie. Both rows of the pair use its terms, so the analytic F is
    /// reciprocal by construction.
    /// The order m of the m x m rule over e for receiver r (1: e's centroid), or 0 for the far rule.
    int pairOrder(PatchId e, PatchId r) const {
        if (m_farRatio > 0.0 && FarRule::ratio(m_geometry.shapes[e], m_geometry.shapes[r]) >= m_farRatio) return 0;
        return ruleOrder(e, r);
    }
    /// The order of the m x m rule alone (a far pair whose factor needs exact visibility takes it).
    int ruleOrder(PatchId e, PatchId r) const { return m_orders(ruleRatio(e, r)); }
    /// r's nearest possible point from e's centroid, in e's radii.
    double ruleRatio(PatchId e, PatchId r) const {
        const PatchShape& a = m_geometry.shapes[e];
        const PatchShape& b = m_geometry.shapes[r];
        return ((b.centroid - a.centroid).norm() - b.radius) / a.radius;
    }
    /// Whether (e, r) is a close pair (within kNearDistance, where the factor varies fastest over e
    /// and the patches may touch): computed as a whole by m_contacts, not by e's rules.
    bool contactPair(PatchId e, PatchId r) const { return !(ruleRatio(e, r) >= kNearDistance); }
    /// A close pair's value in ray units of row e (A_e F_er / A_e x unit): a function of the pair
    /// alone; `viewed` says whether it has a view at all (unoccluded value above 0: a term, visible
    /// or hidden, for the silhouette statuses).
    double contactValue(PatchId e, PatchId r, Workspace& ws, RayCounts& counts, bool& viewed) const;
    /// The points and weights (summing to 1) of the m x m rule over patch e into ws.quadPoints and
    /// ws.quadWeights: one function for both rows of a pair, so that their terms agree bit for bit.
    void emitterRule(PatchId e, int m, Workspace& ws) const;
    /// The far rule's receivers of row i (pairOrder 0): those too large for one shadow ray go to
    /// their rule; the rest get a shadow ray from the centroid, which sets their status.
    void castFarRays(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// Their entries, scaled by `weight`, once the centroid pass has set its statuses too (the
    /// silhouette test reads the neighbours of both); those on a silhouette join ws.split.
    double addFarPairs(double weight, Workspace& ws) const;
    /// F_re from the sum of the pair's terms over e's points (ray units), rounded to F's float as
    /// the exchange hands it over: both rows of the pair round it alike.
    float handedValue(double terms, PatchId e, PatchId r) const {
        return handOver(*m_scene, terms, e, r, double(m_options.origins) * m_options.samples);
    }
    bool emitsFor(PatchId e, PatchId r) const { return hemirad::emitsFor(*m_scene, e, r); }
    /// Lambert's factor from x (normal n) to the part of receiver r above that plane, 0 when x lies
    /// behind r; `polygon` and `corners` say which part (for the shadow ray's aim).
    double pointFactor(PatchId r, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer, const Vec3*& polygon,
                       std::size_t& corners) const;
    /// Patch j's polygon, clipped to the half-space above (x, n) into `buffer` when it straddles
    /// the plane; returns the corner count (0 when nothing lies above).
    std::size_t polygonAbove(PatchId j, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer,
                             const Vec3*& polygon) const;
    /// Where a shadow ray from emitter e's point `point` to (a piece of) receiver r aims: the
    /// polygon's centre, or with jitter a random point drawn from (e, r, point, piece) alone.
    Vec3 aimPoint(const Vec3* polygon, std::size_t corners, PatchId e, PatchId r, std::uint32_t point,
                  std::uint32_t piece) const;

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
    bool m_visibility = true;  ///< analytic estimator: some patch can obstruct (obstructingPatches)
    ShadowPolygons m_shadows;  ///< the patches that can obstruct, for exact partial visibility
    ContactPairs m_contacts;   ///< close pairs, exact (contactPair)
    double m_exactAbove = 0.0;  ///< point factors above this get shadow polygons instead of a shadow ray
    PatchGeometry m_geometry;  ///< analytic estimator only
    EmitterOrders m_orders{1.0, 1, 1};  ///< the emitter rule's order per pair (emitter_rule.hpp)
    FarRule m_far;  ///< the point-to-point kernel for pairs far from each other's horizon
    double m_farRatio = 0.0;  ///< the smallest FarRule::ratio it serves (0: not used, with --origins > 1)
    std::vector<std::vector<double>> m_ruleNodes, m_ruleWeights;  ///< Gauss-Legendre on [0, 1] per order
    int m_splitLevels = 1;  ///< silhouette patches: 1 = split once (4 pieces of a quad), 2 = twice
};

struct BackendDescriptor;
/// The registry entry (hemisphere_descriptor.cpp).
const BackendDescriptor& hemisphereDescriptor();

}  // namespace hemirad
