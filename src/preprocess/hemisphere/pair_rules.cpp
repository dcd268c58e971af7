#include "preprocess/hemisphere/pair_rules.hpp"

#include "engine/polygon.hpp"
#include "preprocess/hemisphere/obstruction.hpp"
#include "preprocess/hemisphere/patch_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hemirad {

namespace {

/// The emitter rules aim at the pair tolerance divided by this. Their error estimates (C rho^-2m,
/// the far kernel's constant) are fits, not bounds, and a low-order rule underestimates a convex
/// kernel (Jensen), so the errors of a row's pairs share a sign and add up along a wall: with the
/// tolerance alone a subdivided cube's adjacent walls were 3.2e-6 off at n = 16, with half 6.1e-7
/// (0.27 -> 0.30 s).
constexpr double kRuleMargin = 2.0;

}  // namespace

void PairRules::build(const Scene& scene, const RayScene& rays, const HemisphereOptions& options) {
    m_scene = &scene;
    m_rays = &rays;
    m_options = options;
    const std::vector<std::uint8_t> blocks = obstructingPatches(scene);
    m_visibility = std::find(blocks.begin(), blocks.end(), 1) != blocks.end();
    // Per pair, the lowest order good for --pair-digits: at least ceil(sqrt(K)) for --origins K,
    // the near-field order within kNearDistance.
    const double tolerance = std::pow(10.0, -double(options.pairDigits));
    m_orders = EmitterOrders(tolerance / kRuleMargin, farOrder(options.origins), nearOrder(options.origins));
    // The far rule is the default's: --origins K > 1 asks for at least ceil(sqrt(K))^2 points over the emitter.
    m_farRatio = options.origins == 1 ? std::pow(FarRule::kErrorConstant * kRuleMargin / tolerance, 0.25) : 0.0;
    const int highest = m_orders.highest();
    m_ruleNodes.assign(std::size_t(highest) + 1, {});
    m_ruleWeights.assign(m_ruleNodes.size(), {});
    for (int m = 1; m <= highest; ++m) gaussLegendre(m, m_ruleNodes[m], m_ruleWeights[m]);
    m_splitLevels = options.jitter ? 2 : 1;
    m_geometry.build(scene);
    if (m_farRatio > 0.0) m_far.build(m_geometry);
    m_geometry.buildNeighbours(scene);
    // Exact partial visibility where one shadow ray's verdict could move the pair by more than a
    // tenth of the pair tolerance in absolute terms (each row sums to at most 1).
    m_shadows.build(m_geometry, blocks);
    m_contacts.build(m_geometry, m_shadows, m_visibility, ContactPairs::precisionFor(options.pairDigits));
    m_wholePairs = options.pairs == PairMethod::Whole;
    // Whole pairs take the cover into their hidden parts; without blockers nothing can cover.
    m_covered = CoveredEmitters();
    if (m_visibility && !m_wholePairs) m_covered.build(m_geometry, rays);
    m_exactAbove = m_visibility ? 0.1 * tolerance : std::numeric_limits<double>::infinity();
    // A ruled pair across a shadow's edge is computed whole where the points' disagreement times
    // its factor could move it by as much as a term that gets its exact visible part (1e-3 by
    // default). A hundredth of the tolerance (1e-4) was measured too: on district1k it left 419
    // entries off by more than 1e-4 instead of 945 and the largest row sum 1.9e-3 off instead of
    // 2.8e-3, for cornell13k's F in 1.6x the time instead of 1.27x (31,510 pairs instead of 18,041).
    m_straddleAbove = m_visibility ? 0.1 * tolerance : std::numeric_limits<double>::infinity();
    // A term on a silhouette (its receiver's mesh neighbours' verdicts differ) is half hidden as
    // likely as not, and a row of many small terms along an occluder's limb adds their errors up:
    // exact from a tenth of the exact terms' bound (1e-4 by default). Pieces with a ray each left
    // two concentric faceted spheres' outer rows 4.5e-3 from closing, exact terms 9.1e-4. At half
    // the bound (5e-4), the terms in pieces held the largest share of district1k's entry errors
    // once the pairs in a penumbra were computed whole (0.057 of 0.176, and 12 of its 46 entries
    // off by more than 1e-4); at a tenth they hold 0.014 and the district has 35 such entries, for
    // 1.05x its time (every silhouette term exact: 35, 1.16x). (Before the pairs in a penumbra and
    // across a shadow's edge were computed whole, 1e-4 took district1k 1.7x its time.)
    m_silhouetteExactAbove = 0.01 * tolerance;
    // A ray term from the centroid is one verdict for the whole emitter. Where an occluder's edge
    // crosses the view between the emitter's points, that verdict is all or nothing for a pair that
    // is partly seen, and a row's such pairs err alike (all behind the same edge): the subdivided
    // Cornell box's floor patches under a block summed 1.5e-2 off, district1k's tall wall slivers
    // 2.8e-3. Terms from a hundredth of the tolerance (1e-4) up ask the emitter's corners: from
    // 1e-5 up cornell13k's F took 45 s instead of 33 s (25 s without probes), for no better
    // district1k, Cornell box or spheres.
    m_penumbraProbeAbove = m_visibility ? 1e-2 * tolerance : std::numeric_limits<double>::infinity();
}

double PairRules::contactValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts, bool& viewed, bool close) const {
    if (close && !m_wholePairs && ruleRatio(e, r) >= kNearDistance) return cutValue(e, r, s, counts, viewed);
    return wholeValue(e, r, s, counts, viewed, close);
}

double PairRules::wholeValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts, bool& viewed, bool close) const {
    ContactPairs::Cost cost;
    double unoccluded = 0.0;
    const double exchange = m_contacts.exchange(e, r, s.contact, cost, unoccluded, close || m_wholePairs);
    viewed = unoccluded > 0.0;
    ++counts.contactPairs;
    counts.contactShafts += cost.shafts;
    counts.contactEvaluations += cost.evaluations;
    return exchange / m_scene->patches[e].area * unit();
}

double PairRules::cutValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts, bool& viewed) const {
    ++counts.cutPairs;
    viewed = false;
    const PatchShape& a = m_geometry.shapes[e];
    const PatchShape& b = m_geometry.shapes[r];
    clipAbovePlane(b.centroid, b.normal, m_geometry.polygon(e), a.count, s.front);
    if (s.front.size() < 3) return 0.0;
    const PolygonMeasures part = measurePolygon(s.front);
    if (!(part.area > 0.0)) return 0.0;
    const double share = std::min(1.0, part.area / m_scene->patches[e].area);
    const int m = std::min(std::max(1, ruleOrder(e, r)), int(m_ruleNodes.size()) - 1);
    s.cutPoints.clear();
    s.cutWeights.clear();
    if (m == 1) {  // the part's centroid (one Gauss node per fan triangle would sit off its centre)
        s.cutPoints.push_back(part.centroid);
        s.cutWeights.push_back(1.0);
    } else {
        polygonQuadrature(s.front.data(), s.front.size(), m_ruleNodes[m], m_ruleWeights[m], s.cutPoints, s.cutWeights);
    }
    double sum = 0.0, least = 2.0, most = -1.0;  // the points' visible shares
    for (std::size_t k = 0; k < s.cutPoints.size(); ++k) {
        PointTerm term;
        term.factor = pointFactor(r, s.cutPoints[k], a.normal, s.clipped, term.polygon, term.corners);
        if (!(term.factor > 0.0)) continue;
        viewed = true;
        double visible = term.factor;
        if (m_visibility) visible = exactVisible(e, r, s.cutPoints[k], term, s, counts.shadowTerms);
        least = std::min(least, visible / term.factor);
        most = std::max(most, visible / term.factor);
        sum += s.cutWeights[k] * visible;
    }
    if (!m_visibility) return share * sum * unit();
    // The front part's corners (inset by 1 % towards its centroid) ask whether a shadow's edge
    // crosses it: then the pair is computed whole, as a penumbral one.
    for (const Vec3& p : s.front) {
        const double corner = visibleShare(e, r, p + 0.01 * (part.centroid - p), s, counts);
        if (!(corner >= 0.0)) continue;
        least = std::min(least, corner);
        most = std::max(most, corner);
    }
    if (most - least > kStraddleSpread) {
        ++counts.cutWholePairs;
        return wholeValue(e, r, s, counts, viewed, true);
    }
    return share * sum * unit();
}

double PairRules::straddlingValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts) const {
    bool viewed = false;
    ++counts.straddlingPairs;  // of the pairs contactValue counts
    return contactValue(e, r, s, counts, viewed, false);
}

bool PairRules::probesAgree(bool blocked, Scratch& s, RayCounts& counts) const {
    const std::size_t rays = s.probeOrigins.size() / 3;
    s.probeBlocked.assign(rays, 0);
    if (rays > 0)
        m_rays->occludedSegmentPairs(s.probeOrigins.data(), s.probeTargets.data(), rays, s.probeBlocked.data());
    counts.rays += rays;
    for (std::size_t k = 0; k < rays; ++k)
        if ((s.probeBlocked[k] != 0) != blocked) return false;
    return true;
}

bool PairRules::cornersAgree(PatchId e, const float target[3], bool blocked, Scratch& s, RayCounts& counts) const {
    const PatchShape& shape = m_geometry.shapes[e];
    s.probeOrigins.clear();
    s.probeTargets.clear();
    for (std::uint32_t k = 0; k < shape.count; ++k) {
        if (cornerCovered(e, k)) continue;
        float origin[3];
        rayOrigin(e, cornerProbe(e, k), origin);
        s.probeOrigins.insert(s.probeOrigins.end(), origin, origin + 3);
        s.probeTargets.insert(s.probeTargets.end(), target, target + 3);
    }
    return probesAgree(blocked, s, counts);
}

bool PairRules::extremesAgree(PatchId e, PatchId r, double factor, bool blocked, Scratch& s, RayCounts& counts) const {
    if (factor < kExtremesAbove * m_exactAbove) return true;
    const PatchShape& a = m_geometry.shapes[e];
    const PatchShape& b = m_geometry.shapes[r];
    Vec3 axis = b.centroid - a.centroid;
    const double length = axis.norm();
    if (!(length > 0.0)) return true;
    axis /= length;
    // A corner's offset from its patch's centroid across the axis.
    const auto across = [&](PatchId j, std::uint32_t k) {
        const Vec3 d = m_geometry.insetCorner(j, k) - m_geometry.shapes[j].centroid;
        return Vec3(d - axis.dot(d) * axis);
    };
    // The corner of j furthest along u (of e: one no solid covers, which sees nothing); none: j's count.
    const auto furthest = [&](PatchId j, const Vec3& u) {
        std::uint32_t best = m_geometry.shapes[j].count;
        double most = -std::numeric_limits<double>::infinity();
        for (std::uint32_t l = 0; l < m_geometry.shapes[j].count; ++l) {
            if (j == e && cornerCovered(e, l)) continue;
            const double h = across(j, l).dot(u);
            if (h > most) most = h, best = l;
        }
        return best;
    };
    s.probeOrigins.clear();
    s.probeTargets.clear();
    s.probePairs.clear();
    // One ray per pair of corners (facing patches pair the same corners from both sides), and
    // none where one end lies behind the other's plane: that segment would cross e or r itself.
    const auto aim = [&](std::uint32_t k, std::uint32_t l) {
        if (k >= a.count || l >= b.count) return;
        const std::uint32_t key = k * b.count + l;
        if (std::find(s.probePairs.begin(), s.probePairs.end(), key) != s.probePairs.end()) return;
        s.probePairs.push_back(key);
        const Vec3 x = cornerProbe(e, k), y = m_geometry.insetCorner(r, l);
        if (!(a.normal.dot(y - x) > 0.0) || !(b.normal.dot(x - y) > 0.0)) return;
        float origin[3], target[3];
        rayOrigin(e, x, origin);
        m_rays->toLocal(y + m_rays->originOffset() * b.normal, target);
        s.probeOrigins.insert(s.probeOrigins.end(), origin, origin + 3);
        s.probeTargets.insert(s.probeTargets.end(), target, target + 3);
    };
    for (std::uint32_t k = 0; k < a.count; ++k)
        if (!cornerCovered(e, k)) aim(k, furthest(r, across(e, k)));
    for (std::uint32_t l = 0; l < b.count; ++l) aim(furthest(e, across(r, l)), l);
    if (!probesAgree(blocked, s, counts)) return false;
    // Every ray was blocked; the centroid may still see a part of r between them (the rays aim at
    // r's centre and rims), or a corner may see it past an occluder's edge that hides the rest
    // of e. Then the pair is in a penumbra: its one ray read 0 for all of it.
    if (!blocked) return true;
    if (visibleShare(e, r, a.centroid, s, counts) > kBlockedCentreShare) return false;
    for (std::uint32_t k = 0; k < a.count; ++k)
        if (!cornerCovered(e, k) && visibleShare(e, r, cornerProbe(e, k), s, counts) > kStraddleSpread) return false;
    return true;
}

double PairRules::penumbralValue(PatchId e, PatchId r, Scratch& s, RayCounts& counts) const {
    bool viewed = false;
    ++counts.penumbralPairs;  // of the pairs contactValue counts
    return contactValue(e, r, s, counts, viewed, false);
}

void PairRules::ruleOver(PatchId e, int m, std::vector<Vec3>& points, std::vector<double>& weights) const {
    points.clear();
    weights.clear();
    if (m_covered.covered(e)) {
        m_covered.freeRule(e, m, points, weights);
        return;
    }
    if (m == 1) {
        points.push_back(m_geometry.shapes[e].centroid);
        weights.push_back(1.0);
        return;
    }
    polygonQuadrature(m_geometry.polygon(e), m_geometry.shapes[e].count, m_ruleNodes[std::size_t(m)],
                      m_ruleWeights[std::size_t(m)], points, weights);
}

double PairRules::visibleShare(PatchId e, PatchId r, const Vec3& x, Scratch& s, RayCounts& counts) const {
    PointTerm term;
    term.factor = pointFactor(r, x, m_geometry.shapes[e].normal, s.clipped, term.polygon, term.corners);
    if (!(term.factor > 0.0)) return -1.0;
    return exactVisible(e, r, x, term, s, counts.shadowProbes) / term.factor;
}

bool PairRules::pointTerm(PatchId e, PatchId r, const Vec3& x, Scratch& s, RayCounts& counts, PointTerm& term) const {
    const Vec3& n = m_geometry.shapes[e].normal;
    term.factor = pointFactor(r, x, n, s.clipped, term.polygon, term.corners);
    if (!(term.factor > 0.0)) return false;
    term.exact = term.factor > m_exactAbove;  // too large for one shadow ray's verdict
    if (term.exact) term.visible = exactVisible(e, r, x, term, s, counts.shadowTerms);
    return true;
}

std::size_t PairRules::receiverCornerTargets(PatchId e, PatchId r, const Vec3& x, std::vector<float>& targets) const {
    const Vec3& n = m_geometry.shapes[e].normal;
    const PatchShape& shape = m_geometry.shapes[r];
    std::size_t added = 0;
    for (std::uint32_t k = 0; k < shape.count; ++k) {
        const Vec3 y = m_geometry.insetCorner(r, k);
        if (!(n.dot(y - x) > 0.0)) continue;
        float target[3];
        m_rays->toLocal(y + m_rays->originOffset() * shape.normal, target);
        targets.insert(targets.end(), target, target + 3);
        ++added;
    }
    return added;
}

void PairRules::rayOrigin(PatchId e, const Vec3& x, float origin[3]) const {
    m_rays->toLocal(x + m_rays->originOffset() * m_geometry.shapes[e].normal, origin);
}

void PairRules::rayTarget(PatchId e, PatchId r, const Vec3* polygon, std::size_t corners, std::uint32_t point,
                          std::uint32_t piece, float target[3]) const {
    m_rays->toLocal(aimPoint(polygon, corners, e, r, point, piece) + m_rays->originOffset() * m_geometry.shapes[r].normal,
                    target);
}

void PairRules::piecesOf(const Vec3* polygon, std::size_t corners, Scratch& s) const {
    s.pieces.clear();
    splitPolygon(polygon, corners, s.pieces);
    for (int level = 1; level < m_splitLevels; ++level) {
        s.finer.clear();
        for (std::size_t q = 0; q < s.pieces.size(); q += 4) splitPolygon(&s.pieces[q], 4, s.finer);
        s.pieces.swap(s.finer);
    }
}

std::size_t PairRules::polygonAbove(PatchId j, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer,
                                    const Vec3*& polygon) const {
    const PatchShape& t = m_geometry.shapes[j];
    polygon = &m_geometry.corners[t.first];
    const double height = n.dot(t.centroid - x);
    if (height <= -t.radius) return 0;
    bool below = false;
    if (height < t.radius)
        for (std::uint32_t k = 0; k < t.count && !below; ++k) below = n.dot(polygon[k] - x) < 0.0;
    if (!below) return t.count;
    clipAbovePlane(x, n, polygon, t.count, buffer);
    polygon = buffer.data();
    return buffer.size();
}

double PairRules::pointFactor(PatchId r, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer, const Vec3*& polygon,
                              std::size_t& corners) const {
    const PatchShape& t = m_geometry.shapes[r];
    corners = 0;
    if (t.normal.dot(x - t.centroid) <= 1e-9 * t.radius) return 0.0;  // x must lie in front of r
    corners = polygonAbove(r, x, n, buffer, polygon);
    return corners == 0 ? 0.0 : pointToPolygonFactor(x, n, polygon, corners);
}

Vec3 PairRules::aimPoint(const Vec3* polygon, std::size_t corners, PatchId e, PatchId r, std::uint32_t point,
                         std::uint32_t piece) const {
    if (!m_options.jitter) return vertexMean(polygon, corners);
    // Drawn from the pair alone, so both rows of a pair aim their shadow rays alike.
    Random random(((m_options.seed * 0x9e3779b97f4a7c15ULL ^ (std::uint64_t(e) << 32 | r)) + 0xa5a5a5a5deadbeefULL) ^
                  (std::uint64_t(point) << 40 | std::uint64_t(piece) << 8));
    const double u = random.uniform(), v = random.uniform();
    return pointOnPolygon(polygon, corners, u, v);
}

}  // namespace hemirad
