// The direct sun on each patch: the sunlit fraction of its area, exact by shadow polygons (every
// patch, front or back, blocks the sun), and the direct irradiance DNI cos(theta) x that fraction.
#pragma once

#include "engine/math.hpp"
#include "engine/scene.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/shadow_polygons.hpp"

#include <Eigen/Core>

#include <vector>

namespace hemirad {

using Vec2 = Eigen::Vector2d;

/// A scene's patches as blockers of parallel beams, set up once (a bounding-volume tree over them,
/// connected coplanar tiles whose union is convex merged into one polygon: preprocess/hemisphere/
/// shadow_polygons.hpp) and asked for any number of directions (a year's suns, a sky's cells).
class BeamShadows {
public:
    /// Keeps a reference to `scene`, which must outlive this.
    explicit BeamShadows(const Scene& scene);

    /// Per patch, the fraction of its area that parallel rays from `toSun` reach: 0 where the patch
    /// faces away (n . toSun <= 0), else 1 less the union of the shadows that every other patch's
    /// part in front of its plane casts along the rays (convex patches; exact up to rounding; every
    /// patch, front or back, blocks). `toSun`: the direction from the scene to the sun (any length
    /// > 0). Patches run in parallel (OpenMP). Throws hemirad::Error for a direction that is zero or
    /// not finite.
    std::vector<double> sunlitFractions(const Vec3& toSun) const;

    const Scene& scene() const { return m_scene; }
    const PatchGeometry& geometry() const { return m_geometry; }
    /// The blockers (merged tiles).
    const ShadowPolygons& blockers() const { return m_shadows; }
    /// Every patch on its own (owner() its id), for finding the receivers of a beam: set up only for
    /// a scene with mirrors.
    const ShadowPolygons& patches() const { return m_patches; }
    /// What lies this close in front of a receiver's plane casts nothing (1e-9 x the scene's size).
    double tolerance() const { return m_tolerance; }

private:
    const Scene& m_scene;
    PatchGeometry m_geometry;
    ShadowPolygons m_shadows, m_patches;
    double m_tolerance = 0.0;
};

/// BeamShadows(scene).sunlitFractions(toSun): one direction (several: keep a BeamShadows).
std::vector<double> sunlitFractions(const Scene& scene, const Vec3& toSun);

/// Direct irradiance per patch, W/m^2: dni (direct-normal irradiance) x cos(theta) x sunlit fraction.
std::vector<double> directIrradiance(const Scene& scene, const Vec3& toSun, double dni, const std::vector<double>& sunlit);

/// The area of the convex polygon p (2D, counter-clockwise or not: the absolute area).
double polygonArea2d(const std::vector<Vec2>& p);

/// The parts of the convex pieces outside the convex polygon `shadow` (2D), as convex pieces; a part
/// of area `minArea` or less is dropped (0: only those of no area).
std::vector<std::vector<Vec2>> subtractConvex(const std::vector<std::vector<Vec2>>& pieces, std::vector<Vec2> shadow,
                                              double minArea = 0.0);

}  // namespace hemirad
