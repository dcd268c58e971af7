// Patch subdivision: regular grids of quads / triangles until no edge exceeds a length.
#pragma once

#include "engine/scene.hpp"

#include <vector>

namespace hemirad {

/// Splits every patch until no edge is longer than maxEdge (scene units, > 0): quads into an
/// nu x nv grid of quads (bilinear), triangles into n^2 triangles, larger polygons into fan
/// triangles first. Materials, objects and source lines are kept; each new patch records its
/// parent polygon and grid cell. Vertices on shared edges are computed identically from both
/// sides, so neighbours with equal edge counts share vertices.
Scene subdivide(const Scene& in, double maxEdge);

/// As above with one maximum edge length per object (Scene::objects; one entry when the scene has
/// none), 0 keeping that object's patches whole: the GUI's meshing of selected objects. Where a
/// refined object meets a coarser one, the fine side's vertices are T-junctions on the coarse edge.
Scene subdivide(const Scene& in, const std::vector<double>& maxEdgeByObject);

/// The number of patches subdivide(in, maxEdgeByObject) makes, without making them.
std::size_t subdividedSize(const Scene& in, const std::vector<double>& maxEdgeByObject);

/// For two subdivisions of one source scene (Parent::sourcePatch into the same scene): for each
/// patch of `to`, the patch of `from` that covers its centroid. Carries per-patch values (materials,
/// radiosity, selection) from one mesh to the other.
std::vector<PatchId> coveringPatches(const Scene& from, const Scene& to);

}  // namespace hemirad
