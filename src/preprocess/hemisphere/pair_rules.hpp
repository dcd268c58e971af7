// The rules both rows of an analytic pair follow. A pair (e, r) is integrated over the points of
// its emitting patch e; row e sums those terms, and row r recomputes them when the exchange has not
// handed them over. Everything the two rows must compute alike, bit for bit, lives here: which rule
// integrates the pair, each point's term (exact visible part or a shadow ray, and where that ray
// aims), how a silhouette receiver is cut into pieces, a close pair's value and the rounding of
// the handed-over entry.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemisphere/contact_pairs.hpp"
#include "preprocess/hemisphere/covered_emitters.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"
#include "preprocess/hemisphere/far_rule.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "preprocess/hemisphere/pair_exchange.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"
#include "preprocess/hemisphere/shadow_polygons.hpp"
#include "rays/ray_scene.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

class PairRules {
public:
    /// One thread's scratch for the rules.
    struct Scratch {
        std::vector<Vec3> quadPoints;  ///< a quadrature rule over the emitter (emitterRule)
        std::vector<double> quadWeights;
        std::vector<Vec3> clipped;     ///< a receiver clipped to a point's half-space
        std::vector<Vec3> pieces, finer;  ///< a silhouette receiver's pieces, 4 corners each
        ShadowPolygons::Scratch shadow;
        ContactPairs::Scratch contact;
        std::vector<float> probeOrigins, probeTargets;  ///< cornersAgree's and extremesAgree's shadow rays
        std::vector<std::uint32_t> probePairs;          ///< extremesAgree's pairs of corners, each cast once
        std::vector<std::uint8_t> probeBlocked;
        std::vector<Vec3> front, cutPoints;  ///< a cut pair's emitter part in front of the receiver, its rule
        std::vector<double> cutWeights;
    };

    /// Row e's term for receiver r at one point x of e's rule.
    struct PointTerm {
        double factor = 0.0;   ///< Lambert's factor from x to r's part above x's plane
        bool exact = false;    ///< factor above exactAbove(): its visible part comes from shadow polygons
        double visible = 0.0;  ///< exact terms: that visible part
        const Vec3* polygon = nullptr;  ///< r's part above x's plane (where a shadow ray aims)
        std::size_t corners = 0;
    };

    /// The scene's geometry, rules and blockers for --pair-digits, --origins and --jitter.
    void build(const Scene& scene, const RayScene& rays, const HemisphereOptions& options);

    /// The order m of the m x m rule over e for receiver r (1: e's centroid), or 0 for the far rule.
    int pairOrder(PatchId e, PatchId r) const {
        // A covered emitter has no centroid pass and no far rule: its rules cover its free part.
        if (m_covered.covered(e)) return std::max(2, ruleOrder(e, r));
        if (m_farRatio > 0.0 && FarRule::ratio(m_geometry.shapes[e], m_geometry.shapes[r]) >= m_farRatio) return 0;
        return ruleOrder(e, r);
    }
    /// A far pair (pairOrder 0): the far rule's factor from e's centroid into `far`, and 0; or, where
    /// that factor is too large for one shadow ray's verdict, the order of the m x m rule that gives
    /// the pair exact visibility instead.
    int farPairOrder(PatchId e, PatchId r, double& far) const {
        far = m_far.factor(m_geometry, e, r, m_scene->patches[r].area);
        return far > m_exactAbove ? ruleOrder(e, r) : 0;
    }
    /// Whether (e, r) is a close pair (within kNearDistance, where the factor varies fastest over e
    /// and the patches may touch), or any pair with --pairs whole: computed as a whole by
    /// contactValue, not by e's rules.
    /// A far pair whose receiver's plane cuts the emitter (PatchGeometry::planeCuts) is one too
    /// (cutValue's, by both rows), unless a solid covers part of the emitter: its rule is then
    /// over the free part (CoveredEmitters), as before.
    bool contactPair(PatchId e, PatchId r) const {
        return m_wholePairs || !(ruleRatio(e, r) >= kNearDistance) ||
               (!m_covered.covered(e) && m_geometry.planeCuts(r, e));
    }
    /// A close pair's value in ray units of row e (A_e F_er / A_e x unit): a function of the pair
    /// alone; `viewed` says whether it has a view at all (unoccluded value above 0: a term, visible
    /// or hidden, for the silhouette statuses).
    /// `close` false: a far pair computed whole (straddlingValue, penumbralValue), its hidden part
    /// by the disagreements alone (ContactPairs::exchange's `changes`).
    /// A far pair that contactPair() holds only because r's plane cuts e gets cutValue instead.
    double contactValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts, bool& viewed, bool close = true) const;
    /// A far pair (3 radii apart or more) whose receiver's plane cuts the emitter, in ray units of
    /// row e: the pair's rule (ruleOrder; order 1: the part's centroid) over e's part in front of
    /// r's plane, each point's
    /// visible part exact (shadow polygons), times that part's share of e. Where the visible
    /// shares of those points and of the part's corners spread more than kStraddleSpread (a
    /// shadow's edge crosses it), the pair computed whole instead (wholeValue, with the close
    /// pairs' least errors). A function of the pair alone, as contactValue's.
    /// Over the whole of e the rule weighed a factor that is 0 behind r's plane and grows from 0 in
    /// front of it, a kink its few points cannot place: district1k's wall 572 (z 11 to 15) read
    /// 8.0e-5 for the roof 808 at z = 14 beside it, where it sees 1.56e-4, unoccluded, and its
    /// wall 734 read 0 for the roof 905 (4.8e-4, partly hidden). Such pairs held 0.013 of the
    /// district's 0.086 summed entry error; with this value its rows off by more than 1e-4 went
    /// from 57 to 38 (entries: 7 to 5), for 1.2 % more visible-part evaluations. The rule over the
    /// front part alone, without the corners, left 46 rows and 13 entries (largest 4.8e-4);
    /// every such pair whole cost cornell13k 28 % more evaluations.
    double cutValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts, bool& viewed) const;
    /// The pair computed whole (ContactPairs::exchange), in ray units of row e; `close`: its hidden
    /// part with the close pairs' least errors.
    double wholeValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts, bool& viewed, bool close) const;
    /// A straddling pair's value (straddles()), as contactValue's (a function of the pair alone, for
    /// both rows), counted apart.
    double straddlingValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts) const;
    /// The share of r's factor that point x of e sees past the blockers: the exact visible part of
    /// r's part above x's plane (shadow polygons, as exact terms) over its factor; -1 when x has no
    /// term for r. The probe of a pair's corners (AnalyticEstimator::cornersWiden). It was r in
    /// four pieces with a shadow ray each: a wall corner that sees 42 % of a far wall read 0 where
    /// the four pieces' centres were hidden (district1k's 468 -> 803, 0 for 8.4e-5; 934 -> 750
    /// 2.9e-5 for 1.8e-4, its top corners seeing 27 % of the wall); exact, the
    /// district's entries off by more than 1e-4 went from 16 to 14 and the 60 mm Cornell box's
    /// from 10 to 6, in the same time.
    double visibleShare(PatchId e, PatchId r, const Vec3& x, Scratch& s, RayCounts& counts) const;
    /// Whether a ruled pair whose points saw between `least` and `most` of the receiver, with the
    /// rule's unoccluded sum `unoccluded` (ray units), straddles a shadow's edge enough for its
    /// rule to miss the pair tolerance: then it is computed whole (contactValue), as a close pair is.
    bool straddles(double unoccluded, double least, double most) const {
        return most - least > kStraddleSpread && (most - least) * unoccluded > m_straddleAbove * unit();
    }
    /// Whether a ray term from e's centroid (the centroid pass or the far rule) with this factor
    /// is probed for a penumbra across e (centroidVerdictHolds: the corners, then the rims).
    bool probesPenumbra(double factor) const { return factor >= m_penumbraProbeAbove; }
    /// Whether e's corners (a hundredth inside) give the shadow ray to `target` (the centroid's ray
    /// target, in the ray scene's frame) the centroid's verdict `blocked`. Where they do not, an
    /// occluder's edge crosses the view of r between e's points: a penumbra, which the centroid's
    /// one verdict (all or nothing) cannot weigh. A floor patch with a block standing on part of it
    /// is the extreme: its centroid under the block saw nothing where its free part sees the room.
    bool cornersAgree(PatchId e, const float target[3], bool blocked, Scratch& s, RayCounts& counts) const;
    /// Whether the rims of the bundle of lines from e to r give the centroid's verdict `blocked`:
    /// from each corner of either patch (a hundredth inside) to the other's corner furthest the
    /// same way across the line between their centroids, one shadow ray each (e.count + r.count).
    /// Where an occluder's limb crosses the view, the lines that pass it lie at the bundle's rim;
    /// cornersAgree's rays, from e's corners to r's centre, lie halfway in. The concentric spheres'
    /// pairs up to 8 % visible read as hidden where both the centroid and the corners agreed.
    /// Asked only of terms whose (unoccluded) factor is at least kExtremesAbove of exactAbove()
    /// (3e-4 by default); true for the rest. Where the verdict is `blocked` and every ray agrees
    /// (or none is cast), the centroid's and the corners' exact visible shares decide too
    /// (kBlockedCentreShare).
    bool extremesAgree(PatchId e, PatchId r, double factor, bool blocked, Scratch& s, RayCounts& counts) const;
    /// cornersAgree, then extremesAgree: whether one shadow ray's verdict from e's centroid to
    /// `target` (the centre of r's part above e's plane, as the ray aimed) holds for the whole pair
    /// of that factor, as both rows of a pair ask it.
    bool centroidVerdictHolds(PatchId e, PatchId r, double factor, const float target[3], bool blocked, Scratch& s,
                              RayCounts& counts) const {
        return cornersAgree(e, target, blocked, s, counts) && extremesAgree(e, r, factor, blocked, s, counts);
    }
    /// The ends of the shadow rays from e's point x to r's corners (a hundredth inside, lifted off
    /// r as rayTarget lifts them; those behind x's plane left out), appended to `targets`; returns
    /// how many. Where one of them gets another verdict than the ray to r's centre, a blocker's
    /// edge crosses r as seen from x, whatever r's mesh neighbours say: the term is split as a
    /// silhouette term is (silhouetteTerm, forEachPiece).
    std::size_t receiverCornerTargets(PatchId e, PatchId r, const Vec3& x, std::vector<float>& targets) const;
    /// Corner k of e a hundredth inside: where cornersAgree's rays start (before rayOrigin's lift).
    Vec3 cornerProbe(PatchId e, std::uint32_t k) const { return m_geometry.insetCorner(e, k); }
    /// A pair in such a penumbra, or a ruled pair whose points' shares spread too far for its few
    /// points but not enough for straddles(): its value whole, as contactValue's (the exact
    /// unoccluded part less the adaptive hidden part), a function of the pair alone for both rows,
    /// counted apart. (Before, the exact visible part at each point of a fixed rule over e, 3 x 3
    /// on a triangle and 2 x 2 on a quadrilateral: the rule placed the shadow's edge across e
    /// coarsely, and every receiver behind the same edge erred alike. district1k's row 573 summed
    /// 7.4e-4 too much over 37 such pairs, row 39 5.8e-4 too little. With the hidden part's rims
    /// (contact_pairs.cpp) the entries off by more than 1e-4 went from 110 to 46 and the largest
    /// row error from 1.2e-3 to 5.9e-4, for 1.2x the time; the Cornell box at 60 mm took 2.2x, the
    /// concentric spheres 2.5x (a quadrilateral's adaptive part starts at 82 evaluations where its
    /// rule had 4: bench/BENCHMARKS.md). Its history: order 4 on district1k's tall wall slivers left a row 1.9e-3 off, order
    /// 3 8.2e-4; before that, each point's term below exactAbove() was r in four pieces with a ray
    /// each, and the concentric spheres' pairs 18 to 41 % visible read a fifth of their visible
    /// part low.)
    double penumbralValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts) const;
    /// Whether a ruled pair (as straddles() takes it) spreads enough to be worth penumbralValue.
    bool spreadsPenumbra(double unoccluded, double least, double most) const {
        return most - least > kStraddleSpread && (most - least) * unoccluded >= m_penumbraProbeAbove * unit();
    }
    /// A silhouette receiver's term from point x of e: where its factor exceeds the silhouette bound
    /// (m_silhouetteExactAbove, a tenth of exactAbove()), Lambert's factor to the part of r that x sees
    /// past the blockers (exact, shadow polygons, as pointTerm's exact terms) into `visible`, and
    /// true; else false (forEachPiece takes it in pieces, a shadow ray each).
    bool silhouetteTerm(PatchId e, PatchId r, const Vec3& x, Scratch& s, RayCounts& counts, double& visible) const {
        PointTerm term;
        term.factor = pointFactor(r, x, m_geometry.shapes[e].normal, s.clipped, term.polygon, term.corners);
        if (!(term.factor > m_silhouetteExactAbove)) return false;
        visible = exactVisible(e, r, x, term, s, counts.shadowTerms);
        return true;
    }
    /// The points and weights (summing to 1, or to a covered emitter's free fraction) of the m x m
    /// rule over patch e into s.quadPoints and s.quadWeights.
    void emitterRule(PatchId e, int m, Scratch& s) const { ruleOver(e, m, s.quadPoints, s.quadWeights); }
    /// Whether corner k of e (a hundredth inside, cornerProbe) lies under a solid standing on e:
    /// no probe is cast from it (it sees nothing, whatever the receiver).
    bool cornerCovered(PatchId e, std::uint32_t k) const { return m_covered.cornerCovered(e, k); }
    const CoveredEmitters& coveredEmitters() const { return m_covered; }
    /// Row e's term for r at point x of e's rule; false when x has no term for r (factor not above 0).
    bool pointTerm(PatchId e, PatchId r, const Vec3& x, Scratch& s, RayCounts& counts, PointTerm& term) const;
    /// The ends of the shadow ray from e's point x (index `point` of e's rule) to (a piece of) r, in
    /// the ray scene's frame, each lifted off its patch: the polygon's centre, or with jitter a random
    /// point drawn from (e, r, point, piece) alone.
    void rayOrigin(PatchId e, const Vec3& x, float origin[3]) const;
    void rayTarget(PatchId e, PatchId r, const Vec3* polygon, std::size_t corners, std::uint32_t point,
                   std::uint32_t piece, float target[3]) const;
    /// Receiver r on a silhouette seen from e's point x (index `point`): r's part above x's plane
    /// in pieces of 4 corners (one split, two with --jitter); visit(factor, target) for each piece
    /// with a factor above 0, target its shadow ray's end (aimed as piece 1, 2, ...).
    template <class Visit>
    void forEachPiece(PatchId e, PatchId r, const Vec3& x, std::uint32_t point, Scratch& s, Visit visit) const {
        const Vec3& n = m_geometry.shapes[e].normal;
        const Vec3* polygon;
        const std::size_t corners = polygonAbove(r, x, n, s.clipped, polygon);
        piecesOf(polygon, corners, s);
        for (std::size_t q = 0; q < s.pieces.size(); q += 4) {
            const double f = pointToPolygonFactor(x, n, &s.pieces[q], 4);
            if (!(f > 0.0)) continue;
            float target[3];
            rayTarget(e, r, &s.pieces[q], 4, point, std::uint32_t(1 + q / 4), target);
            visit(f, target);
        }
    }
    /// F_re from the sum of the pair's terms over e's points (ray units), as the exchange hands it
    /// over: both rows of the pair compute it alike.
    double handedValue(double terms, PatchId e, PatchId r) const { return handOver(*m_scene, terms, e, r, unit()); }
    /// Which patch of a pair integrates the pair's factor over its points (the other is exact): the
    /// smaller one, the lower id on a tie.
    bool emitsFor(PatchId e, PatchId r) const { return hemirad::emitsFor(*m_scene, e, r); }

    /// Visible shares further apart than this across a pair's points (or its emitter's corners) mean
    /// a shadow's edge crosses the emitter: its few points cannot place it. At 0.25, the ruled
    /// pairs with exact terms whose shares spread less than that held district1k's largest row
    /// errors (row 934: 2.6e-4 of its 5.9e-4 from them); at 0.05 (with the silhouette bound at
    /// 1e-4) its entries off by more than 1e-4 went from 35 to 19 and the 60 mm Cornell box's
    /// from 32 to 10, for 1.17x the box's time (0.1: 24 and 22 entries).
    static constexpr double kStraddleSpread = 0.05;
    /// extremesAgree's bound, of exactAbove(): below it a term keeps cornersAgree's answer. With
    /// every probed term (from a tenth) cornell13k's F took 74 s instead of 58 s on two threads
    /// for 1.58 M penumbra computations; district1k, the Cornell box at 60 mm and the spheres
    /// were no better.
    static constexpr double kExtremesAbove = 0.3;
    /// Where every ray extremesAgree casts is blocked, as the centroid's was, and the centroid's
    /// exact visible part is more than this share of r, the pair is in a penumbra after all.
    /// district1k's wall 755 sees 36 % of the wall 638, 125 m away, from its centroid, and none
    /// of it from its west part; the rays to 638's centre and rims were all blocked, and the pair
    /// read 3.5e-4 (the centroid's share, split on a silhouette) or 0 for 1.65e-4. With it, no
    /// entry of the district is off by more than 1e-4 (2 before), and the 60 mm box has 2 such
    /// entries instead of 4, for 5 % more shadow-polygon probes there. Where the rays all saw
    /// r and the centroid less than 75 % of it, computing the pair whole made the box's row 35
    /// 6.9e-4 off instead of 1.2e-4 (its far pairs computed whole went 11 % low).
    /// Where the centroid's share is below this, each corner (not covered) whose exact share is
    /// above kStraddleSpread makes the pair a penumbra too: district1k's wall 468 sees the ground
    /// 340 from near one corner alone (15 to 36 %, none from its centroid) and read 0 for 5.0e-5.
    /// cornell13k: 2.6 M more shadow-polygon probes, 350 more pairs in a penumbra. The centroid's
    /// share asked also of blocked terms below kExtremesAbove (from the silhouette bound up)
    /// mended district1k's wall sliver 916 (it read 53 % of the wall 576 where it sees 34 %)
    /// but took cornell13k 25 % longer (47,000 more pairs in a penumbra): not taken.
    static constexpr double kBlockedCentreShare = 0.25;

    /// F in ray units: the accumulator's take() scales by 1 / (origins samples).
    double unit() const { return double(m_options.origins) * m_options.samples; }
    /// Whether some patch can obstruct another (else no shadow ray is cast).
    bool visibility() const { return m_visibility; }
    /// Point factors above this get their exact visible part instead of a shadow ray.
    double exactAbove() const { return m_exactAbove; }
    const PatchGeometry& geometry() const { return m_geometry; }
    const EmitterOrders& orders() const { return m_orders; }
    const FarRule& farRule() const { return m_far; }
    std::size_t blockers() const { return m_shadows.size(); }
    /// Convex solids among the patches that can obstruct, and the patches that are their faces.
    std::size_t solids() const { return m_shadows.solids(); }
    std::size_t solidFaces() const { return m_shadows.solidFaces(); }
    int splitLevels() const { return m_splitLevels; }

private:
    /// The m x m rule over e (its free part where a solid covers some of it) into points, weights.
    void ruleOver(PatchId e, int m, std::vector<Vec3>& points, std::vector<double>& weights) const;
    /// The order of the m x m rule alone (a far pair whose factor needs exact visibility takes it).
    int ruleOrder(PatchId e, PatchId r) const { return m_orders(ruleRatio(e, r)); }
    /// r's nearest possible point from e's centroid, in e's radii.
    double ruleRatio(PatchId e, PatchId r) const {
        const PatchShape& a = m_geometry.shapes[e];
        const PatchShape& b = m_geometry.shapes[r];
        return ((b.centroid - a.centroid).norm() - b.radius) / a.radius;
    }
    /// Lambert's factor from x (normal n) to the part of receiver r above that plane, 0 when x lies
    /// behind r; `polygon` and `corners` say which part.
    double pointFactor(PatchId r, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer, const Vec3*& polygon,
                       std::size_t& corners) const;
    /// The visible part of `term` (its factor and polygon set) from x past the blockers, by shadow
    /// polygons; one more in `count` (RayCounts::shadowTerms for F's terms, shadowProbes for probes).
    double exactVisible(PatchId e, PatchId r, const Vec3& x, const PointTerm& term, Scratch& s,
                        std::uint64_t& count) const {
        ++count;
        return m_shadows.visibleFactor(x, m_geometry.shapes[e].normal, term.polygon, term.corners, e, r, term.factor,
                                       s.shadow);
    }
    /// Patch j's polygon, clipped to the half-space above (x, n) into `buffer` when it straddles
    /// the plane; returns the corner count (0 when nothing lies above).
    std::size_t polygonAbove(PatchId j, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer,
                             const Vec3*& polygon) const;
    /// Casts the probe rays in s.probeOrigins and s.probeTargets; whether every verdict is `blocked`.
    bool probesAgree(bool blocked, Scratch& s, RayCounts& counts) const;
    /// A polygon in pieces of 4 corners into s.pieces: one split, two with --jitter.
    void piecesOf(const Vec3* polygon, std::size_t corners, Scratch& s) const;
    Vec3 aimPoint(const Vec3* polygon, std::size_t corners, PatchId e, PatchId r, std::uint32_t point,
                  std::uint32_t piece) const;

    const Scene* m_scene = nullptr;
    const RayScene* m_rays = nullptr;
    HemisphereOptions m_options;
    bool m_visibility = true;
    PatchGeometry m_geometry;
    ShadowPolygons m_shadows;  ///< the patches that can obstruct, for exact partial visibility
    ContactPairs m_contacts;   ///< close pairs, exact (contactPair)
    CoveredEmitters m_covered;  ///< emitters a solid stands on in part
    bool m_wholePairs = false;  ///< --pairs whole: every pair is a close pair
    double m_exactAbove = 0.0;
    double m_straddleAbove = 0.0;  ///< F units: straddles() needs spread x unoccluded above this
    double m_silhouetteExactAbove = 0.0;  ///< silhouette terms above this get their exact visible part
    double m_penumbraProbeAbove = 0.0;  ///< centroid ray terms from this factor up are probed (e's corners, the rims)
    EmitterOrders m_orders{1.0, 1, 1};  ///< the emitter rule's order per pair (emitter_rule.hpp)
    FarRule m_far;  ///< the point-to-point kernel for pairs far from each other's horizon
    double m_farRatio = 0.0;  ///< the smallest FarRule::ratio it serves (0: not used, with --origins > 1)
    std::vector<std::vector<double>> m_ruleNodes, m_ruleWeights;  ///< Gauss-Legendre on [0, 1] per order (up to
                                                                  ///< the highest rule's)
    int m_splitLevels = 1;  ///< silhouette patches: 1 = split once (4 pieces of a quad), 2 = twice
};

}  // namespace hemirad
