// Closed convex solids among the blockers (see convex_solids.hpp).
#include "preprocess/hemisphere/convex_solids.hpp"

#include "preprocess/hemisphere/point_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace hemirad {

void ConvexSolids::build(const PatchGeometry& geometry, const std::vector<std::uint8_t>& blocks) {
    const std::size_t n = geometry.shapes.size();
    m_solidOf.assign(n, kNone);
    m_faces = 0;
    m_solids.clear();
    m_normals.clear();
    m_offsets.clear();
    // Corners match within 1e-9 of the scene's size, as PatchGeometry's neighbours do.
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const Vec3& c : geometry.corners) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    if (geometry.corners.empty()) return;
    const double match = std::max(1e-9 * (hi - lo).norm(), 1e-300);
    // Flat within the rounding of the corners as files give them (cornell13k's are written to
    // 1e-4 mm: a gridded side's tiles leave its plane by 7e-5 mm, 2e-7 of the box).
    const double flatness = kFlatness * (hi - lo).norm();
    const auto near = [match](const Vec3& a, const Vec3& b) { return (a - b).norm() <= match; };
    const auto corner = [&](PatchId j, std::uint32_t k) -> const Vec3& {
        return geometry.corners[geometry.shapes[j].first + k % geometry.shapes[j].count];
    };

    // Components over the lines where blockers meet. Along a line, the edges of one side (in one
    // direction, chained end to start) must be covered by the other side's (the other direction)
    // from one end of the run to the other: whole edges shared, or T-junctions (a roof's edge
    // against a wall split into strips, strips split differently on each side). Such a line joins
    // the faces of both runs unless two of them meet concavely (the other face rises in front of
    // one's plane: a wall on its ground); then, or where the other side does not cover the run,
    // its edges are open edges. A fork (two edges going on from one point along the line on one
    // side: three faces at an edge, or two alike) spoils the faces met.
    std::vector<PatchId> root(n);
    for (PatchId j = 0; j < n; ++j) root[j] = j;
    const auto find = [&](PatchId j) {
        while (root[j] != j) j = root[j] = root[root[j]];
        return j;
    };
    std::vector<std::uint8_t> spoilt(n, 0);
    std::vector<std::array<Vec3, 2>> openEdges;
    std::vector<PatchId> openOwner;
    // Edges by the position of their first (0) or second (1) corner.
    struct Edge {
        PatchId face;
        std::uint32_t k;
    };
    std::array<PointGrid<Edge>, 2> ends = {PointGrid<Edge>(match), PointGrid<Edge>(match)};
    for (PatchId j = 0; j < n; ++j)
        if (blocks[j])
            for (std::uint32_t k = 0; k < geometry.shapes[j].count; ++k)
                for (int side = 0; side < 2; ++side) ends[side].add(corner(j, k + side), {j, k});
    // The edges along unit direction d (on the line through `on`) whose corner `which` (0 first,
    // 1 second) lies at p.
    std::vector<Edge> found;
    const auto along = [&](const Vec3& p, int which, const Vec3& d, const Vec3& on) {
        found.clear();
        ends[which].nearby(p, [&](const Edge& e) {
            const Vec3& a = corner(e.face, e.k);
            const Vec3& b = corner(e.face, e.k + 1);
            if (!near(which == 0 ? a : b, p)) return;
            const Vec3 edge = b - a;
            const double length = edge.norm();
            if (!(length > 0.0) || edge.dot(d) < (1.0 - 1e-9) * length) return;
            const Vec3 far = (which == 0 ? b : a) - on;  // off the line within kFlatness of the way
            if (far.cross(d).norm() > kFlatness * far.norm() + match) return;
            found.push_back(e);
        });
        return found.size();
    };
    const auto concave = [&](PatchId j, PatchId o) {
        const PatchShape& t = geometry.shapes[j];
        const double offset = t.normal.dot(t.centroid);
        for (std::uint32_t c = 0; c < geometry.shapes[o].count; ++c)
            if (t.normal.dot(corner(o, c)) - offset > flatness) return true;
        return false;
    };
    std::vector<std::uint8_t> done(geometry.corners.size(), 0);
    std::vector<Edge> run, other;
    for (PatchId j = 0; j < n; ++j) {
        if (!blocks[j]) continue;
        for (std::uint32_t k = 0; k < geometry.shapes[j].count; ++k) {
            if (done[geometry.shapes[j].first + k]) continue;
            const Vec3& a = corner(j, k);
            const Vec3 d = (corner(j, k + 1) - a).normalized();
            if (!d.allFinite()) {
                spoilt[j] = 1;
                continue;
            }
            // This side's run through the edge, both ways, and the other side's from its end back.
            bool forked = false;
            run.assign(1, {j, k});
            while (run.size() <= geometry.corners.size() && along(corner(run.back().face, run.back().k + 1), 0, d, a) > 0) {
                forked = forked || found.size() > 1;
                run.push_back(found[0]);
            }
            std::reverse(run.begin(), run.end());
            while (run.size() <= geometry.corners.size() && along(corner(run.back().face, run.back().k), 1, d, a) > 0) {
                forked = forked || found.size() > 1;
                run.push_back(found[0]);
            }
            const Vec3 from = corner(run.back().face, run.back().k), to = corner(run.front().face, run.front().k + 1);
            bool covered = false;
            other.clear();
            for (Vec3 at = to; other.size() <= geometry.corners.size() && along(at, 0, -d, a) > 0;) {
                forked = forked || found.size() > 1;
                other.push_back(found[0]);
                at = corner(found[0].face, found[0].k + 1);
                if ((at - from).dot(d) < -match) break;  // past the run's end
                if (near(at, from)) {
                    covered = true;
                    break;
                }
            }
            bool joins = covered;
            for (const Edge& e : run) {
                done[geometry.shapes[e.face].first + e.k] = 1;
                if (forked) spoilt[e.face] = 1;
                for (const Edge& f : other) joins = joins && !concave(e.face, f.face) && !concave(f.face, e.face);
            }
            if (forked)
                for (const Edge& f : other) spoilt[f.face] = 1;
            if (joins) {
                for (const Edge& f : other) done[geometry.shapes[f.face].first + f.k] = 1;
                for (const Edge& e : run)
                    for (const Edge& f : other) root[find(e.face)] = find(f.face);
            } else {
                for (const Edge& e : run) {
                    openEdges.push_back({corner(e.face, e.k), corner(e.face, e.k + 1)});
                    openOwner.push_back(e.face);
                }
            }
        }
    }
    std::vector<std::vector<PatchId>> members(n);
    for (PatchId j = 0; j < n; ++j)
        if (blocks[j]) members[find(j)].push_back(j);
    std::vector<std::vector<std::size_t>> opens(n);
    for (std::size_t k = 0; k < openEdges.size(); ++k) opens[find(openOwner[k])].push_back(k);

    std::vector<Vec3> points;
    std::vector<std::pair<Vec3, double>> planes;
    for (PatchId c = 0; c < n; ++c) {
        const std::vector<PatchId>& faces = members[c];
        if (faces.empty()) continue;
        if (std::any_of(faces.begin(), faces.end(), [&](PatchId j) { return spoilt[j] != 0; })) continue;
        points.clear();
        for (const PatchId j : faces)
            for (std::uint32_t k = 0; k < geometry.shapes[j].count; ++k) points.push_back(corner(j, k));
        std::sort(points.begin(), points.end(), [](const Vec3& a, const Vec3& b) {
            return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
        });
        points.erase(std::unique(points.begin(), points.end()), points.end());
        Vec3 plo = points[0], phi = points[0];
        for (const Vec3& p : points) plo = plo.cwiseMin(p), phi = phi.cwiseMax(p);
        Solid solid;
        solid.tolerance = std::max(kFlatness * (phi - plo).norm(), match);
        solid.lo = plo;
        solid.hi = phi;
        for (const Vec3& p : points) solid.radius = std::max(solid.radius, (p - 0.5 * (plo + phi)).norm());
        // The open side: the open edges' loops, reversed, as one polygon's Newell normal.
        if (!opens[c].empty()) {
            const Vec3 origin = openEdges[opens[c][0]][0];
            Vec3 normal = Vec3::Zero();
            for (const std::size_t k : opens[c]) normal += (openEdges[k][1] - origin).cross(openEdges[k][0] - origin);
            const double length = normal.norm();
            if (!(length > 0.0)) continue;
            solid.open = true;
            solid.openNormal = normal / length;
            solid.openOffset = solid.openNormal.dot(origin);
            bool flat = true;
            for (const std::size_t k : opens[c])
                for (const Vec3& p : openEdges[k])
                    flat = flat && std::abs(solid.openNormal.dot(p) - solid.openOffset) <= solid.tolerance;
            if (!flat) continue;
        }
        planes.clear();
        for (const PatchId j : faces) {
            const PatchShape& t = geometry.shapes[j];
            planes.push_back({t.normal, t.normal.dot(t.centroid)});
        }
        std::sort(planes.begin(), planes.end(), [](const auto& a, const auto& b) {
            return std::lexicographical_compare(a.first.data(), a.first.data() + 3, b.first.data(), b.first.data() + 3) ||
                   (a.first == b.first && a.second < b.second);
        });
        planes.erase(std::unique(planes.begin(), planes.end(),
                                 [&](const auto& a, const auto& b) {
                                     return a.first.dot(b.first) > 1.0 - 1e-12 && std::abs(a.second - b.second) <= solid.tolerance;
                                 }),
                     planes.end());
        if (planes.size() + (solid.open ? 1 : 0) < 4) continue;  // no volume
        if (std::uint64_t(planes.size() + 1) * points.size() > kMostChecks) continue;
        // Convex and facing out: every corner behind or on every plane.
        bool convex = true;
        for (std::size_t k = 0; k < planes.size() && convex; ++k)
            for (const Vec3& p : points) convex = convex && planes[k].first.dot(p) - planes[k].second <= solid.tolerance;
        if (solid.open)
            for (const Vec3& p : points) convex = convex && solid.openNormal.dot(p) - solid.openOffset <= solid.tolerance;
        if (!convex) continue;
        solid.firstPlane = std::uint32_t(m_normals.size());
        solid.planes = std::uint32_t(planes.size());
        for (const auto& [normal, offset] : planes) {
            m_normals.push_back(normal);
            m_offsets.push_back(offset);
        }
        for (const PatchId j : faces) m_solidOf[j] = std::uint32_t(m_solids.size());
        m_faces += faces.size();
        m_solids.push_back(solid);
    }
}

bool ConvexSolids::entersByFrontFace(std::uint32_t solid, const Vec3& x, std::vector<std::uint32_t>& hint) const {
    const Solid& q = m_solids[solid];
    if (q.open && q.openNormal.dot(x) - q.openOffset > q.tolerance) return false;
    if (hint.size() < m_solids.size()) hint.resize(m_solids.size(), 0);
    const std::uint32_t start = hint[solid] < q.planes ? hint[solid] : 0;
    for (std::uint32_t k = 0; k < q.planes; ++k) {
        const std::uint32_t plane = (start + k) % q.planes;
        if (m_normals[q.firstPlane + plane].dot(x) - m_offsets[q.firstPlane + plane] > q.tolerance) {
            hint[solid] = plane;
            return true;
        }
    }
    return false;
}

}  // namespace hemirad
