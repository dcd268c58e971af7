// The hemisphere back end's analytic estimator: Lambert's exact point-to-polygon factors with
// shadow rays (Wallace, Elmquist & Haines 1989 cast rays for visibility of analytic point-to-area
// factors; Baum, Rushmeier & Winget 1989 give the exact polygon form).
//
// Each pair (e, r) is integrated over the points of its emitting patch e (pair_exchange.hpp). A
// row does two things: as the emitter, it sums its terms for its receivers over its rules' points
// (analytic_emitter.cpp); as a receiver, it takes the entries of the pairs other rows emit for it,
// handed over or recomputed (analytic_receiver.cpp). Both follow the pair's rules (pair_rules.hpp),
// so that A_i F_ij = A_j F_ji to F's rounding.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemisphere/pair_exchange.hpp"
#include "preprocess/hemisphere/pair_rules.hpp"
#include "preprocess/row_accumulator.hpp"
#include "rays/ray_scene.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace hemirad {

class AnalyticEstimator {
public:
    struct Workspace;

    explicit AnalyticEstimator(const HemisphereOptions& options) : m_options(options) {}
    void prepare(const Scene& scene, const RayScene& rays);
    /// One thread's workspace, whose rows publish their pairs to `exchange`.
    Workspace workspace(PairExchange& exchange) const;
    /// Row i's direct factors added to `row` in ray units (rules().unit() per unit of F); returns
    /// their sum (row fraction).
    double addRow(PatchId i, RowAccumulator& row, Workspace& ws, RayCounts& counts) const;
    const PairRules& rules() const { return m_rules; }

private:
    // As the emitter (analytic_emitter.cpp).
    /// Factors from point x (index `point` of row i's rule) to the `candidates` (all patches in
    /// the centroid pass when null) that i emits for, scaled by `weight`; returns their sum.
    double addFrom(PatchId i, const Vec3& x, std::uint32_t point, const std::vector<PatchId>* candidates, double weight,
                   RowAccumulator& row, Workspace& ws, RayCounts& counts) const;
    /// The far rule's receivers of row i (pairOrder 0): those too large for one shadow ray go to
    /// their rule; the rest get a shadow ray from the centroid, which sets their status.
    void castFarRays(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// How a pair's terms are replaced: not (None), by its value whole (Whole: contactValue), or
    /// by its penumbralValue (Penumbral).
    enum class Straddle { None, Whole, Penumbral };
    /// After the centroid pass (its exact terms, m = 1) and each rule pass of order m >= 2 (all
    /// terms): the receivers straddling a shadow's edge (straddleOf) get their replacement value in
    /// place of the rule's terms.
    double replaceStraddlingPairs(PatchId i, const std::vector<PatchId>& receivers, RowAccumulator& row, Workspace& ws,
                                  RayCounts& counts) const;
    /// Whether emitter e's pair with r straddles a shadow's edge (straddlesWhole: Whole), or its
    /// shares spread enough that its few points cannot weigh them (PairRules::spreadsPenumbra:
    /// Penumbral), with e's corners' and edges' midpoints' shares too (cornersWiden) where the pair
    /// is below the straddle bound, or every point saw all of r or none while the corners' rays or
    /// the rims say otherwise (PairRules::centroidVerdictHolds: Penumbral). Both rows of the pair
    /// decide alike.
    Straddle straddleOf(PatchId e, PatchId r, double unoccluded, double least, double most, Workspace& ws,
                        RayCounts& counts) const;
    /// Row i's entry for receiver j (ray units) set to `value` in place of its terms, and kept so for
    /// the exchange; returns the change.
    static double replaceEntry(PatchId j, double value, RowAccumulator& row, Workspace& ws);
    /// The replacement value (ray units) of a pair: straddlingValue (Whole) or penumbralValue.
    double replacementValue(Straddle straddle, PatchId e, PatchId r, Workspace& ws, RayCounts& counts) const;
    /// Whether emitter e's pair with r, whose terms saw shares of r from `least` to `most` (one
    /// share per term: visible / whole for an exact term, its shadow ray's verdict for a ray term)
    /// with the unoccluded terms summing to `unoccluded` (ray units), straddles a shadow's edge:
    /// the shares too far apart, or all of them missing a part while a corner or an edge's
    /// midpoint of e (cornersWiden) sees a share far enough away. Both rows of the pair
    /// decide alike, bit for bit.
    bool straddlesWhole(PatchId e, PatchId r, double unoccluded, double& least, double& most, Workspace& ws,
                        RayCounts& counts) const;
    /// least..most widened by the shares (PairRules::visibleShare, exact) of e's corners, then of
    /// its edges' midpoints (a hundredth inside, neither end under a solid), one by one until
    /// enough() says so; whether it did. The midpoints: district1k's ground 67 sees wall 828
    /// through a gap between two buildings from a band across its middle alone (28 % of the pair
    /// visible, 0 at its corners and rule points); the 60 mm Cornell box's entries off by more
    /// than 1e-4 went from 6 to 4 with them, the district's from 14 to 10.
    template <class Enough>
    bool cornersWiden(PatchId e, PatchId r, double& least, double& most, Workspace& ws, RayCounts& counts,
                      Enough enough) const;
    /// After the centroid pass: its ray terms and the far rule's (probesPenumbra) for which the
    /// centroid's verdict does not hold (PairRules::centroidVerdictHolds: the emitter's corners or
    /// the bundle's rims disagree) replaced by their penumbralValue.
    double replacePenumbralPairs(PatchId i, RowAccumulator& row, Workspace& ws, RayCounts& counts) const;
    /// Their entries, scaled by `weight`, once the centroid pass has set its statuses too (the
    /// silhouette test reads the neighbours of both); those on a silhouette join the point's split.
    double addFarPairs(double weight, RowAccumulator& row, Workspace& ws) const;
    /// For the ray terms from point x of row i (receivers `patches` with their factors, above 0
    /// where there is a term, and their centre rays' verdicts `blocked`): whether a ray to a
    /// corner of the receiver (PairRules::receiverCornerTargets) got another verdict, into
    /// `differ`; such a term is split as a receiver on a silhouette is. The silhouette test asks
    /// the receiver's mesh neighbours, which are blind where a blocker's edge crosses a whole
    /// strip of them (a ground cell between buildings, a tall wall whose lower part a nearer
    /// building hides): their centres all see, or all miss, what their corners do not.
    void probeReceiverCorners(PatchId i, const Vec3& x, const std::vector<PatchId>& patches,
                              const std::vector<double>& factors, const std::vector<std::uint8_t>& blocked,
                              std::vector<std::uint8_t>& differ, Workspace& ws, RayCounts& counts) const;

    // As a receiver (analytic_receiver.cpp).
    /// Row i's entries for the patches that emit for i: the terms each of their rows sums for i
    /// (handed over by the exchange or recomputed), scaled by A_j / A_i; sets their visibility
    /// status. Returns their sum (row fraction in ray units).
    double addReversedPairs(PatchId i, RowAccumulator& row, Workspace& ws, RayCounts& counts) const;
    /// The terms row j sums for receiver i, appended to the workspace's reversed terms (with
    /// `rays`, a shadow ray per ray term); false when j has no term for i.
    bool reversedTerms(PatchId j, PatchId i, bool rays, Workspace& ws, RayCounts& counts) const;
    /// How emitter p's terms (with their shadow rays' verdicts) are replaced, as row j decides it
    /// as the emitter (replaceStraddlingPairs, replacePenumbralPairs).
    Straddle reversedStraddles(PatchId i, std::size_t p, Workspace& ws, RayCounts& counts) const;
    /// Of those, the emitters on a silhouette seen from i (a mesh neighbour's status differs): their
    /// ray terms again with i split into pieces, each with its own shadow ray (not for a pair that
    /// straddles a shadow's edge: its value is whole).
    void splitReversedSilhouettes(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// The emitters' ray terms whose rays to this row's corners disagree with their rays to its
    /// centre (row j's probeReceiverCorners), split as row j splits them (silhouetteTerm or
    /// pieces): into the reversed terms' splitValue, which their sum takes as row j's kept sum does.
    void splitDifferingTerms(PatchId i, Workspace& ws, RayCounts& counts) const;
    /// Reversed term t (emitter j's point) with this row's patch i split as row j splits it: its
    /// exact visible part above the silhouette bound, times the point's weight, into `exact` (left
    /// alone where 0); else each piece's shadow ray and value (factor times the weight) to
    /// piece(origin, target, value), in row j's order.
    template <class Piece>
    void splitTerm(PatchId j, PatchId i, std::uint32_t t, Workspace& ws, RayCounts& counts, double& exact,
                   Piece piece) const;

    HemisphereOptions m_options;
    const Scene* m_scene = nullptr;
    const RayScene* m_rays = nullptr;
    PairRules m_rules;
};

/// Shadow rays gathered, then cast as one batch: from one origin to many targets, or as segments
/// each with its own origin.
struct ShadowRayBatch {
    std::vector<float> origins, targets;  ///< 3 floats per ray (origins: segments only)
    std::vector<std::uint8_t> blocked;    ///< per ray after casting
    void clear() {
        origins.clear();
        targets.clear();
    }
    void addSegment(const float origin[3], const float target[3]) {
        origins.insert(origins.end(), origin, origin + 3);
        targets.insert(targets.end(), target, target + 3);
    }
    std::size_t segments() const { return origins.size() / 3; }
};

/// The sums a row keeps, as the emitter, for each receiver: its terms before its silhouette split
/// (0 for a pair hidden from every point), added in the order its receiver recomputes them, and
/// published at the end of the row so that the exchange hands over equal bits.
struct KeptSums {
    std::vector<double> sum;  ///< per receiver (-1: no term)
    std::vector<PatchId> touched;
    std::vector<PairExchange::Entry> outgoing;
    /// A term for receiver r: its value when visible, 0 when hidden.
    void keep(PatchId r, double visibleValue) {
        if (sum[r] < 0.0) {
            sum[r] = 0.0;
            touched.push_back(r);
        }
        if (visibleValue > 0.0) sum[r] += visibleValue;
    }
};

struct AnalyticEstimator::Workspace {
    PairRules::Scratch rules;
    PairExchange* exchange = nullptr;
    std::vector<std::uint8_t> status;  ///< per patch for one point: 0 not aimed at, 1 visible, 2 blocked
    KeptSums kept;

    // As the emitter: receivers by the order of their rule over the row ([0]: the far rule), and
    // the close pairs.
    std::vector<std::vector<PatchId>> byOrder;
    std::vector<std::uint8_t> ruled;  ///< per patch: in byOrder or a close pair (not in the centroid pass)
    std::vector<PatchId> contacts;
    /// Per receiver of a rule pass (order 2 and up): the rule's unoccluded terms summed (ray units)
    /// and the least and most share of the receiver any point saw (least > most: no term yet).
    struct Seen {
        std::vector<double> unoccluded;
        std::vector<float> least, most;
        void note(PatchId j, double share, double term) {
            unoccluded[j] += term;
            least[j] = std::min(least[j], float(share));
            most[j] = std::max(most[j], float(share));
        }
        void reset(PatchId j) {
            unoccluded[j] = 0.0;
            least[j] = 2.0f;
            most[j] = -1.0f;
        }
    } seen;
    /// One point's receivers with a shadow ray (candidates: their factors and aims), those with
    /// exact visibility (their visible and whole factors), and those on a silhouette.
    struct Point {
        std::vector<PatchId> candidates;
        std::vector<double> factors;
        ShadowRayBatch rays;
        std::vector<PatchId> exact;
        std::vector<double> exactVisible, exactWhole;
        std::vector<PatchId> split;
        std::vector<std::uint8_t> cornersDiffer;  ///< per candidate: a ray to its receiver's corner disagreed
        std::vector<std::uint8_t> splitKept;      ///< per split receiver: split because its corners disagreed
        std::vector<double> splitValue;           ///< per split receiver: its value split
        std::vector<std::uint32_t> pieceOf;       ///< per piece's ray: its split receiver
    } point;
    /// The receivers' corners' rays of one point (probeReceiverCorners) and the term of each.
    ShadowRayBatch cornerRays;
    std::vector<std::uint32_t> cornerRayTerm;
    /// The centroid pass's ray terms and far pairs that probesPenumbra: their factor, and their
    /// centroid ray's target and verdict.
    struct Penumbra {
        std::vector<PatchId> patches;
        std::vector<double> factors;
        std::vector<float> targets;
        std::vector<std::uint8_t> blocked;
        std::vector<std::uint8_t> verdicts, agree;  ///< one corner's verdicts; whether all corners agreed
        void add(PatchId j, double factor, const float* target, std::uint8_t verdict) {
            patches.push_back(j);
            factors.push_back(factor);
            targets.insert(targets.end(), target, target + 3);
            blocked.push_back(verdict);
        }
        void clear() {
            patches.clear();
            factors.clear();
            targets.clear();
            blocked.clear();
        }
    } penumbra;
    /// The far rule's receivers with a shadow ray from the centroid.
    struct Far {
        std::vector<PatchId> patches;
        std::vector<double> factors;
        ShadowRayBatch rays;
        std::vector<std::uint8_t> cornersDiffer;
    } far;

    // As a receiver: the patches that emit for this row, the range of each one's terms, its entry
    // and its terms' sum; per term its factor, weight, point and shadow ray.
    struct Reversed {
        std::vector<PatchId> emitters;
        std::vector<std::uint32_t> termBegin, termEnd;
        std::vector<double> sum;    ///< per emitter: its terms for this row, in ray units
        std::vector<double> handed;  ///< and its entry as the exchange hands it over (-1: from the terms)
        std::vector<double> factors, weights;
        std::vector<double> wholes;           ///< the unoccluded factor (exact terms: factors holds the visible part)
        std::vector<std::uint8_t> whole;      ///< per emitter: its pair straddles a shadow's edge, computed whole
        std::vector<Vec3> points;             ///< the emitter's point
        std::vector<std::uint32_t> pointIndex;  ///< its index in the emitter's rule
        std::vector<std::uint32_t> rayOf;     ///< its shadow ray, or kNoRay (exact: shadow polygons)
        ShadowRayBatch rays;
        std::vector<std::uint8_t> differs;    ///< per term: a ray to a corner of this row's patch disagreed with its ray
        std::vector<double> splitValue;       ///< per term that differs: its split value, as row j keeps it
        ShadowRayBatch cornerRays;            ///< those corners' rays (probeReceiverCorners' in row j)
        std::vector<std::uint32_t> cornerRayTerm;  ///< and the term of each
        ShadowRayBatch pieces;                ///< the pieces' rays of the terms that differ
        std::vector<std::uint32_t> pieceTerm;  ///< and the term of each
        std::vector<double> pieceTermValue;    ///< and its value (factor times the point's weight)
        std::vector<std::uint32_t> silhouette;  ///< the emitters on a silhouette seen from this row
        std::vector<std::uint32_t> pieceOf;     ///< per silhouette piece ray: its emitter
        std::vector<double> pieceValue;         ///< and its term (factor times the point's weight)
        std::vector<PairExchange::Entry> taken;  ///< handed over by the exchange
        std::vector<double> published;  ///< per patch: its row's entry for this one (-1: none)
        static constexpr std::uint32_t kNoRay = ~std::uint32_t(0);
        void clear() {
            emitters.clear();
            termBegin.clear();
            termEnd.clear();
            sum.clear();
            handed.clear();
            factors.clear();
            weights.clear();
            wholes.clear();
            whole.clear();
            points.clear();
            pointIndex.clear();
            rayOf.clear();
            rays.clear();
            differs.clear();
            cornerRays.clear();
            cornerRayTerm.clear();
        }
    } reversed;
};

}  // namespace hemirad
