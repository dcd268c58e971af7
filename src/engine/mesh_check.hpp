// Mesh diagnosis (issue 34): what a scene's mesh does to F, issue by issue, counted with examples.
#pragma once

#include "engine/scene.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace hemirad {

struct MeshCheckOptions {
    /// Positions closer than this times the scene extent (bounding-box diagonal) are one point; also
    /// the distance within which a vertex lies on an edge and a corner on a plane. Default 1e-6.
    double relativeTolerance = 1e-6;
    /// A patch is a sliver when its longest edge exceeds this many times its minimum width (the
    /// least distance between two parallel lines enclosing it; for a triangle longest edge^2 / (2 area)).
    double sliverRatio = 20.0;
    /// A polygon is non-planar when a corner is farther than this times its longest edge from its
    /// Newell plane (the loader's warning threshold).
    double planarity = 1e-4;
    /// Examples kept per issue (the first ones in patch order).
    std::size_t examples = 5;
};

/// One occurrence of an issue.
struct MeshExample {
    std::vector<PatchId> patches;  ///< the patches involved, the one the issue is about first
    std::vector<int> lines;        ///< their OBJ source lines (Patch::sourceLine; 0: not from a file)
    std::vector<Vec3> points;      ///< where: a T-junction's vertex, an edge's two ends (empty: the whole patch)
    double value = 0.0;            ///< the issue's measure (MeshIssue::valueName); 0 where it has none
};

/// The issues in report order; MeshReport::issues[k] is kind k.
enum class MeshIssueKind {
    TJunctions, Duplicates, Overlaps, BackToBack, Orientation, NonManifold, OpenEdges, Slivers, ZeroArea, NonPlanar
};
constexpr std::size_t kMeshIssueKinds = 10;

struct MeshIssue {
    std::string key;        ///< JSON key, e.g. "t_junctions"
    std::string title;      ///< what is counted, for people
    std::string unit;       ///< what `count` counts: "vertex-edge contacts", "pairs", "edges", "patches"
    std::string valueName;  ///< what MeshExample::value measures ("" when nothing)
    std::string effect;     ///< one sentence: what the issue does to F
    std::size_t count = 0;
    std::vector<MeshExample> examples;
};

struct MeshReport {
    MeshCheckOptions options;
    std::size_t patches = 0;
    std::size_t vertices = 0;       ///< distinct corner positions after welding
    std::size_t edges = 0;          ///< distinct undirected edges between welded corners
    double extent = 0.0;            ///< bounding-box diagonal
    double tolerance = 0.0;         ///< options.relativeTolerance * extent, in scene units
    std::vector<MeshIssue> issues;  ///< kMeshIssueKinds entries, in MeshIssueKind order

    std::size_t openEdgesRaw = 0;       ///< edges used by one patch only
    std::size_t openEdgesCovered = 0;   ///< of those, covered exactly by collinear open edges of other patches
    std::size_t duplicatesReversed = 0; ///< duplicate pairs of opposite orientation (also back-to-back)
    std::size_t zeroAreaSkipped = 0;    ///< faces the loader skipped as degenerate (addSkippedZeroArea)
    std::string zeroAreaSkippedNote;    ///< the loader's message about them
    /// (1/3) sum_i A_i (c_i - o) . n_i over the patches with area: negative when they face into the
    /// volume they enclose (a room), positive when they face out of it (an object seen from outside).
    double signedVolume = 0.0;
    /// Every edge, after T-junction covering, is used by exactly two patches in opposite directions.
    bool watertight = false;
    /// Watertight, facing inward (signedVolume < 0) and without coinciding patches: a closed enclosure,
    /// where every row of F sums to 1 (more with mirrors' extended factors).
    bool closed = false;
    std::string closedReason;
    /// F would be meaningless: no patches, non-finite coordinates or every patch of zero area.
    bool meaningless = false;
    std::string meaninglessReason;

    const MeshIssue& issue(MeshIssueKind kind) const { return issues[static_cast<std::size_t>(kind)]; }
    MeshIssue& issue(MeshIssueKind kind) { return issues[static_cast<std::size_t>(kind)]; }
};

/// Diagnoses the mesh of `scene`: pure (no I/O), single-threaded, O(n log n) in the patch count
/// (spatial grids, sorting). Zero-area patches (narrower than the tolerance) and patches with
/// non-finite coordinates take part in no other check.
MeshReport checkMesh(const Scene& scene, const MeshCheckOptions& options = {});

/// Adds `count` faces the loader skipped as degenerate (its "degenerate patches skipped" warnings)
/// to the zero-area issue, with the loader's message; they have no patch index.
void addSkippedZeroArea(MeshReport& report, std::size_t count, const std::string& note);

}  // namespace hemirad
