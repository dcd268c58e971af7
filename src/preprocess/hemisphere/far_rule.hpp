// The far-field form factor of a pair of patches: the point-to-point kernel cos cos' / (pi r^2)
// integrated by a 2 x 2 Gauss-Legendre rule on each patch (16 kernel terms, no trigonometry).
#pragma once

#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace hemirad {

/// Where the kernel is good enough: both patches well in front of each other. Its relative error
/// behaves like C rho^-4 with rho = min(distance, height of each centroid above the other's plane)
/// / the larger radius (a pair near one's horizon varies fast across the other): measured on
/// squares, rectangles and triangles against squares in random orientations (rho = 3..20; beyond,
/// Lambert's formula itself is no better than 1e-7) C stays below 2.
class FarRule {
public:
    static constexpr double kErrorConstant = 2.0;

    /// The 2 x 2 rule's points and weights on every patch (polygonQuadrature's map).
    void build(const PatchGeometry& geometry) {
        std::vector<double> nodes, weights;
        gaussLegendre(2, nodes, weights);
        m_start.assign(1, 0);
        m_points.clear();
        m_weights.clear();
        for (PatchId j = 0; j < geometry.shapes.size(); ++j) {
            polygonQuadrature(geometry.polygon(j), geometry.shapes[j].count, nodes, weights, m_points, m_weights);
            m_start.push_back(static_cast<std::uint32_t>(m_points.size()));
        }
    }

    /// The pair's rho (see above); below 0 when one lies behind the other's plane.
    static double ratio(const PatchShape& e, const PatchShape& r) {
        const Vec3 v = r.centroid - e.centroid;
        return std::min({v.norm(), e.normal.dot(v), -r.normal.dot(v)}) / std::max(e.radius, r.radius);
    }

    /// F from e to r (unoccluded) = A_r sum_pq w_p w_q (n_e . v)(-n_r . v) / (pi |v|^4), v = y_q - x_p.
    double factor(const PatchGeometry& geometry, PatchId e, PatchId r, double receiverArea) const {
        const Vec3& ne = geometry.shapes[e].normal;
        const Vec3& nr = geometry.shapes[r].normal;
        double sum = 0.0;
        for (std::uint32_t p = m_start[e]; p < m_start[e + 1]; ++p) {
            double inner = 0.0;
            for (std::uint32_t q = m_start[r]; q < m_start[r + 1]; ++q) {
                const Vec3 v = m_points[q] - m_points[p];
                const double d2 = v.squaredNorm();
                inner += m_weights[q] * std::max(0.0, ne.dot(v)) * std::max(0.0, -nr.dot(v)) / (d2 * d2);
            }
            sum += m_weights[p] * inner;
        }
        return receiverArea * sum / kPi;
    }

private:
    std::vector<std::uint32_t> m_start;
    std::vector<Vec3> m_points;
    std::vector<double> m_weights;
};

}  // namespace hemirad
