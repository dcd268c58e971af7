// Whether any patch can hide part of one patch from another: where none can (a convex room), the
// analytic estimator needs no shadow rays at all.
#pragma once

#include <cstddef>

namespace hemirad {

class Scene;

/// A patch can only obstruct a view between two patches if some of the scene lies strictly behind
/// its plane: a segment between two points in the closed half-space in front of it never crosses
/// it. Returns false when every patch's plane has every patch corner in front (within 1e-9 of the
/// scene's size): a convex enclosure or an open convex surface. Patches are grouped by plane, so a
/// subdivided room costs (its planes) x (its vertices); above `budget` such tests it gives up and
/// answers true (visibility stays on). Threads: OpenMP.
bool somePatchCanObstruct(const Scene& scene, double budget = 5e8);

}  // namespace hemirad
