// The pairwise part of the mesh check: patches whose boxes touch, tested for vertex-on-edge contacts,
// coinciding (duplicate, overlapping, back-to-back) patches and collinear open edges.
#pragma once

#include "engine/scene.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

/// The welded mesh the checks share.
struct WeldedMesh {
    double tolerance = 0.0;               ///< scene units
    std::vector<std::uint32_t> corner;    ///< per Scene::corners entry: its welded vertex
    std::vector<Vec3> position;           ///< per welded vertex
    std::vector<std::uint8_t> usable;     ///< per patch: finite and not zero-area (takes part in the checks)
    std::vector<std::uint8_t> openEdge;   ///< per Scene::corners entry c: the edge c -> next corner is used once
};

/// A vertex strictly inside the edge (corner `edge` -> next corner) of patch `patch`, and not a
/// corner of it; `other` is a patch that has the vertex as a corner.
struct VertexOnEdge {
    std::uint64_t edgeKey;  ///< the edge's two welded vertices, lower one in the high half
    std::uint32_t vertex;
    PatchId patch, other;
    std::uint32_t edge;
};

/// Two patches that coincide: coplanar within the tolerance and overlapping by more than a band of
/// the tolerance's width along the smaller one's boundary.
struct CoincidingPair {
    PatchId a, b;
    bool sameVertices;  ///< the same welded corners (a duplicate)
    bool reversed;      ///< opposite normals
    double overlap;     ///< area of the overlap
};

/// Part [t0, t1] (of 0..1) of the open edge at Scene::corners entry `corner` that a collinear open
/// edge of another patch covers.
struct EdgeCover {
    std::uint32_t corner;
    double t0, t1;
};

struct PairFindings {
    std::vector<VertexOnEdge> vertexOnEdge;
    std::vector<CoincidingPair> coinciding;
    std::vector<EdgeCover> covers;
};

/// Tests every pair of usable patches whose boxes (grown by the tolerance) touch.
PairFindings findPairIssues(const Scene& scene, const WeldedMesh& mesh);

}  // namespace hemirad
