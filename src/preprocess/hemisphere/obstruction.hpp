// Which patches can hide part of one patch from another: where none can (a convex room), the
// analytic estimator needs no shadow rays at all, and only these patches cast shadow polygons.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hemirad {

class Scene;

/// A patch can only obstruct a view between two patches if some of the scene lies strictly on
/// each side of its plane: a segment between two points in one closed half-space never crosses
/// the plane's interior. Returns, per patch, 1 where the scene's corners lie on both sides of its
/// plane (beyond 1e-9 of the scene's size), else 0: no patch of a convex enclosure or an open
/// convex surface can obstruct. Patches are grouped by plane, and a plane with the scene's bounding
/// box on one side needs no scan, so a subdivided room costs little; above `budget` corner tests
/// it gives up and flags the remaining planes' patches (visibility stays on). Threads: OpenMP.
std::vector<std::uint8_t> obstructingPatches(const Scene& scene, double budget = 5e8);

/// Whether some patch can obstruct (obstructingPatches flags one).
bool somePatchCanObstruct(const Scene& scene, double budget = 5e8);

}  // namespace hemirad
