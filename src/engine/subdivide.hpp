// Patch subdivision: regular grids of quads / triangles until no edge exceeds a length.
#pragma once

#include "engine/scene.hpp"

namespace hemirad {

/// Splits every patch until no edge is longer than maxEdge (scene units, > 0): quads into an
/// nu x nv grid of quads (bilinear), triangles into n^2 triangles, larger polygons into fan
/// triangles first. Materials, objects and source lines are kept; each new patch records its
/// parent polygon and grid cell. Vertices on shared edges are computed identically from both
/// sides, so neighbours with equal edge counts share vertices.
Scene subdivide(const Scene& in, double maxEdge);

}  // namespace hemirad
