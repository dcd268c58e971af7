// The direct sun on each patch: the sunlit fraction of its area, exact by shadow polygons (every
// patch, front or back, blocks the sun), and the direct irradiance DNI cos(theta) x that fraction.
#pragma once

#include "engine/math.hpp"
#include "engine/scene.hpp"

#include <Eigen/Core>

#include <vector>

namespace hemirad {

using Vec2 = Eigen::Vector2d;

/// Per patch, the fraction of its area that the sun's parallel rays reach: 0 where the patch faces
/// away (n . toSun <= 0), else 1 less the union of the shadows that every other patch's part in
/// front of its plane casts along the rays (convex patches; exact up to rounding). `toSun`: the
/// direction from the scene to the sun (any length > 0). Candidate blockers come from the patches'
/// boxes overlapping as the sun sees them (engine/box_grid.hpp); patches run in parallel (OpenMP).
/// Throws hemirad::Error for a direction that is zero or not finite.
std::vector<double> sunlitFractions(const Scene& scene, const Vec3& toSun);

/// Direct irradiance per patch, W/m^2: dni (direct-normal irradiance) x cos(theta) x sunlit fraction.
std::vector<double> directIrradiance(const Scene& scene, const Vec3& toSun, double dni, const std::vector<double>& sunlit);

/// The area of the convex polygon p (2D, counter-clockwise or not: the absolute area).
double polygonArea2d(const std::vector<Vec2>& p);

/// The parts of the convex pieces outside the convex polygon `shadow` (2D), as convex pieces.
std::vector<std::vector<Vec2>> subtractConvex(const std::vector<std::vector<Vec2>>& pieces, std::vector<Vec2> shadow);

}  // namespace hemirad
