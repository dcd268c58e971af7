// What the hemicube draws: a vertex stream of patch triangles and whole subdivided parent polygons.
#pragma once

#include "engine/scene.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

/// Triangles in scene-centred float coordinates, each vertex tagged with a code: a patch id, or
/// kParentBit | parent index for a planar parent polygon drawn whole, whose fragments find their
/// patch from the parent's grid (drawing the 12 triangles of a subdivided box instead of 25,000
/// measured 25-50x faster on llvmpipe).
struct HemicubeGeometry {
    static constexpr std::uint32_t kParentBit = 0x80000000u;

    /// Grid kinds as the fragment shader reads them.
    enum Kind : std::uint32_t { kNone = 0, kParallelogram = 1, kTriangle = 2, kQuad = 3 };
    struct Vertex {
        float x, y, z;
        std::uint32_t code;
        float u, v;             ///< grid parameter: (u, v), barycentric (a, b), or planar position (kQuad)
        std::uint32_t grid[4];  ///< first patch, nu, nv, Kind
    };
    /// std430 layout of the fragment shader's Parent struct (general quads: inverse bilinear).
    struct ParentRecord {
        float q12[4];  ///< corners 1 and 2 in the parent's plane, corner 0 at the origin
        float q3[4];
    };

    /// Sorted by Kind: vertices [rangeStart[k], rangeStart[k + 1]) are drawn with the kind-k program.
    std::vector<Vertex> vertices;
    std::uint32_t rangeStart[5] = {0, 0, 0, 0, 0};
    std::vector<ParentRecord> parents;
    std::vector<std::uint32_t> codeOfPatch;  ///< the code patch i is drawn under
    Vec3 centre = Vec3::Zero();
    double extent = 0;
    std::size_t patchesInParents = 0;

    /// usesParents = false draws every patch's own triangles (the reference path).
    static HemicubeGeometry build(const Scene& scene, bool useParents);
};

}  // namespace hemirad
