// Mesh check: welding, per-patch measures, edge topology (open, non-manifold, orientation, T-junction
// covering), the pairwise findings, and the closed/meaningless verdicts.
#include "engine/mesh_check.hpp"

#include "engine/mesh_check_pairs.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_map>

namespace hemirad {
namespace {

void describe(MeshReport& r) {
    struct Text {
        const char *key, *title, *unit, *valueName, *effect;
    };
    static const Text texts[kMeshIssueKinds] = {
        {"t_junctions", "T-junctions (a vertex inside another patch's edge, not a corner of it)", "vertex-edge contacts", "",
         "partial-edge contacts: F between the touching patches needs contact-aware factors, and neighbour-based "
         "visibility (the analytic estimator's silhouette and open-edge splits) treats the split edge as open."},
        {"duplicates", "duplicate patches (the same corners, either orientation)", "pairs", "overlap area",
         "double-counted area: both copies emit and receive, and the F rows and columns of one hide the other "
         "(a reversed copy is a two-sided sheet: also counted as back-to-back)."},
        {"overlapping_coplanar", "overlapping coplanar patches (facing the same way, interiors overlapping)", "pairs",
         "overlap area",
         "double-counted area where they overlap: the F rows of one hide the other, rounding decides which a ray hits."},
        {"back_to_back", "back-to-back patches (coplanar, opposite normals, overlapping)", "pairs", "overlap area",
         "each sees nothing through the other (a shared party wall, a two-sided sheet): each F row is what its own "
         "side sees, and no power passes between the sides."},
        {"inconsistent_orientation", "neighbours with inconsistent orientation (a shared edge run the same way by both)",
         "pairs", "",
         "one of the two normals is flipped: that patch emits into and receives from the wrong side, so its F row "
         "sees the back of the surface."},
        {"non_manifold_edges", "non-manifold edges (used by more than two patches)", "edges", "patches on the edge",
         "fins, inner walls or stacked copies meet there: F is defined, but the scene is no simple enclosure and its "
         "rows need not sum to 1."},
        {"open_edges", "open edges (used by one patch, not covered by collinear edges of others)", "edges", "",
         "power leaves through the gaps (an edge resting on another patch's face leaves that patch seeing back "
         "faces beyond it): rows of F sum to less than 1."},
        {"slivers", "slivers (longest edge / minimum width above the limit)", "patches", "aspect ratio",
         "few rays or origins span a thin patch: its F row and column are noisy, and factors to its close "
         "neighbours are poorly resolved."},
        {"zero_area", "zero-area patches (narrower than the tolerance)", "patches", "area",
         "no area: the patch's F row is 0/0 (undefined) and its column receives nothing."},
        {"non_planar", "non-planar polygons (a corner off the Newell plane by more than the limit)", "patches",
         "deviation / longest edge",
         "rays and the hemicube see the fan triangles of its corners, its area and normal come from the Newell "
         "plane: F differs between back ends by up to the deviation."},
    };
    r.issues.resize(kMeshIssueKinds);
    for (std::size_t k = 0; k < kMeshIssueKinds; ++k) {
        r.issues[k].key = texts[k].key;
        r.issues[k].title = texts[k].title;
        r.issues[k].unit = texts[k].unit;
        r.issues[k].valueName = texts[k].valueName;
        r.issues[k].effect = texts[k].effect;
    }
}

class Examples {
public:
    Examples(const Scene& scene, MeshIssue& issue, std::size_t limit) : m_scene(scene), m_issue(issue), m_limit(limit) {}
    void add(std::vector<PatchId> patches, std::vector<Vec3> points = {}, double value = 0.0) {
        ++m_issue.count;
        if (m_issue.examples.size() >= m_limit) return;
        MeshExample e;
        for (PatchId id : patches) e.lines.push_back(m_scene.patches[id].sourceLine);
        e.patches = std::move(patches);
        e.points = std::move(points);
        e.value = value;
        m_issue.examples.push_back(std::move(e));
    }

private:
    const Scene& m_scene;
    MeshIssue& m_issue;
    std::size_t m_limit;
};

/// The least distance between two parallel lines enclosing the polygon, one of them through an edge
/// (for a convex polygon the minimum width has a side flush with an edge).
double minimumWidth(const std::vector<Vec3>& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec3 d = p[(k + 1) % p.size()] - p[k];
        const double length = d.norm();
        if (!(length > 0.0)) continue;
        double height = 0.0;
        for (const Vec3& x : p) height = std::max(height, (x - p[k]).cross(d).norm() / length);
        best = std::min(best, height);
    }
    return std::isfinite(best) ? best : 0.0;
}

/// Corners within the tolerance of an earlier corner become that corner. A grid of cells twice the
/// tolerance: the positions within the tolerance of a point lie in at most 2 x 2 x 2 cells.
/// Fills mesh.corner and mesh.position.
void weld(const Scene& scene, const Vec3& origin, WeldedMesh& mesh) {
    struct Hash {
        std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
            return std::size_t(k[0]) * 0x9e3779b97f4a7c15ULL ^ std::size_t(k[1]) * 0xc2b2ae3d27d4eb4fULL ^
                   std::size_t(k[2]) * 0x165667b19e3779f9ULL;
        }
    };
    const double tol = mesh.tolerance, cell = 2.0 * tol;
    auto cellOf = [&](const Vec3& x) {
        const Vec3 c = (x - origin) / cell;
        return std::array<std::int64_t, 3>{std::int64_t(std::floor(c.x())), std::int64_t(std::floor(c.y())),
                                           std::int64_t(std::floor(c.z()))};
    };
    std::unordered_map<std::array<std::int64_t, 3>, std::uint32_t, Hash> head;  // cell -> latest vertex in it
    std::vector<std::uint32_t> next;  // per welded vertex: the previous one in its cell
    constexpr std::uint32_t kNone = UINT32_MAX;
    std::vector<std::uint32_t> ofVertex(scene.vertices.size(), kNone);
    head.reserve(scene.vertices.size());
    mesh.corner.assign(scene.corners.size(), kNone);
    for (std::size_t c = 0; c < scene.corners.size(); ++c) {
        const std::uint32_t v = scene.corners[c];
        if (ofVertex[v] == kNone) {
            const Vec3& x = scene.vertices[v];
            const auto lo = cellOf(x - Vec3::Constant(tol)), hi = cellOf(x + Vec3::Constant(tol));
            std::uint32_t found = kNone;
            for (std::int64_t i = lo[0]; i <= hi[0] && found == kNone; ++i)
                for (std::int64_t j = lo[1]; j <= hi[1] && found == kNone; ++j)
                    for (std::int64_t k = lo[2]; k <= hi[2] && found == kNone; ++k) {
                        const auto it = head.find({i, j, k});
                        for (std::uint32_t w = it == head.end() ? kNone : it->second; w != kNone; w = next[w])
                            if ((mesh.position[w] - x).norm() <= tol) {
                                found = w;
                                break;
                            }
                    }
            if (found == kNone) {
                found = static_cast<std::uint32_t>(mesh.position.size());
                mesh.position.push_back(x);
                auto [it, added] = head.emplace(cellOf(x), found);
                next.push_back(added ? kNone : it->second);
                it->second = found;
            }
            ofVertex[v] = found;
        }
        mesh.corner[c] = ofVertex[v];
    }
}

struct EdgeUse {
    std::uint64_t key;
    PatchId patch;
    std::uint32_t corner;  // Scene::corners entry where the edge starts
    bool forward;          // runs from the lower welded vertex to the higher
    bool operator<(const EdgeUse& o) const { return key != o.key ? key < o.key : patch < o.patch; }
};

/// Edges of the usable patches: open ones marked in mesh.openEdge, the others judged.
void edgeTopology(const Scene& scene, WeldedMesh& mesh, MeshReport& r) {
    std::vector<EdgeUse> uses;
    for (PatchId i = 0; i < scene.size(); ++i) {
        if (!mesh.usable[i]) continue;
        const Patch& p = scene.patches[i];
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const std::uint32_t a = mesh.corner[p.firstCorner + k], b = mesh.corner[p.firstCorner + (k + 1) % p.cornerCount];
            if (a == b) continue;
            uses.push_back({std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), i, p.firstCorner + k, a < b});
        }
    }
    std::sort(uses.begin(), uses.end());
    mesh.openEdge.assign(scene.corners.size(), 0);
    Examples orientation(scene, r.issue(MeshIssueKind::Orientation), r.options.examples);
    Examples nonManifold(scene, r.issue(MeshIssueKind::NonManifold), r.options.examples);
    std::vector<std::tuple<PatchId, PatchId, std::uint64_t>> flipped;  // the pair and their edge
    for (std::size_t s = 0, e = 0; s < uses.size(); s = e) {
        while (e < uses.size() && uses[e].key == uses[s].key) ++e;
        ++r.edges;
        const std::vector<Vec3> ends = {mesh.position[uses[s].key >> 32], mesh.position[uses[s].key & 0xffffffffu]};
        if (e - s == 1) {
            mesh.openEdge[uses[s].corner] = 1;
        } else if (e - s == 2) {
            if (uses[s].patch != uses[s + 1].patch && uses[s].forward == uses[s + 1].forward)
                flipped.emplace_back(uses[s].patch, uses[s + 1].patch, uses[s].key);
        } else {
            std::vector<PatchId> patches;
            for (std::size_t k = s; k < e; ++k) patches.push_back(uses[k].patch);
            patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
            nonManifold.add(patches, ends, double(patches.size()));
        }
    }
    // Edges in key order; examples in patch order read better, and a pair sharing two edges is one pair.
    std::sort(flipped.begin(), flipped.end());
    flipped.erase(std::unique(flipped.begin(), flipped.end(),
                              [](const auto& x, const auto& y) {
                                  return std::get<0>(x) == std::get<0>(y) && std::get<1>(x) == std::get<1>(y);
                              }),
                  flipped.end());
    for (const auto& [a, b, key] : flipped)
        orientation.add({a, b}, {mesh.position[key >> 32], mesh.position[key & 0xffffffffu]});
}

/// Open edges covered exactly by the union of collinear open edges of other patches (a T-junction
/// chain: AB of one patch, AC and CB of two others) are not open.
void openEdges(const Scene& scene, const WeldedMesh& mesh, std::vector<EdgeCover> covers, MeshReport& r) {
    std::sort(covers.begin(), covers.end(), [](const EdgeCover& a, const EdgeCover& b) {
        return a.corner != b.corner ? a.corner < b.corner : a.t0 < b.t0;
    });
    Examples open(scene, r.issue(MeshIssueKind::OpenEdges), r.options.examples);
    std::size_t next = 0;
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const std::uint32_t c = p.firstCorner + k;
            if (!mesh.openEdge[c]) continue;
            ++r.openEdgesRaw;
            const Vec3& a = mesh.position[mesh.corner[c]];
            const Vec3& b = mesh.position[mesh.corner[p.firstCorner + (k + 1) % p.cornerCount]];
            const double slack = mesh.tolerance / (b - a).norm();
            double reach = 0.0;
            while (next < covers.size() && covers[next].corner < c) ++next;
            for (; next < covers.size() && covers[next].corner == c; ++next)
                if (covers[next].t0 <= reach + slack) reach = std::max(reach, covers[next].t1);
            if (reach >= 1.0 - slack) ++r.openEdgesCovered;
            else open.add({i}, {a, b});
        }
    }
}

void pairIssues(const Scene& scene, const WeldedMesh& mesh, PairFindings& found, MeshReport& r) {
    auto& touching = found.vertexOnEdge;
    // One contact per vertex and edge, however many patches share either.
    std::sort(touching.begin(), touching.end(), [](const VertexOnEdge& a, const VertexOnEdge& b) {
        return std::tie(a.edgeKey, a.vertex, a.patch, a.other) < std::tie(b.edgeKey, b.vertex, b.patch, b.other);
    });
    touching.erase(std::unique(touching.begin(), touching.end(),
                               [](const VertexOnEdge& a, const VertexOnEdge& b) {
                                   return a.edgeKey == b.edgeKey && a.vertex == b.vertex;
                               }),
                   touching.end());
    std::sort(touching.begin(), touching.end(), [](const VertexOnEdge& a, const VertexOnEdge& b) {
        return std::tie(a.patch, a.edge, a.other, a.vertex) < std::tie(b.patch, b.edge, b.other, b.vertex);
    });
    Examples tJunctions(scene, r.issue(MeshIssueKind::TJunctions), r.options.examples);
    for (const VertexOnEdge& t : touching) tJunctions.add({t.patch, t.other}, {mesh.position[t.vertex]});

    std::sort(found.coinciding.begin(), found.coinciding.end(),
              [](const CoincidingPair& a, const CoincidingPair& b) { return std::tie(a.a, a.b) < std::tie(b.a, b.b); });
    Examples duplicates(scene, r.issue(MeshIssueKind::Duplicates), r.options.examples);
    Examples overlaps(scene, r.issue(MeshIssueKind::Overlaps), r.options.examples);
    Examples backToBack(scene, r.issue(MeshIssueKind::BackToBack), r.options.examples);
    for (const CoincidingPair& c : found.coinciding) {
        if (c.sameVertices) duplicates.add({c.a, c.b}, {}, c.overlap);
        if (c.sameVertices && c.reversed) ++r.duplicatesReversed;
        if (c.reversed) backToBack.add({c.a, c.b}, {}, c.overlap);
        else if (!c.sameVertices) overlaps.add({c.a, c.b}, {}, c.overlap);
    }
}

void verdict(const Scene& scene, MeshReport& r) {
    auto count = [&](MeshIssueKind k) { return r.issue(k).count; };
    const std::size_t open = count(MeshIssueKind::OpenEdges), nonManifold = count(MeshIssueKind::NonManifold),
                      flipped = count(MeshIssueKind::Orientation);
    const std::size_t coinciding =
        count(MeshIssueKind::Duplicates) + count(MeshIssueKind::Overlaps) + count(MeshIssueKind::BackToBack);
    r.watertight = !r.meaningless && open == 0 && nonManifold == 0 && flipped == 0;
    const std::string n = std::to_string(open);
    if (r.meaningless) r.closedReason = r.meaninglessReason;
    else if (open) r.closedReason = n + " open edge" + (open == 1 ? "" : "s") + ", " + std::to_string(r.openEdgesRaw) +
                                    " before T-junction covering: power escapes, rows of F sum to less than 1";
    else if (nonManifold) r.closedReason = std::to_string(nonManifold) + " non-manifold edges: no simple enclosure";
    else if (flipped) r.closedReason = std::to_string(flipped) + " neighbour pairs with inconsistent orientation";
    else if (coinciding) r.closedReason = std::to_string(coinciding) + " pairs of coinciding patches";
    else if (!(r.signedVolume < -r.tolerance * scene.totalArea()))
        r.closedReason = "watertight, but the patches face out of the volume they enclose (an object seen from outside)";
    else {
        r.closed = true;
        r.closedReason = std::string("watertight and facing inward: every row of F should sum to 1") +
                         (scene.hasMirrors() ? " (more with mirrors: extended factors)" : "");
    }
}

}  // namespace

MeshReport checkMesh(const Scene& scene, const MeshCheckOptions& options) {
    MeshReport r;
    r.options = options;
    describe(r);
    r.patches = scene.size();
    auto fail = [&](const std::string& why) {
        r.meaningless = true;
        r.meaninglessReason = why;
        r.closedReason = why;
        return r;
    };
    if (scene.size() == 0) return fail("the scene has no patches");
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        bool finite = std::isfinite(p.area) && p.normal.allFinite();
        for (std::uint32_t k = 0; k < p.cornerCount && finite; ++k) finite = scene.corner(p, k).allFinite();
        if (!finite)
            return fail("patch " + std::to_string(i) + (p.sourceLine ? " (line " + std::to_string(p.sourceLine) + ")" : "") +
                        " has non-finite coordinates");
    }
    r.extent = scene.extent();
    r.tolerance = options.relativeTolerance * r.extent;

    WeldedMesh mesh;
    mesh.tolerance = r.tolerance;
    mesh.usable.assign(scene.size(), 0);
    Examples slivers(scene, r.issue(MeshIssueKind::Slivers), options.examples);
    Examples zeroArea(scene, r.issue(MeshIssueKind::ZeroArea), options.examples);
    Examples nonPlanar(scene, r.issue(MeshIssueKind::NonPlanar), options.examples);
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        const std::vector<Vec3> points = scene.polygon(i);
        double longest = 0.0;
        for (std::size_t k = 0; k < points.size(); ++k)
            longest = std::max(longest, (points[(k + 1) % points.size()] - points[k]).norm());
        const double width = minimumWidth(points);
        if (!(p.area > 0.0) || p.normal.squaredNorm() == 0.0 || !(width > r.tolerance)) {
            zeroArea.add({i}, {}, p.area);
            continue;
        }
        mesh.usable[i] = 1;
        if (longest > options.sliverRatio * width) slivers.add({i}, {}, longest / width);
        double deviation = 0.0;
        for (const Vec3& x : points) deviation = std::max(deviation, std::abs((x - p.centroid).dot(p.normal)));
        if (p.cornerCount > 3 && deviation > options.planarity * longest) nonPlanar.add({i}, {}, deviation / longest);
    }
    if (r.issue(MeshIssueKind::ZeroArea).count == scene.size())
        return fail("every patch has zero area (narrower than the tolerance " + std::to_string(r.tolerance) + ")");

    Vec3 lo, hi;
    scene.bounds(lo, hi);
    weld(scene, lo, mesh);
    r.vertices = mesh.position.size();
    edgeTopology(scene, mesh, r);
    PairFindings found = findPairIssues(scene, mesh);
    openEdges(scene, mesh, std::move(found.covers), r);
    pairIssues(scene, mesh, found, r);

    const Vec3 middle = 0.5 * (lo + hi);
    for (PatchId i = 0; i < scene.size(); ++i)
        if (mesh.usable[i]) {
            const Patch& p = scene.patches[i];
            r.signedVolume += p.area * (p.centroid - middle).dot(p.normal) / 3.0;
        }
    verdict(scene, r);
    return r;
}

void addSkippedZeroArea(MeshReport& report, std::size_t count, const std::string& note) {
    report.zeroAreaSkipped += count;
    report.issue(MeshIssueKind::ZeroArea).count += count;
    if (!note.empty()) report.zeroAreaSkippedNote = note;
}

}  // namespace hemirad
