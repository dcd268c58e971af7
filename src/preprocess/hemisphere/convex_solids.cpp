// Closed convex solids among the blockers (see convex_solids.hpp).
#include "preprocess/hemisphere/convex_solids.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace hemirad {

void ConvexSolids::build(const PatchGeometry& geometry, const std::vector<std::uint8_t>& blocks) {
    const std::size_t n = geometry.shapes.size();
    m_solidOf.assign(n, kNone);
    m_solids.clear();
    m_normals.clear();
    m_offsets.clear();
    if (geometry.neighbourStart.size() != n + 1) return;
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

    // Components over convex (or flat) edges shared by two blockers in opposite directions; a
    // component is spoilt by an edge shared the same way round, by three or more patches, or with
    // a patch that does not block. Unshared and concave edges are its open edges.
    std::vector<PatchId> root(n);
    for (PatchId j = 0; j < n; ++j) root[j] = j;
    const auto find = [&](PatchId j) {
        while (root[j] != j) j = root[j] = root[root[j]];
        return j;
    };
    std::vector<std::uint8_t> spoilt(n, 0);
    std::vector<std::array<Vec3, 2>> openEdges;
    std::vector<PatchId> openOwner;
    for (PatchId j = 0; j < n; ++j) {
        if (!blocks[j]) continue;
        const std::uint32_t count = geometry.shapes[j].count;
        for (std::uint32_t k = 0; k < count; ++k) {
            const Vec3& a = corner(j, k);
            const Vec3& b = corner(j, k + 1);
            std::uint32_t opposite = 0;
            PatchId other = j;
            for (std::uint32_t e = geometry.neighbourStart[j]; e < geometry.neighbourStart[j + 1]; ++e) {
                const PatchId o = geometry.neighbours[e];
                if (o == j) continue;
                for (std::uint32_t c = 0; c < geometry.shapes[o].count; ++c) {
                    const Vec3& p = corner(o, c);
                    const Vec3& q = corner(o, c + 1);
                    if (near(p, b) && near(q, a)) {
                        ++opposite;
                        other = o;
                    } else if (near(p, a) && near(q, b)) {
                        spoilt[j] = 1;
                    }
                }
            }
            // A concave edge (the other face rises in front of this one's plane: a wall on its
            // ground) joins no solid: it is an open edge of each.
            if (opposite == 1) {
                const PatchShape& t = geometry.shapes[j];
                const double offset = t.normal.dot(t.centroid);
                for (std::uint32_t c = 0; c < geometry.shapes[other].count; ++c)
                    if (t.normal.dot(corner(other, c)) - offset > flatness) opposite = 0;
            }
            if (opposite == 0) {
                openEdges.push_back({a, b});
                openOwner.push_back(j);
            } else if (opposite > 1 || !blocks[other]) {
                spoilt[j] = 1;
            } else {
                root[find(j)] = find(other);
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
