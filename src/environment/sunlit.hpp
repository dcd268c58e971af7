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

private:
    const Scene& m_scene;
    PatchGeometry m_geometry;
    ShadowPolygons m_shadows;
    double m_tolerance = 0.0;  ///< what lies this close in front of a receiver's plane casts nothing
};

/// BeamShadows(scene).sunlitFractions(toSun): one direction (several: keep a BeamShadows).
std::vector<double> sunlitFractions(const Scene& scene, const Vec3& toSun);

/// Direct irradiance per patch, W/m^2: dni (direct-normal irradiance) x cos(theta) x sunlit fraction.
std::vector<double> directIrradiance(const Scene& scene, const Vec3& toSun, double dni, const std::vector<double>& sunlit);

/// Per patch, the patches whose bounding boxes overlap it as a parallel beam along `direction`
/// sees them (the candidates to shadow it in that beam; engine/box_grid.hpp).
std::vector<std::vector<PatchId>> beamCandidates(const Scene& scene, const Vec3& direction);

/// A plane n . y = offset (n unit).
struct Plane {
    Vec3 normal;
    double offset = 0.0;
};

/// Points in a plane's 2D coordinates: ((c - origin) . u, (c - origin) . v).
std::vector<Vec2> planeCoordinates(const std::vector<Vec3>& points, const Vec3& origin, const Vec3& u, const Vec3& v);

/// The part of `pieces` (convex, 2D in the plane through `origin` with unit `normal` and axes u, v)
/// that a parallel beam from direction `toSource` (unit, normal . toSource > 0) reaches past the
/// `blockers` (patch ids; `self` skipped): each blocker's part in front of the plane (and in front
/// of `slab` when given: n . y >= offset) projected along the beam and subtracted; a blocker whose
/// corners all lie within `tolerance` of the plane or behind it casts nothing.
std::vector<std::vector<Vec2>> shadowedPieces(const Scene& scene, std::vector<std::vector<Vec2>> pieces, const Vec3& origin,
                                              const Vec3& normal, const Vec3& u, const Vec3& v, const Vec3& toSource,
                                              const std::vector<PatchId>& blockers, PatchId self, const Plane* slab,
                                              double tolerance);

/// Patch i's sunlit part as convex pieces in its plane's coordinates (origin its corner 0, axes u,
/// v): shadowedPieces of the whole patch. The pieces sunlitFractions sums.
std::vector<std::vector<Vec2>> sunlitPieces(const Scene& scene, PatchId i, const Vec3& toSun, const std::vector<PatchId>& blockers,
                                            const Vec3& u, const Vec3& v, double tolerance);

/// The area of the convex polygon p (2D, counter-clockwise or not: the absolute area).
double polygonArea2d(const std::vector<Vec2>& p);

/// The parts of the convex pieces outside the convex polygon `shadow` (2D), as convex pieces; a part
/// of area `minArea` or less is dropped (0: only those of no area).
std::vector<std::vector<Vec2>> subtractConvex(const std::vector<std::vector<Vec2>>& pieces, std::vector<Vec2> shadow,
                                              double minArea = 0.0);

}  // namespace hemirad
