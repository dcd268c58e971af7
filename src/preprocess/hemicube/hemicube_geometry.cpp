// Building the hemicube's vertex stream and parent table.
#include "preprocess/hemicube/hemicube_geometry.hpp"

#include "engine/polygon.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {
namespace {

/// A parent can be drawn whole when it is a planar quad or triangle grid of more than one patch.
bool drawableParent(const Scene& scene, const Parent& parent) {
    if (parent.patchCount < 2 || parent.kind == GridKind::Single) return false;
    if (parent.nu > 0xffff || parent.nv > 0xffff) return false;  // the shader packs nu, nv in 16 bits
    std::vector<Vec3> corners;
    for (std::uint32_t k = 0; k < parent.cornerCount; ++k)
        corners.push_back(scene.vertices[scene.parentCorners[parent.firstCorner + k]]);
    const PolygonMeasures m = measurePolygon(corners);
    return m.area > 0 && m.planarDeviation <= 1e-6 * m.maxEdge;
}

}  // namespace

HemicubeGeometry HemicubeGeometry::build(const Scene& scene, bool useParents) {
    HemicubeGeometry g;
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    g.centre = 0.5 * (lo + hi);
    g.extent = (hi - lo).norm();
    g.codeOfPatch.assign(scene.size(), 0);
    auto local = [&](const Vec3& p) { return Vec3(p - g.centre); };
    std::vector<Vertex> byKind[4];
    auto push = [&](const Vec3& p, std::uint32_t code, float u = 0, float v = 0, const std::uint32_t* grid = nullptr) {
        const Vec3 q = local(p);
        Vertex vertex{float(q.x()), float(q.y()), float(q.z()), code, u, v, {0, 0, 0, kNone}};
        if (grid) std::copy(grid, grid + 4, vertex.grid);
        byKind[vertex.grid[3]].push_back(vertex);
    };
    std::vector<bool> inParent(scene.size(), false);
    if (useParents)
        for (const Parent& parent : scene.parents) {
            if (!drawableParent(scene, parent)) continue;
            const auto index = static_cast<std::uint32_t>(g.parents.size());
            const std::uint32_t code = kParentBit | index;
            std::vector<Vec3> c;
            for (std::uint32_t k = 0; k < parent.cornerCount; ++k)
                c.push_back(scene.vertices[scene.parentCorners[parent.firstCorner + k]]);
            const Vec3 normal = measurePolygon(c).normal;
            const Vec3 axisU = (c[1] - c[0]).normalized();
            const Vec3 axisV = normal.cross(axisU).normalized();
            auto planar = [&](const Vec3& p) { return Eigen::Vector2d((p - c[0]).dot(axisU), (p - c[0]).dot(axisV)); };
            ParentRecord r{};
            std::uint32_t grid[4] = {parent.firstPatch, parent.nu, parent.nv, kTriangle};
            if (parent.kind == GridKind::Quad) {
                const Eigen::Vector2d q1 = planar(c[1]), q2 = planar(c[2]), q3 = planar(c[3]);
                r.q12[0] = float(q1.x());
                r.q12[1] = float(q1.y());
                r.q12[2] = float(q2.x());
                r.q12[3] = float(q2.y());
                r.q3[0] = float(q3.x());
                r.q3[1] = float(q3.y());
                // Parallelograms: (u, v) is affine in position, so interpolation gives it exactly.
                const bool parallelogram = (c[0] + c[2] - c[1] - c[3]).norm() <= 1e-6 * (c[2] - c[0]).norm();
                grid[3] = parallelogram ? kParallelogram : kQuad;
                if (parallelogram) {
                    push(c[0], code, 0, 0, grid), push(c[1], code, 1, 0, grid), push(c[2], code, 1, 1, grid);
                    push(c[0], code, 0, 0, grid), push(c[2], code, 1, 1, grid), push(c[3], code, 0, 1, grid);
                } else {
                    // The planar position is affine too; the fragment inverts the bilinear map from it.
                    auto pushPlanar = [&](const Vec3& p) {
                        const Eigen::Vector2d q = planar(p);
                        push(p, code, float(q.x()), float(q.y()), grid);
                    };
                    pushPlanar(c[0]), pushPlanar(c[1]), pushPlanar(c[2]);
                    pushPlanar(c[0]), pushPlanar(c[2]), pushPlanar(c[3]);
                }
            } else {
                push(c[0], code, 0, 0, grid), push(c[1], code, 1, 0, grid), push(c[2], code, 0, 1, grid);
            }
            g.parents.push_back(r);
            for (std::uint32_t k = 0; k < parent.patchCount; ++k) {
                inParent[parent.firstPatch + k] = true;
                g.codeOfPatch[parent.firstPatch + k] = code;
            }
            g.patchesInParents += parent.patchCount;
        }
    for (PatchId id = 0; id < scene.size(); ++id) {
        if (inParent[id]) continue;
        const Patch& p = scene.patches[id];
        g.codeOfPatch[id] = id;
        for (std::uint32_t k = 1; k + 1 < p.cornerCount; ++k) {
            push(scene.corner(p, 0), id);
            push(scene.corner(p, k), id);
            push(scene.corner(p, k + 1), id);
        }
    }
    for (int k = 0; k < 4; ++k) {
        g.rangeStart[k] = static_cast<std::uint32_t>(g.vertices.size());
        g.vertices.insert(g.vertices.end(), byKind[k].begin(), byKind[k].end());
    }
    g.rangeStart[4] = static_cast<std::uint32_t>(g.vertices.size());
    return g;
}

}  // namespace hemirad
