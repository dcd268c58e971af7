// Lambert's point-to-polygon factor, half-space clipping and area-uniform polygon points.
#include "preprocess/hemisphere/point_polygon.hpp"
#include "support.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// Brute-force cos cos / (pi r^2) over the part of rectangle x = X, y in [y0, y1], z in [z0, z1]
/// above the element at the origin with normal +z (midpoint rule), the independent check of clipping.
double perpendicularByQuadrature(double X, double y0, double y1, double z0, double z1) {
    const int n = 1200;
    double sum = 0.0;
    const double dy = (y1 - y0) / n, dz = (z1 - z0) / n;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            const double y = y0 + (a + 0.5) * dy, z = z0 + (b + 0.5) * dz;
            if (z <= 0) continue;
            const double r2 = X * X + y * y + z * z;
            sum += (z / std::sqrt(r2)) * (X / std::sqrt(r2)) / (kPi * r2) * dy * dz;
        }
    return sum;
}

/// Lambert's formula in long double with the C library's atan2l: the reference for the angles
/// pointToPolygonFactor computes its own way; `scale` the sum of its terms' sizes (far from the
/// polygon they nearly cancel, and double rounding is relative to them, not to the factor).
double lambertLongDouble(const Vec3& x, const Vec3& n, const std::vector<Vec3>& p, double& scale) {
    long double sum = 0.0L, size = 0.0L;
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec3& from = p[(k + p.size() - 1) % p.size()];
        long double a[3], b[3];
        for (int i = 0; i < 3; ++i) {
            a[i] = (long double)from[i] - (long double)x[i];
            b[i] = (long double)p[k][i] - (long double)x[i];
        }
        const long double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        const long double s = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (!(s > 0.0L)) continue;
        const long double term =
            std::atan2(s, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * (n[0] * c[0] + n[1] * c[1] + n[2] * c[2]) / s;
        sum += term;
        size += std::fabs(term);
    }
    const long double twoPi = 2.0L * 3.14159265358979323846264338327950288L;
    scale = double(size / twoPi);
    return double(std::fabs(sum) / twoPi);
}

}  // namespace

TEST_CASE("Lambert's edge angles keep their digits from nearly 0 to nearly pi, in every octant of the edge") {
    // A triangle and a quad seen from afar (every angle tiny), from a point just above their plane
    // (angles near pi for the edges it lies close to), and from points around them: the factor
    // within 1e-14 of the formula in long double with the C library's atan2l, relative to the
    // terms' sizes (the sum cancels far away, as it does with any atan2).
    const std::vector<std::vector<Vec3>> polygons = {
        {{0, 0, 0}, {1, 0, 0}, {0.2, 0.9, 0}},
        {{-1, -0.5, 0}, {1.5, -0.5, 0}, {1.2, 0.7, 0}, {-0.8, 0.6, 0}},
    };
    const std::vector<Vec3> points = {{0.3, 0.2, 1e-6}, {0.3, 0.2, 1e-3}, {0.3, 0.2, 0.5}, {0.5, 1e-7, 1e-7},
                                      {3, 2, 1},        {-2, -3, 0.3},    {0.1, 0.1, 2e3}, {30, -20, 50}};
    const std::vector<Vec3> normals = {{0, 0, -1}, Vec3(1, 0, -1).normalized(), Vec3(0.3, -0.4, -0.8).normalized()};
    int compared = 0;
    for (const auto& polygon : polygons)
        for (const Vec3& x : points)
            for (const Vec3& normal : normals) {
                double scale = 0.0;
                const double reference = lambertLongDouble(x, normal, polygon, scale);
                if (!(reference > 0.0)) continue;
                CAPTURE(x.transpose());
                CAPTURE(normal.transpose());
                CHECK(std::abs(pointToPolygonFactor(x, normal, polygon.data(), polygon.size()) - reference) <=
                      1e-14 * scale);
                ++compared;
            }
    CHECK(compared >= 30);
}

TEST_CASE("Point to rectangle: Howell B-3 with the normal through a corner, both windings") {
    const Vec3 x(0, 0, 0), n(0, 0, 1);
    const std::vector<Vec3> ccw = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const std::vector<Vec3> cw(ccw.rbegin(), ccw.rend());
    CHECK(b3(1, 1, 1) == relative(0.138532, 1e-5));
    CHECK(pointToPolygonFactor(x, n, ccw.data(), 4) == relative(b3(1, 1, 1), 1e-12));
    CHECK(pointToPolygonFactor(x, n, cw.data(), 4) == relative(b3(1, 1, 1), 1e-12));
    const std::vector<Vec3> wide = {{0, 0, 0.5}, {3, 0, 0.5}, {3, 2, 0.5}, {0, 2, 0.5}};
    CHECK(pointToPolygonFactor(x, n, wide.data(), 4) == relative(b3(3, 2, 0.5), 1e-12));
}

TEST_CASE("Point to a regular polygon on the axis approaches the disk's R^2 / (R^2 + H^2)") {
    const double R = 0.7, H = 1.3;
    std::vector<Vec3> disk;
    for (int k = 0; k < 4096; ++k)
        disk.emplace_back(R * std::cos(2 * kPi * k / 4096), R * std::sin(2 * kPi * k / 4096), H);
    CHECK(pointToPolygonFactor(Vec3::Zero(), Vec3(0, 0, 1), disk.data(), disk.size()) ==
          relative(R * R / (R * R + H * H), 1e-6));
}

TEST_CASE("A polygon straddling the tangent plane counts only its part above it") {
    const Vec3 x(0, 0, 0), n(0, 0, 1);
    const std::vector<Vec3> wall = {{1, -1, -0.5}, {1, 1, -0.5}, {1, 1, 1}, {1, -1, 1}};
    std::vector<Vec3> clipped;
    clipAbovePlane(x, n, wall.data(), wall.size(), clipped);
    REQUIRE(clipped.size() == 4);
    for (const Vec3& p : clipped) CHECK(p.z() >= 0.0);
    CHECK(pointToPolygonFactor(x, n, clipped.data(), clipped.size()) ==
          relative(perpendicularByQuadrature(1, -1, 1, -0.5, 1), 1e-5));
    // Entirely below: nothing; a triangle with one corner above keeps a triangle.
    const std::vector<Vec3> below = {{1, 0, -1}, {1, 1, -1}, {1, 1, -0.1}};
    clipAbovePlane(x, n, below.data(), below.size(), clipped);
    CHECK(clipped.empty());
    const std::vector<Vec3> tip = {{1, 0, -1}, {1, 1, -1}, {1, 0.5, 1}};
    clipAbovePlane(x, n, tip.data(), tip.size(), clipped);
    CHECK(clipped.size() == 3);
}

TEST_CASE("Points on polygons are area-uniform: the mean of a grid of (u, v) is the centroid") {
    const std::vector<Vec3> parallelogram = {{0, 0, 0}, {2, 0, 0}, {3, 1, 0}, {1, 1, 0}};
    const std::vector<Vec3> pentagon = {{0, 0, 0}, {4, 0, 0}, {5, 2, 0}, {2, 4, 0}, {-1, 2, 0}};
    for (const auto* polygon : {&parallelogram, &pentagon}) {
        // Area centroid by the fan triangles.
        Vec3 centroid = Vec3::Zero();
        double area = 0.0;
        const auto& p = *polygon;
        for (std::size_t k = 1; k + 1 < p.size(); ++k) {
            const double a = 0.5 * (p[k] - p[0]).cross(p[k + 1] - p[0]).norm();
            centroid += a * (p[0] + p[k] + p[k + 1]) / 3.0;
            area += a;
        }
        centroid /= area;
        Vec3 mean = Vec3::Zero();
        const int n = 400;
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b) mean += pointOnPolygon(p.data(), p.size(), (a + 0.5) / n, (b + 0.5) / n);
        mean /= double(n) * n;
        CHECK((mean - centroid).norm() < 1e-2);
    }
}

TEST_CASE("Gauss-Legendre of order n integrates degree 2n - 1 exactly on [0, 1]") {
    for (int n : {1, 2, 6, 12}) {
        std::vector<double> nodes, weights;
        gaussLegendre(n, nodes, weights);
        for (int degree = 0; degree <= 2 * n - 1; ++degree) {
            double sum = 0.0;
            for (int k = 0; k < n; ++k) sum += weights[k] * std::pow(nodes[k], degree);
            CHECK(sum == relative(1.0 / (degree + 1), 1e-12));
        }
    }
}

TEST_CASE("Polygon quadrature reproduces area moments on a skewed quad, a triangle and a pentagon") {
    std::vector<double> nodes, weights;
    gaussLegendre(4, nodes, weights);
    const std::vector<Vec3> quad = {{0, 0, 0}, {3, 0.2, 0}, {2.5, 2, 0}, {-0.3, 1.4, 0}};
    const std::vector<Vec3> triangle = {{0, 0, 0}, {2, 0, 0}, {0.5, 1.5, 0}};
    const std::vector<Vec3> pentagon = {{0, 0, 0}, {4, 0, 0}, {5, 2, 0}, {2, 4, 0}, {-1, 2, 0}};
    for (const auto* polygon : {&quad, &triangle, &pentagon}) {
        const auto& p = *polygon;
        // Exact moments by fan triangles: centroid and the mean of x^2 (degree 2, within the rule's reach).
        double area = 0.0, meanX = 0.0, meanX2 = 0.0;
        for (std::size_t k = 1; k + 1 < p.size(); ++k) {
            const Vec3 &a = p[0], &b = p[k], &c = p[k + 1];
            const double t = 0.5 * (b - a).cross(c - a).norm();
            area += t;
            meanX += t * (a.x() + b.x() + c.x()) / 3.0;
            meanX2 += t * (a.x() * a.x() + b.x() * b.x() + c.x() * c.x() + a.x() * b.x() + b.x() * c.x() + a.x() * c.x()) / 6.0;
        }
        std::vector<Vec3> points;
        std::vector<double> w;
        polygonQuadrature(p.data(), p.size(), nodes, weights, points, w);
        double sum = 0.0, x = 0.0, x2 = 0.0;
        for (std::size_t q = 0; q < points.size(); ++q) {
            sum += w[q];
            x += w[q] * points[q].x();
            x2 += w[q] * points[q].x() * points[q].x();
        }
        CHECK(sum == relative(1.0, 1e-12));
        CHECK(x == relative(meanX / area, 1e-12));
        CHECK(x2 == relative(meanX2 / area, 1e-12));
    }
    // A degenerate polygon falls back to its vertex centroid instead of dividing by zero.
    const std::vector<Vec3> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    std::vector<Vec3> points;
    std::vector<double> w;
    polygonQuadrature(line.data(), line.size(), nodes, weights, points, w);
    REQUIRE(points.size() == 1);
    CHECK(w[0] == 1.0);
    CHECK(points[0].x() == doctest::Approx(1.0));
}

TEST_CASE("Split pieces' factors add up to the polygon's, once and twice split") {
    const Vec3 x(0.1, -0.2, 0), n(0, 0, 1);
    // A tilted planar pentagon, z = 1 + 0.25 x + 0.1 y.
    const std::vector<Vec3> pentagon = {{0, 0, 1}, {2, 0, 1.5}, {2.5, 1, 1.725}, {1, 2, 1.45}, {-0.5, 1, 0.975}};
    const double whole = pointToPolygonFactor(x, n, pentagon.data(), pentagon.size());
    std::vector<Vec3> once, twice;
    splitPolygon(pentagon.data(), pentagon.size(), once);
    REQUIRE(once.size() == 4 * pentagon.size());
    for (std::size_t q = 0; q < once.size(); q += 4) splitPolygon(&once[q], 4, twice);
    for (const auto* pieces : {&once, &twice}) {
        double sum = 0.0;
        for (std::size_t q = 0; q < pieces->size(); q += 4) sum += pointToPolygonFactor(x, n, &(*pieces)[q], 4);
        CHECK(sum == relative(whole, 1e-12));
    }
}
