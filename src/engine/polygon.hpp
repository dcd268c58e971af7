// Planar-polygon measures of a patch: fan-triangle area, Newell normal, centroid, planarity and convexity.
#pragma once

#include "engine/math.hpp"

#include <vector>

namespace hemirad {

struct PolygonMeasures {
    double area = 0.0;          ///< sum of the fan triangles' areas (what rays and rasterisers see)
    Vec3 normal = Vec3::Zero(); ///< unit Newell normal; zero when the polygon is degenerate
    Vec3 centroid = Vec3::Zero();
    double planarDeviation = 0.0;  ///< largest distance of a corner from the plane (centroid, normal)
    double maxEdge = 0.0;
    bool convex = true;         ///< no reflex corner when projected on the Newell plane
};

/// Measures the polygon p[0..n-1] (n >= 3, counter-clockwise seen from the normal's side).
PolygonMeasures measurePolygon(const std::vector<Vec3>& p);

}  // namespace hemirad
