// Close pairs: the exact unoccluded exchange area, a shaft test, and the adaptive hidden part.
#include "preprocess/hemisphere/contact_pairs.hpp"

#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <array>
#include <cmath>

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

double triangleArea(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a).norm(); }

}  // namespace

double ContactPairs::exchange(PatchId e, PatchId r, Scratch& s, Cost& cost, double& unoccluded) const {
    const PatchShape& a = m_geometry->shapes[e];
    const PatchShape& b = m_geometry->shapes[r];
    const double exact =
        exchangeArea(m_geometry->polygon(e), a.count, a.normal, m_geometry->polygon(r), b.count, b.normal, s.exchange);
    unoccluded = exact;
    if (!(exact > 0.0) || !m_visibility) return exact;
    return std::max(0.0, exact - hidden(e, r, exact, s, cost));
}

double ContactPairs::hidden(PatchId e, PatchId r, double exact, Scratch& s, Cost& cost) const {
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
    std::uint32_t evaluations = 0;
    bool sawVisible = false, sawHidden = false;  // some point saw part of r, some point missed part of it
    const auto estimate = [&](const Vec3& p0, const Vec3& p1, const Vec3& p2) {
        double sum = 0.0;
        for (std::size_t k = 0; k < rule.weight.size(); ++k) {
            const Vec3 x = rule.point[k][0] * p0 + rule.point[k][1] * p1 + rule.point[k][2] * p2;
            const double f = pointToPolygonFactor(x, n, receiver, corners);
            if (!(f > 0.0)) continue;
            const double visible = m_shadows->visibleFactor(x, n, receiver, corners, e, r, f, s.shadow, &s.blockers);
            sawVisible = sawVisible || visible > 0.0;
            sawHidden = sawHidden || visible < f;
            sum += rule.weight[k] * (f - visible);
        }
        evaluations += std::uint32_t(rule.weight.size());
        return sum * triangleArea(p0, p1, p2);
    };
    // A cell: a triangle, its rule's value and its four children's (corner-midpoint split).
    double forced = 0.0;  // per unit area: a cell's least error once the rims contradict the points
    const auto open = [&](const Vec3& p0, const Vec3& p1, const Vec3& p2, double coarse) {
        ContactCell c{{p0, p1, p2}, coarse, {}, 0.0, 0.0};
        const Vec3 m01 = 0.5 * (p0 + p1), m12 = 0.5 * (p1 + p2), m20 = 0.5 * (p2 + p0);
        c.child = {estimate(p0, m01, m20), estimate(m01, p1, m12), estimate(m20, m12, p2), estimate(m12, m20, m01)};
        c.fine = c.child[0] + c.child[1] + c.child[2] + c.child[3];
        c.error = std::abs(c.fine - c.coarse) + forced * triangleArea(p0, p1, p2);
        return c;
    };
    // The rule on each fan triangle, then its first split, whatever the points see: seven points
    // that all see the receiver whole (or none of it) do not make the pair unobstructed (or
    // hidden); the district's ground triangle 593 under a roof's edge saw wall 406 whole from all
    // seven and is 2 % hidden (0.1126 for 0.1104, a Monte Carlo estimate 0.1097 +- 0.0005).
    s.coarse.clear();
    double area = 0.0;
    for (std::size_t k = 1; k + 1 < s.emitter.size(); ++k) {
        const Vec3 &p0 = s.emitter[0], &p1 = s.emitter[k], &p2 = s.emitter[k + 1];
        area += triangleArea(p0, p1, p2);
        s.coarse.push_back(estimate(p0, p1, p2));
    }
    const auto larger = [](const ContactCell& a, const ContactCell& b) { return a.error < b.error; };
    s.cells.clear();
    double error = 0.0;
    for (std::size_t k = 1; k + 1 < s.emitter.size(); ++k) {
        const Vec3 &p0 = s.emitter[0], &p1 = s.emitter[k], &p2 = s.emitter[k + 1];
        s.cells.push_back(open(p0, p1, p2, s.coarse[k - 1]));
        error += s.cells.back().error;
        std::push_heap(s.cells.begin(), s.cells.end(), larger);
    }
    // Every point so far saw r whole, or none of it: a hidden (or visible) part of the view that
    // lies between them leaves every cell's disagreement near 0, and the refinement stops there at
    // any --pair-digits. The district's ground 157 saw wall 834 whole from all 35 points, 0.01706,
    // where a Monte Carlo estimate gives 0.01654 +- 0.00002; 264 -> 580 read 2e-9 for 1.3e-4. The
    // emitter's corners and edge midpoints (a thousandth inside) probe its rims: where one sees r
    // otherwise, every cell gets a least error by its area, and the budget refines them, the
    // largest first.
    if (!(sawVisible && sawHidden)) {
        Vec3 centre = Vec3::Zero();
        for (const Vec3& y : s.emitter) centre += y;
        centre /= double(s.emitter.size());
        bool contradicted = false;
        for (std::size_t k = 0; k < s.emitter.size() && !contradicted; ++k) {
            const Vec3 next = s.emitter[(k + 1) % s.emitter.size()];
            for (const Vec3& y : std::array<Vec3, 2>{s.emitter[k], Vec3(0.5 * (s.emitter[k] + next))}) {
                const Vec3 x = y + 1e-3 * (centre - y);
                const double f = pointToPolygonFactor(x, n, receiver, corners);
                if (!(f > 0.0)) continue;
                const double visible = m_shadows->visibleFactor(x, n, receiver, corners, e, r, f, s.shadow, &s.blockers);
                ++evaluations;
                if ((sawVisible && visible < f) || (sawHidden && visible > 0.0)) {
                    contradicted = true;
                    break;
                }
            }
        }
        if (contradicted) {
            forced = 1e-3 * exact / area;
            error = 0.0;
            for (ContactCell& c : s.cells) {
                c.error += forced * triangleArea(c.corner[0], c.corner[1], c.corner[2]);
                error += c.error;
            }
            std::make_heap(s.cells.begin(), s.cells.end(), larger);
        }
    }
    // The budget shrinks with the blockers in the shaft (each evaluation meets them all): a big
    // patch's pairs in a cluttered scene get one refinement, a touching pair past one blocker the
    // whole budget (2000 at the default --pair-digits 2, 2000 x 10^(D-2) at D).
    const double allowed = std::max(m_precision.tolerance * exact, m_precision.floor * area);
    const std::uint32_t budget = std::max<std::uint32_t>(
        kLeastEvaluations, m_precision.budget / std::uint32_t(std::max<std::size_t>(s.blockers.size(), 1)));
    while (error > allowed && evaluations < budget) {
        std::pop_heap(s.cells.begin(), s.cells.end(), larger);
        const ContactCell worst = s.cells.back();
        s.cells.pop_back();
        error -= worst.error;
        const Vec3 &p0 = worst.corner[0], &p1 = worst.corner[1], &p2 = worst.corner[2];
        const Vec3 m01 = 0.5 * (p0 + p1), m12 = 0.5 * (p1 + p2), m20 = 0.5 * (p2 + p0);
        const std::array<std::array<Vec3, 3>, 4> children = {{{p0, m01, m20}, {m01, p1, m12}, {m20, m12, p2}, {m12, m20, m01}}};
        for (std::size_t c = 0; c < 4; ++c) {
            s.cells.push_back(open(children[c][0], children[c][1], children[c][2], worst.child[c]));
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
    p.budget = std::uint32_t(std::min(2000.0 * std::pow(10.0, digits - 2.0), 2147483648.0));
    return p;
}

}  // namespace hemirad
