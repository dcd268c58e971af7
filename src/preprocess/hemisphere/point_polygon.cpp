// Lambert's contour integral, half-space clipping and area-uniform points on polygons.
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

namespace {

/// Cephes' atan (S. Moshier): atan(x) = x + x z P(z) / Q(z), z = x^2, for |x| <= tan(pi/8) (a
/// rational of degree 4/5, within 2 ulp); p and q are P(z) and Q(z).
inline void atanRational(double z, double& p, double& q) {
    constexpr double P0 = -8.750608600031904122785e-1, P1 = -1.615753718733365076637e1,
                     P2 = -7.500855792314704667340e1, P3 = -1.228866684490136173410e2,
                     P4 = -6.485021904942025371773e1;
    constexpr double Q0 = 2.485846490142306297962e1, Q1 = 1.650270098316988542046e2, Q2 = 4.328810604912902668951e2,
                     Q3 = 4.853903996359136964868e2, Q4 = 1.945506571482613964425e2;
    p = (((P0 * z + P1) * z + P2) * z + P3) * z + P4;
    q = ((((z + Q0) * z + Q1) * z + Q2) * z + Q3) * z + Q4;
}

/// tan(pi/8)^2: below it atanRational needs no reduction.
constexpr double kTanEighthPiSquared = 0.17157287525380990239;

/// atan2(s, c) for s > 0: the angle between two vectors from |a x b| and a . b, within 2.2 ulp of
/// the exact angle (glibc's atan2: 0.5 ulp) at 60 % of its time, most of which glibc spends keeping
/// the caller's rounding mode. The argument min/max(s, |c|) in [0, 1], reduced above tan(pi/8) by
/// atan(t) = pi/4 + atan((t - 1)/(t + 1)); the constants pi/4, pi/2 and pi carried in two parts, so
/// that the sums keep the small angle's digits.
inline double edgeAngle(double s, double c) {
    constexpr double kQuarterPi = 0.78539816339744830962, kQuarterPiLow = 3.061616997868382943065e-17;
    constexpr double kHalfPi = 1.57079632679489661923, kHalfPiLow = 6.123233995736765886130e-17;
    constexpr double kPiLow = 1.224646799147353177226e-16;
    const double ac = std::abs(c);
    const bool steep = s > ac;
    const double t = steep ? ac / s : s / ac;
    const bool high = t > 0.41421356237309504880;
    const double x = high ? (t - 1.0) / (t + 1.0) : t;
    double p, q;
    atanRational(x * x, p, q);
    const double r = x * (x * x) * p / q;  // atan(x) - x
    double angle = high ? kQuarterPi + (x + (r + kQuarterPiLow)) : x + r;
    if (steep) angle = kHalfPi - (angle - kHalfPiLow);
    return c < 0.0 ? kPi - (angle - kPiLow) : angle;
}

}  // namespace

double pointToPolygonFactor(const Vec3& x, const Vec3& n, const Vec3* p, std::size_t count) {
    double sum = 0.0;
    Vec3 a = p[count - 1] - x;
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3 b = p[k] - x;
        const Vec3 c = a.cross(b);
        const double s2 = c.squaredNorm(), d = a.dot(b);
        if (d > 0.0 && s2 <= kTanEighthPiSquared * (d * d)) {
            // An angle below pi/8 (every edge of a polygon seen from afar): gamma / |c| =
            // atan(t) / (t d) with t = |c| / d, that is (1 + z P / Q) / d with z = t^2: no root.
            if (s2 > 0.0) {
                double p, q;
                const double z = s2 / (d * d);
                atanRational(z, p, q);
                sum += n.dot(c) * (q + z * p) / (d * q);
            }
        } else {
            // atan2 keeps the angle accurate for nearly parallel edges where acos loses digits.
            const double s = std::sqrt(s2);
            if (s > 0.0) sum += edgeAngle(s, d) * n.dot(c) / s;
        }
        a = b;
    }
    return std::abs(sum) / (2.0 * kPi);
}

Vec3 vertexMean(const Vec3* p, std::size_t count) {
    Vec3 sum = Vec3::Zero();
    for (std::size_t k = 0; k < count; ++k) sum += p[k];
    return sum / double(count);
}

void clipAbovePlane(const Vec3& x, const Vec3& n, const Vec3* p, std::size_t count, std::vector<Vec3>& out) {
    out.clear();
    Vec3 a = p[count - 1];
    double ha = n.dot(a - x);
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3& b = p[k];
        const double hb = n.dot(b - x);
        // Only a strict sign change crosses the plane: a corner on it is kept once, not twice.
        if ((ha > 0.0 && hb < 0.0) || (ha < 0.0 && hb > 0.0)) out.push_back(a + (ha / (ha - hb)) * (b - a));
        if (hb >= 0.0) out.push_back(b);
        a = b;
        ha = hb;
    }
    if (out.size() < 3) out.clear();
}

Vec3 pointOnPolygon(const Vec3* p, std::size_t count, double u, double v) {
    if (count == 4 && (p[0] + p[2] - p[1] - p[3]).norm() <= 1e-9 * (p[2] - p[0]).norm())
        return p[0] + u * (p[1] - p[0]) + v * (p[3] - p[0]);
    double total = 0.0;
    for (std::size_t k = 1; k + 1 < count; ++k) total += (p[k] - p[0]).cross(p[k + 1] - p[0]).norm();
    // u picks the fan triangle (0, t, t + 1) by area and is rescaled to [0, 1) within it.
    double low = 0.0;
    std::size_t t = 1;
    for (; t + 2 < count; ++t) {
        const double high = low + (p[t] - p[0]).cross(p[t + 1] - p[0]).norm() / total;
        if (u < high) break;
        low = high;
    }
    const double width = (p[t] - p[0]).cross(p[t + 1] - p[0]).norm() / total;
    u = width > 0.0 ? std::min((u - low) / width, 1.0) : 0.0;
    if (u + v > 1.0) {  // fold the unit square onto the triangle
        u = 1.0 - u;
        v = 1.0 - v;
    }
    return p[0] + u * (p[t] - p[0]) + v * (p[t + 1] - p[0]);
}

void splitPolygon(const Vec3* p, std::size_t count, std::vector<Vec3>& out) {
    const Vec3 centre = vertexMean(p, count);
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3& previous = p[(k + count - 1) % count];
        const Vec3& next = p[(k + 1) % count];
        out.push_back(p[k]);
        out.push_back(0.5 * (p[k] + next));
        out.push_back(centre);
        out.push_back(0.5 * (previous + p[k]));
    }
}

void polygonQuadrature(const Vec3* p, std::size_t count, const std::vector<double>& nodes,
                       const std::vector<double>& weights, std::vector<Vec3>& points, std::vector<double>& pointWeights) {
    const std::size_t first = pointWeights.size();
    double total = 0.0;
    if (count == 4) {
        for (std::size_t a = 0; a < nodes.size(); ++a)
            for (std::size_t b = 0; b < nodes.size(); ++b) {
                const double u = nodes[a], v = nodes[b];
                const Vec3 du = (1 - v) * (p[1] - p[0]) + v * (p[2] - p[3]);
                const Vec3 dv = (1 - u) * (p[3] - p[0]) + u * (p[2] - p[1]);
                points.push_back((1 - u) * (1 - v) * p[0] + u * (1 - v) * p[1] + u * v * p[2] + (1 - u) * v * p[3]);
                pointWeights.push_back(weights[a] * weights[b] * du.cross(dv).norm());
                total += pointWeights.back();
            }
    } else {
        for (std::size_t t = 1; t + 1 < count; ++t) {
            const double area = (p[t] - p[0]).cross(p[t + 1] - p[0]).norm();
            for (std::size_t a = 0; a < nodes.size(); ++a)
                for (std::size_t b = 0; b < nodes.size(); ++b) {
                    const double u = nodes[a], v = nodes[b];
                    points.push_back(p[0] + u * (p[t] - p[0]) + u * v * (p[t + 1] - p[t]));
                    pointWeights.push_back(weights[a] * weights[b] * u * area);
                    total += pointWeights.back();
                }
        }
    }
    if (!(total > 0.0)) {  // a degenerate polygon: its vertex centroid carries everything
        points.resize(first);
        pointWeights.resize(first);
        points.push_back(vertexMean(p, count));
        pointWeights.push_back(1.0);
        return;
    }
    for (std::size_t k = first; k < pointWeights.size(); ++k) pointWeights[k] /= total;
}

void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    nodes.assign(n, 0.0);
    weights.assign(n, 0.0);
    for (int k = 0; k < n; ++k) {
        double x = std::cos(kPi * (k + 0.75) / (n + 0.5)), dp = 1.0;  // Tricomi's initial guess
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1.0, p1 = x;  // P_n(x) by the three-term recurrence
            for (int m = 2; m <= n; ++m) {
                const double p2 = ((2 * m - 1) * x * p1 - (m - 1) * p0) / m;
                p0 = p1;
                p1 = p2;
            }
            if (n == 1) p0 = 1.0;
            dp = n * (x * p1 - p0) / (x * x - 1.0);
            const double step = p1 / dp;
            x -= step;
            if (std::abs(step) < 1e-15) break;
        }
        nodes[k] = 0.5 * (1.0 - x);
        weights[k] = 1.0 / ((1.0 - x * x) * dp * dp);  // 2 / ((1 - x^2) P'^2), halved for [0, 1]
    }
}

}  // namespace hemirad
