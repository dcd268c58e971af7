// Polygon measures (Newell's method for the normal, fan triangulation for area and centroid).
#include "engine/polygon.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

PolygonMeasures measurePolygon(const std::vector<Vec3>& p) {
    PolygonMeasures m;
    const std::size_t n = p.size();
    Vec3 newell = Vec3::Zero();
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3& a = p[k];
        const Vec3& b = p[(k + 1) % n];
        newell += Vec3((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                       (a.x() - b.x()) * (a.y() + b.y()));
        m.maxEdge = std::max(m.maxEdge, (b - a).norm());
    }
    Vec3 weighted = Vec3::Zero();
    for (std::size_t k = 1; k + 1 < n; ++k) {
        const double area = 0.5 * (p[k] - p[0]).cross(p[k + 1] - p[0]).norm();
        m.area += area;
        weighted += area * (p[0] + p[k] + p[k + 1]) / 3.0;
    }
    const double len = newell.norm();
    // Degenerate: zero area, or a Newell normal too small to trust relative to the polygon's size.
    if (!(m.area > 0.0) || !(len > 1e-12 * m.maxEdge * m.maxEdge)) {
        m.area = 0.0;
        return m;
    }
    m.normal = newell / len;
    m.centroid = weighted / m.area;
    for (const Vec3& q : p)
        m.planarDeviation = std::max(m.planarDeviation, std::abs((q - m.centroid).dot(m.normal)));
    for (std::size_t k = 0; k < n && m.convex; ++k) {
        const Vec3 e0 = p[(k + 1) % n] - p[k];
        const Vec3 e1 = p[(k + 2) % n] - p[(k + 1) % n];
        // A reflex corner turns clockwise about the normal; collinear corners are allowed.
        if (e0.cross(e1).dot(m.normal) < -1e-9 * e0.norm() * e1.norm()) m.convex = false;
    }
    return m;
}

}  // namespace hemirad
