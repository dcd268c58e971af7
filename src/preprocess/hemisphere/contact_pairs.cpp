// Close pairs: the exact unoccluded exchange area, a shaft test, and the adaptive hidden part.
#include "preprocess/hemisphere/contact_pairs.hpp"

#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hemirad {

namespace {

/// Dunavant's degree-5 rule on a triangle: barycentric points (a, b, b) in 3 rotations, weights
/// summing to 1.
struct TriangleRule {
    std::array<std::array<double, 3>, 7> point;
    std::array<double, 7> weight;
};
const TriangleRule& dunavant5() {
    static const TriangleRule rule = [] {
        TriangleRule t;
        const double a1 = 0.059715871789770, b1 = 0.470142064105115, w1 = 0.132394152788506;
        const double a2 = 0.797426985353087, b2 = 0.101286507323456, w2 = 0.125939180544827;
        t.point[0] = {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
        t.weight[0] = 0.225;
        for (int k = 0; k < 3; ++k) {
            std::array<double, 3> p1 = {b1, b1, b1}, p2 = {b2, b2, b2};
            p1[k] = a1;
            p2[k] = a2;
            t.point[1 + k] = p1;
            t.weight[1 + k] = w1;
            t.point[4 + k] = p2;
            t.weight[4 + k] = w2;
        }
        return t;
    }();
    return rule;
}

/// The planes of the convex hull of two planar convex polygons, inward: each polygon's own plane
/// and every plane through an edge of one and a corner of the other that has all corners of both
/// on its inner side (the hull's bridge faces).
void hullPlanes(const std::vector<Vec3>& a, const Vec3& normalA, const std::vector<Vec3>& b, const Vec3& normalB,
                double tolerance, std::vector<Vec3>& normals, std::vector<double>& offsets) {
    normals.clear();
    offsets.clear();
    normals.push_back(normalA);
    offsets.push_back(normalA.dot(a[0]));
    normals.push_back(normalB);
    offsets.push_back(normalB.dot(b[0]));
    const auto bridges = [&](const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
        for (std::size_t k = 0; k < p.size(); ++k) {
            const Vec3& p0 = p[k];
            const Vec3 edge = p[(k + 1) % p.size()] - p0;
            for (const Vec3& v : q) {
                Vec3 m = edge.cross(v - p0);
                const double length = m.norm();
                if (!(length > 0.0)) continue;
                m /= length;
                double low = 0.0, high = 0.0;
                for (const auto* set : {&p, &q})
                    for (const Vec3& y : *set) {
                        const double h = m.dot(y - p0);
                        low = std::min(low, h);
                        high = std::max(high, h);
                    }
                if (low >= -tolerance) {
                    normals.push_back(m);
                    offsets.push_back(m.dot(p0));
                } else if (high <= tolerance) {
                    normals.push_back(-m);
                    offsets.push_back(-m.dot(p0));
                }
            }
        }
    };
    bridges(a, b);
    bridges(b, a);
}

/// The share of a cell's least error (a view its rim has and its points have not, or a jump
/// between them) that counts toward its error. Whole, it took a pair short of budget off its
/// disagreements: district1k's 344 -> 855 read 0.12068 for 0.12024 (0.12031 before the rims), and
/// 62 entries were off by more than 1e-4; 0.1 left 60, 0.03 55 (budget 2000, every cell's rim
/// evaluated; 45 with the rims' checks, 46 with them for close pairs only).
constexpr double kLeastErrorShare = 0.03;

/// The share of a cell's visible spread (some points see a part of the receiver, others all or
/// none: a shadow's edge crosses it) that counts toward its error. At 0.03 the cells along such
/// edges took the budget from the rest of the pair: the touching pair past an occluder of
/// test_contact_pairs.cpp went from 7e-5 to 4e-4 relative; at 0.003 both it and district1k's
/// 215 -> 833 are within 1.4e-4 (0.01: 1.7e-4 and 2.9e-4), for 6 % more of district1k's
/// visible-part evaluations instead of 20 %.
constexpr double kNarrowingErrorShare = 0.003;

double triangleArea(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a).norm(); }

}  // namespace

double ContactPairs::exchange(PatchId e, PatchId r, Scratch& s, Cost& cost, double& unoccluded, bool changes) const {
    const PatchShape& a = m_geometry->shapes[e];
    const PatchShape& b = m_geometry->shapes[r];
    const double exact =
        exchangeArea(m_geometry->polygon(e), a.count, a.normal, m_geometry->polygon(r), b.count, b.normal, s.exchange);
    unoccluded = exact;
    if (!(exact > 0.0) || !m_visibility) return exact;
    return std::max(0.0, exact - hidden(e, r, exact, s, cost, changes));
}

double ContactPairs::hidden(PatchId e, PatchId r, double exact, Scratch& s, Cost& cost, bool changes) const {
    // The parts of e and r in front of each other (exchangeArea's clipping).
    s.emitter = s.exchange.e;
    s.receiver = s.exchange.r;
    const Vec3& n = m_geometry->shapes[e].normal;
    const Vec3& normalR = m_geometry->shapes[r].normal;
    double size = 0.0;
    for (const Vec3& y : s.emitter) size = std::max(size, (y - s.receiver[0]).norm());
    const double tolerance = 1e-9 * size;
    hullPlanes(s.emitter, n, s.receiver, normalR, tolerance, s.hullNormals, s.hullOffsets);
    m_shadows->collect(s.hullNormals.data(), s.hullOffsets.data(), s.hullNormals.size(), tolerance, e, r, s.blockers,
                       s.shadow);
    if (s.blockers.empty()) return 0.0;
    ++cost.shafts;

    // sum over the emitter part of (f - visible) dA, globally adaptive on triangles from its fan:
    // the triangle whose children disagree most with it is split next (QUADPACK's strategy), until
    // the disagreements sum below the tolerance or the budget is spent; the children's sums are the
    // estimate. Deterministic: both rows of a pair get the same bits.
    const TriangleRule& rule = dunavant5();
    const Vec3* receiver = s.receiver.data();
    const std::size_t corners = s.receiver.size();
    std::uint64_t evaluations = 0;
    // The hidden part of r's factor f at x, f - visible, and x's view of r: 1 all of it, 2 a part,
    // 4 none of it (0: x has no view of r at all).
    const auto hiddenAt = [&](const Vec3& x, std::uint8_t& seen, double& visible) {
        ++evaluations;
        const double f = pointToPolygonFactor(x, n, receiver, corners);
        visible = 0.0;
        if (!(f > 0.0)) {
            seen = 0;
            return 0.0;
        }
        visible = m_shadows->visibleFactor(x, n, receiver, corners, e, r, f, s.shadow, &s.blockers);
        seen = visible < f ? (visible > 0.0 ? 2 : 4) : 1;
        return f - visible;
    };
    // The views the rule's points of the cell being opened had, their least and largest hidden
    // part, and their least and largest visible part.
    std::uint8_t views = 0;
    double lowest = 0.0, highest = 0.0, leastVisible = 0.0, mostVisible = 0.0;
    const auto estimate = [&](const Vec3& p0, const Vec3& p1, const Vec3& p2) {
        double sum = 0.0;
        for (std::size_t k = 0; k < rule.weight.size(); ++k) {
            std::uint8_t seen = 0;
            double visible = 0.0;
            const double h =
                hiddenAt(rule.point[k][0] * p0 + rule.point[k][1] * p1 + rule.point[k][2] * p2, seen, visible);
            sum += rule.weight[k] * h;
            views |= seen;
            if (seen == 0) continue;
            lowest = std::min(lowest, h), highest = std::max(highest, h);
            leastVisible = std::min(leastVisible, visible), mostVisible = std::max(mostVisible, visible);
        }
        return sum * triangleArea(p0, p1, p2);
    };
    // A cell: a triangle, its rule's value and its four children's (corner-midpoint split), and
    // their disagreement as its error. Where the view changes within the cell, that disagreement
    // can be 0 by chance: the rule's points (none nearer an edge than 6 % of the cell) all fell on
    // one side of the change. So a share (kLeastErrorShare) of a least error counts too:
    //   - where a corner or an edge's midpoint (a thousandth inside) has a view none of the rule's
    //     points had, its hidden part less the cell's mean, times the area: the cell is split
    //     until its points see what its rim sees (the emitter's rim first, then the children of
    //     cells whose rim disagreed: district1k's ground 157 saw wall 834 whole from all 35 first
    //     points, 0.01706 for a Monte Carlo estimate of 0.01654 +- 0.00002; 792 -> 636 read 0 for
    //     1.18e-4);
    //   - where some points saw all of r and some none of it (a jump: a blocker standing on the
    //     emitter's plane, or a penumbra narrower than the cell), the spread of their hidden
    //     parts times the area: the district's ground sliver 157, a building's corner standing on
    //     its tip, reads 0.016158 for wall 832 (Monte Carlo 0.016165 +- 1e-5) where the
    //     disagreements stopped the refinement at 0.016244 even with --pair-digits 4;
    //   - where some points saw a part of r and others all of it or none (a shadow's edge crosses
    //     the cell: the visible part has a kink along it, which a polynomial rule misses at any
    //     level until the cell is small), the spread of their visible parts times the area: the
    //     district's ground 215 sees wall 833 past a building standing on its edge, the view
    //     narrowing across it from 0.0117 to 0; the 35 first points gave a disagreement of 4e-6
    //     of F and the pair read 0.00243 for 0.00221 (a Monte Carlo estimate 0.002222 +- 1e-5).
    //     With it district1k's entries off by more than 1e-4 went from 10 to 7, for 6 % more
    //     visible-part evaluations (the 60 mm Cornell box: no change), its share smaller
    //     (kNarrowingErrorShare). The visible spread, not the hidden one: a pair whose points
    //     see slivers of r at a contact and none of it elsewhere (the same ground and the
    //     building's west wall) is hidden almost whole, and its hidden parts' spread (f's own
    //     variation) spent the whole budget on nothing.
    // Close pairs only (`changes`): far pairs computed whole (across a shadow's edge, in a
    // penumbra) gained nothing from them and took the Cornell box at 60 mm 1.29x its time (user
    // seconds 4.78 -> 6.15; district1k 46 entries off by more than 1e-4 without, 45 with).
    double allowed = 0.0;  // the error the pair may keep (set once the emitter's area is known)
    // `rimPoints`: the rim's corners (3) or its corners and edges' midpoints (6).
    const auto open = [&](const Vec3& p0, const Vec3& p1, const Vec3& p2, double coarse, bool rim, std::size_t rimPoints = 6) {
        ContactCell c{{p0, p1, p2}, coarse, {}, 0.0, 0.0, false};
        const Vec3 m01 = 0.5 * (p0 + p1), m12 = 0.5 * (p1 + p2), m20 = 0.5 * (p2 + p0);
        views = 0;
        lowest = std::numeric_limits<double>::infinity();
        highest = 0.0;
        leastVisible = std::numeric_limits<double>::infinity();
        mostVisible = 0.0;
        c.child = {estimate(p0, m01, m20), estimate(m01, p1, m12), estimate(m20, m12, p2), estimate(m12, m20, m01)};
        c.fine = c.child[0] + c.child[1] + c.child[2] + c.child[3];
        double least = 0.0;  // the cell's least error per unit area
        if (changes && (views & 1) && (views & 4))
            least = highest - lowest;
        else if (changes && (views & 2) && (views & 5))
            least = kNarrowingErrorShare / kLeastErrorShare * (mostVisible - leastVisible);
        const Vec3 centre = (p0 + p1 + p2) / 3.0;
        const double cellArea = triangleArea(p0, p1, p2);
        const std::array<Vec3, 6> rimAt = {p0, p1, p2, m01, m12, m20};
        for (std::size_t q = 0; rim && q < std::min(rimPoints, rimAt.size()); ++q) {
            const Vec3& y = rimAt[q];
            std::uint8_t seen = 0;
            double visible = 0.0;
            const double h = hiddenAt(y + 1e-3 * (centre - y), seen, visible);
            if (seen == 0 || !(cellArea > 0.0)) continue;
            if (!(seen & views)) {  // a view none of the points had
                least = std::max(least, std::abs(h - c.fine / cellArea));
                c.rim = true;
            } else if (!changes) {  // a far pair: a hidden part beyond the points' range
                const double beyond = std::max(h - highest, lowest - h);
                if (!(beyond > 0.0)) continue;
                least = std::max(least, beyond);
                if (kLeastErrorShare * beyond * cellArea > allowed) c.rim = true;
            }
        }
        c.error = std::abs(c.fine - c.coarse) + kLeastErrorShare * least * cellArea;
        return c;
    };
    // The rule on each fan triangle, then its first split, whatever the points see: seven points
    // that all see the receiver whole (or none of it) do not make the pair unobstructed (or
    // hidden); the district's ground triangle 593 under a roof's edge saw wall 406 whole from all
    // seven and is 2 % hidden (0.1126 for 0.1104, a Monte Carlo estimate 0.1097 +- 0.0005).
    s.coarse.clear();
    double area = 0.0;
    views = 0;
    for (std::size_t k = 1; k + 1 < s.emitter.size(); ++k) {
        const Vec3 &p0 = s.emitter[0], &p1 = s.emitter[k], &p2 = s.emitter[k + 1];
        area += triangleArea(p0, p1, p2);
        s.coarse.push_back(estimate(p0, p1, p2));
    }
    // A far pair computed whole is in a penumbra or across a shadow's edge: its emitter's corners
    // or points disagreed, and the rims are where the first points may miss why. Where they all
    // see none of r, only the rims find the view (district1k's ground sliver 271 sees wall 588
    // from a wedge along one edge, 4 % of it, and read 1.5e-12 for 1.42e-4). Where the points
    // see r whole or nearly, a rim point's hidden part beyond theirs counts as a least error
    // (open(), far pairs): district1k's wall sliver 835 stands on a neighbour's roof, whose edge
    // hides up to 40 % of the wall 806 from the sliver's lowest metre; the first 35 points, all
    // above it, saw 99 % or more, and the pair read 0.005093 for 0.005072 (as did 804 and
    // 958). Such a far pair's first cells ask their corners (its midpoints too where the points
    // see none), and a cell keeps its rims for its children only where that least error could
    // reach the pair's allowance. On district1k alone it took the rows off by more than 1e-4 from
    // 25 to 22 (summed entry error 0.0655 -> 0.0620). Visible-part evaluations with it (and the
    // corners' check of PairRules::extremesAgree): district1k +7 %, the 60 mm box +30 % (29,467 of
    // its 57,378 pairs computed whole are far), the concentric spheres +28 % (1.38x the time: each
    // evaluation meets the inner sphere's facets), cornell13k +11 % (1.08x the time). Every first
    // cell's midpoints too cost the spheres and the box another 7 % and 4 % of evaluations for no
    // better district1k.
    allowed = std::max(m_precision.tolerance * exact, m_precision.floor * area);
    const auto larger = [](const ContactCell& a, const ContactCell& b) { return a.error < b.error; };
    s.cells.clear();
    double error = 0.0;
    for (std::size_t k = 1; k + 1 < s.emitter.size(); ++k) {
        const Vec3 &p0 = s.emitter[0], &p1 = s.emitter[k], &p2 = s.emitter[k + 1];
        s.cells.push_back(open(p0, p1, p2, s.coarse[k - 1], true, changes || views == 4 ? 6 : 3));
        error += s.cells.back().error;
        std::push_heap(s.cells.begin(), s.cells.end(), larger);
    }
    // The budget shrinks with the blockers in the shaft (each evaluation meets them all): a big
    // patch's pairs in a cluttered scene get one refinement, a touching pair past one blocker the
    // whole budget (2500 at the default --pair-digits 2, 2500 x 10^(D-2) at D; it was 2000 before
    // the rims were evaluated, which add 6 evaluations to each child of a cell whose rim disagreed).
    // Past it, a pair whose disagreements still sum above the overrun (twice the floor) goes on,
    // up to kBudgetOverrun times the budget.
    const std::uint32_t budget = std::max<std::uint32_t>(
        kLeastEvaluations, m_precision.budget / std::uint32_t(std::max<std::size_t>(s.blockers.size(), 1)));
    const double overrun = m_precision.overrun * area;
    const std::uint64_t most = std::uint64_t(kBudgetOverrun) * budget;
    while (error > allowed && (evaluations < budget || (error > overrun && evaluations < most))) {
        std::pop_heap(s.cells.begin(), s.cells.end(), larger);
        const ContactCell worst = s.cells.back();
        s.cells.pop_back();
        error -= worst.error;
        const Vec3 &p0 = worst.corner[0], &p1 = worst.corner[1], &p2 = worst.corner[2];
        const Vec3 m01 = 0.5 * (p0 + p1), m12 = 0.5 * (p1 + p2), m20 = 0.5 * (p2 + p0);
        const std::array<std::array<Vec3, 3>, 4> children = {{{p0, m01, m20}, {m01, p1, m12}, {m20, m12, p2}, {m12, m20, m01}}};
        for (std::size_t c = 0; c < 4; ++c) {
            s.cells.push_back(open(children[c][0], children[c][1], children[c][2], worst.child[c], worst.rim));
            error += s.cells.back().error;
            std::push_heap(s.cells.begin(), s.cells.end(), larger);
        }
    }
    double sum = 0.0;
    for (const ContactCell& c : s.cells) sum += c.fine;
    cost.evaluations += evaluations;
    return sum;
}

ContactPairs::Precision ContactPairs::precisionFor(std::uint32_t pairDigits) {
    const double digits = double(pairDigits);
    Precision p;
    p.tolerance = std::pow(10.0, -(digits + 2.0));
    p.floor = std::pow(10.0, -(digits + 3.0));
    p.overrun = 2.0 * p.floor;
    p.budget = std::uint32_t(std::min(2500.0 * std::pow(10.0, digits - 2.0), 2147483648.0));
    return p;
}

}  // namespace hemirad
