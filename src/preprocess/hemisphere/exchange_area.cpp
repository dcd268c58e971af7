// Exact exchange areas of touching polygons: the double contour integral with graded rules at the
// contact singularities, and the contact classification.
#include "preprocess/hemisphere/exchange_area.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace hemirad {

namespace {

/// Gauss-Legendre on [-1, 1], 10 points (Abramowitz & Stegun 25.4.30): enough for a piece whose
/// nearest singularity lies at least its own length away (error ~ 5.8^-20).
constexpr std::array<double, 5> kNodes = {0.1488743389816312, 0.4333953941292472, 0.6794095682990244,
                                           0.8650633666889845, 0.9739065285171717};
constexpr std::array<double, 5> kWeights = {0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
                                             0.1494513491505806, 0.0666713443086881};
/// Grading towards a contact: pieces shrink by this ratio (a piece's singularity then lies
/// 0.43 of its length beyond its end: ~1e-11 per piece at 10 points).
constexpr double kGrading = 0.3;
/// The innermost graded piece, relative to the edge: an s ln s contact contributes ~ h^2 there.
constexpr double kInnermost = 1e-7;

using Edge = ContourEdge;

/// int_0^L ln(|p - q0 - t v| / scale) dt for unit v, closed form: with tau = t - a, a = (p - q0) . v and
/// h the distance of p from the line, the antiderivative of ln sqrt(tau^2 + h^2) is
/// tau ln sqrt(tau^2 + h^2) - tau + h atan(tau / h).
double lineLogIntegral(const Vec3& p, const Edge& b, double logScale) {
    const Vec3 w = p - b.start;
    const double a = w.dot(b.direction);
    const double h = (w - a * b.direction).norm();
    const auto antiderivative = [&](double tau) {
        const double r2 = tau * tau + h * h;
        double g = -tau;
        if (r2 > 0.0) g += tau * (0.5 * std::log(r2) - logScale);
        if (h > 0.0) g += h * std::atan(tau / h);
        return g;
    };
    return antiderivative(b.length - a) - antiderivative(-a);
}

double gaussPiece(const Edge& a, const Edge& b, double s0, double s1, double logScale) {
    const double half = 0.5 * (s1 - s0), mid = 0.5 * (s0 + s1);
    double sum = 0.0;
    for (std::size_t k = 0; k < kNodes.size(); ++k)
        sum += kWeights[k] * (lineLogIntegral(a.start + (mid - half * kNodes[k]) * a.direction, b, logScale) +
                              lineLogIntegral(a.start + (mid + half * kNodes[k]) * a.direction, b, logScale));
    return half * sum;
}

/// The piece [s0, s1] of edge a, graded towards an end whose nearest singularity lies closer than
/// the piece's length (near0, near1: that distance at each end).
double gradedPiece(const Edge& a, const Edge& b, double s0, double s1, double near0, double near1, double logScale) {
    const double length = s1 - s0;
    if (!(length > 0.0)) return 0.0;
    const bool close0 = near0 < length, close1 = near1 < length;
    if (!close0 && !close1) return gaussPiece(a, b, s0, s1, logScale);
    if (close0 && close1) {
        const double mid = 0.5 * (s0 + s1);
        return gradedPiece(a, b, s0, mid, near0, length, logScale) + gradedPiece(a, b, mid, s1, length, near1, logScale);
    }
    // Towards the close end c: pieces [c + g^(k+1) L, c + g^k L] outwards, the innermost [c, c + g^K L].
    const double stop = std::max(close0 ? near0 : near1, kInnermost * a.length);
    double sum = 0.0, outer = length;
    while (outer * kGrading > stop) {
        const double inner = outer * kGrading;
        sum += close0 ? gaussPiece(a, b, s0 + inner, s0 + outer, logScale) : gaussPiece(a, b, s1 - outer, s1 - inner, logScale);
        outer = inner;
    }
    return sum + (close0 ? gaussPiece(a, b, s0, s0 + outer, logScale) : gaussPiece(a, b, s1 - outer, s1, logScale));
}

/// int_a int_b ln(|x - y| / scale) dt ds. The inner integral is analytic in s but near where x(s)
/// comes close to an end of b (branch points at s = the end's projection +- i its distance from
/// line a) and, when the lines pass each other within b, near their closest approach (a kink
/// where they cross). Those points cut edge a into pieces graded towards them.
double edgePairIntegral(const Edge& a, const Edge& b, double logScale) {
    struct Singularity {
        double s, distance;
    };
    std::array<Singularity, 3> singular;
    std::size_t count = 0;
    for (const Vec3& end : {b.start, Vec3(b.start + b.length * b.direction)}) {
        const Vec3 w = end - a.start;
        const double s = w.dot(a.direction);
        singular[count++] = {s, (w - s * a.direction).norm()};
    }
    // Closest approach of the two lines, when it lies inside b.
    const Vec3 cross = a.direction.cross(b.direction);
    const double sin2 = cross.squaredNorm();
    if (sin2 > 1e-12) {
        const Vec3 w = b.start - a.start;
        const double c = a.direction.dot(b.direction);
        const double wa = w.dot(a.direction), wb = w.dot(b.direction);
        const double s = (wa - c * wb) / sin2, t = (c * wa - wb) / sin2;
        if (t > 0.0 && t < b.length) singular[count++] = {s, std::abs(w.dot(cross)) / sin2};  // gap / sin
    }
    // Breakpoints: each singularity's foot on [0, L] with its distance from there.
    std::array<double, 5> cut;
    std::array<double, 5> near;
    std::size_t cuts = 0;
    cut[cuts] = 0.0;
    near[cuts++] = 2.0 * a.length;
    cut[cuts] = a.length;
    near[cuts++] = 2.0 * a.length;
    for (std::size_t k = 0; k < count; ++k) {
        const double foot = std::clamp(singular[k].s, 0.0, a.length);
        const double distance = std::hypot(singular[k].s - foot, singular[k].distance);
        cut[cuts] = foot;
        near[cuts++] = distance;
    }
    // Sort the cuts (at most 5) and merge coincident ones, keeping the smaller distance.
    for (std::size_t i = 1; i < cuts; ++i)
        for (std::size_t j = i; j > 0 && cut[j] < cut[j - 1]; --j) {
            std::swap(cut[j], cut[j - 1]);
            std::swap(near[j], near[j - 1]);
        }
    const double merge = 1e-12 * a.length;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < cuts; ++i) {
        if (kept > 0 && cut[i] - cut[kept - 1] <= merge) {
            near[kept - 1] = std::min(near[kept - 1], near[i]);
            continue;
        }
        cut[kept] = cut[i];
        near[kept++] = near[i];
    }
    double sum = 0.0;
    for (std::size_t i = 0; i + 1 < kept; ++i) sum += gradedPiece(a, b, cut[i], cut[i + 1], near[i], near[i + 1], logScale);
    return sum;
}

/// The part of p[0..count) with n . (y - origin) >= -tolerance into `out`; corners within the
/// tolerance of the plane count as on it (kept, no crossing made next to them).
void clipInFront(const Vec3& origin, const Vec3& n, const Vec3* p, std::size_t count, double tolerance,
                 std::vector<Vec3>& out) {
    out.clear();
    const auto height = [&](const Vec3& y) {
        const double h = n.dot(y - origin);
        return std::abs(h) <= tolerance ? 0.0 : h;
    };
    Vec3 a = p[count - 1];
    double ha = height(a);
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3& b = p[k];
        const double hb = height(b);
        if ((ha > 0.0 && hb < 0.0) || (ha < 0.0 && hb > 0.0)) out.push_back(a + (ha / (ha - hb)) * (b - a));
        if (hb >= 0.0) out.push_back(b);
        a = b;
        ha = hb;
    }
    if (out.size() < 3) out.clear();
}

double polygonSize(const Vec3* p, std::size_t count) {
    double size = 0.0;
    for (std::size_t k = 0; k < count; ++k) size = std::max(size, (p[(k + 1) % count] - p[k]).norm());
    return size;
}

double distanceToSegment(const Vec3& x, const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double length2 = d.squaredNorm();
    const double t = length2 > 0.0 ? std::clamp((x - a).dot(d) / length2, 0.0, 1.0) : 0.0;
    return (x - (a + t * d)).norm();
}

/// Whether x lies inside the convex polygon p (in its plane, normal n), within `tolerance` of it.
bool insidePolygon(const Vec3& x, const Vec3* p, std::size_t count, const Vec3& n, double tolerance) {
    if (std::abs(n.dot(x - p[0])) > tolerance) return false;
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3 edge = p[(k + 1) % count] - p[k];
        const double length = edge.norm();
        if (length > 0.0 && n.dot(edge.cross(x - p[k])) / length < -tolerance) return false;
    }
    return true;
}

}  // namespace

const char* contactName(PairContact contact) {
    switch (contact) {
    case PairContact::None: return "none";
    case PairContact::SharedCorner: return "shared corner";
    case PairContact::CornerOnEdge: return "corner on edge";
    case PairContact::CornerOnPatch: return "corner on patch";
    case PairContact::EdgeOverlap: return "overlapping edges";
    case PairContact::Coplanar: return "coplanar";
    }
    return "?";
}

PairContact classifyContact(const Vec3* a, std::size_t na, const Vec3& normalA, const Vec3* b, std::size_t nb,
                            const Vec3& normalB, double tolerance) {
    bool coplanar = normalA.cross(normalB).norm() <= 1e-9;
    for (std::size_t k = 0; k < nb && coplanar; ++k) coplanar = std::abs(normalA.dot(b[k] - a[0])) <= tolerance;
    if (coplanar) return PairContact::Coplanar;
    // Collinear edges sharing a segment longer than the tolerance.
    for (std::size_t i = 0; i < na; ++i) {
        const Vec3 &a0 = a[i], &a1 = a[(i + 1) % na];
        const Vec3 d = a1 - a0;
        const double length = d.norm();
        if (!(length > tolerance)) continue;
        const Vec3 u = d / length;
        for (std::size_t j = 0; j < nb; ++j) {
            const Vec3 &b0 = b[j], &b1 = b[(j + 1) % nb];
            const double t0 = (b0 - a0).dot(u), t1 = (b1 - a0).dot(u);
            if ((b0 - a0 - t0 * u).norm() > tolerance || (b1 - a0 - t1 * u).norm() > tolerance) continue;
            if (std::min(std::max(t0, t1), length) - std::max(std::min(t0, t1), 0.0) > tolerance)
                return PairContact::EdgeOverlap;
        }
    }
    const auto cornerOnEdge = [&](const Vec3* p, std::size_t np, const Vec3* q, std::size_t nq) {
        for (std::size_t i = 0; i < np; ++i)
            for (std::size_t j = 0; j < nq; ++j) {
                const Vec3 &q0 = q[j], &q1 = q[(j + 1) % nq];
                if ((p[i] - q0).norm() > tolerance && (p[i] - q1).norm() > tolerance &&
                    distanceToSegment(p[i], q0, q1) <= tolerance)
                    return true;
            }
        return false;
    };
    if (cornerOnEdge(a, na, b, nb) || cornerOnEdge(b, nb, a, na)) return PairContact::CornerOnEdge;
    bool shared = false;
    for (std::size_t i = 0; i < na; ++i)
        for (std::size_t j = 0; j < nb; ++j) shared = shared || (a[i] - b[j]).norm() <= tolerance;
    if (shared) return PairContact::SharedCorner;
    for (std::size_t i = 0; i < na; ++i)
        if (insidePolygon(a[i], b, nb, normalB, tolerance)) return PairContact::CornerOnPatch;
    for (std::size_t j = 0; j < nb; ++j)
        if (insidePolygon(b[j], a, na, normalA, tolerance)) return PairContact::CornerOnPatch;
    return PairContact::None;
}

double exchangeArea(const Vec3* e, std::size_t ne, const Vec3& normalE, const Vec3* r, std::size_t nr,
                    const Vec3& normalR, ExchangeAreaScratch& scratch) {
    const double size = std::max(polygonSize(e, ne), polygonSize(r, nr));
    if (!(size > 0.0)) return 0.0;
    const double tolerance = 1e-12 * size;
    // Coplanar pairs (either facing) exchange nothing; the contour integral would not say so.
    if (normalE.cross(normalR).norm() <= 1e-12) {
        bool inPlane = true;
        for (std::size_t k = 0; k < nr && inPlane; ++k) inPlane = std::abs(normalE.dot(r[k] - e[0])) <= tolerance;
        if (inPlane) return 0.0;
    }
    clipInFront(r[0], normalR, e, ne, tolerance, scratch.e);
    clipInFront(e[0], normalE, r, nr, tolerance, scratch.r);
    if (scratch.e.empty() || scratch.r.empty()) return 0.0;
    const auto edges = [](const std::vector<Vec3>& p, std::vector<ContourEdge>& out) {
        out.clear();
        for (std::size_t k = 0; k < p.size(); ++k) {
            const Vec3 d = p[(k + 1) % p.size()] - p[k];
            const double length = d.norm();
            if (length > 0.0) out.push_back({p[k], d / length, length});
        }
    };
    edges(scratch.e, scratch.edgesE);
    edges(scratch.r, scratch.edgesR);
    // ln(|x - y| / size): the constant integrates to zero around closed contours and keeps the
    // terms near the size of the result.
    const double logScale = std::log(size);
    double sum = 0.0;
    for (const ContourEdge& a : scratch.edgesE)
        for (const ContourEdge& b : scratch.edgesR) {
            const double c = a.direction.dot(b.direction);
            if (std::abs(c) <= 1e-14) continue;  // perpendicular edges: no term
            sum += c * edgePairIntegral(a, b, logScale);
        }
    // Both contours run counter-clockwise about their own normals (checked against C-11 and C-14).
    return std::max(0.0, sum / (2.0 * kPi));
}

}  // namespace hemirad
