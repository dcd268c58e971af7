// The scene's planar mirrors as reflectors, and the clipping of polygons to an aperture's cone.
#include "preprocess/hemisphere/reflectors.hpp"

#include "engine/polygon.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>

namespace hemirad {

std::string findReflectors(const Scene& scene, std::vector<Reflector>& out) {
    out.clear();
    auto describe = [&](PatchId j, const char* what) {
        const Patch& p = scene.patches[j];
        return scene.path + (p.sourceLine > 0 ? ":" + std::to_string(p.sourceLine) : std::string()) +
               ": mirror patch " + std::to_string(j) + " is " + what;
    };
    auto add = [&](const std::vector<Vec3>& polygon, double specular) {
        const PolygonMeasures m = measurePolygon(polygon);
        Reflector r;
        r.polygon = polygon;
        r.normal = m.normal;
        r.centre = m.centroid;
        r.offset = m.normal.dot(m.centroid);
        for (const Vec3& p : polygon) r.radius = std::max(r.radius, (p - m.centroid).norm());
        r.specular = specular;
        out.push_back(std::move(r));
        return m;
    };
    const double flat = 1e-9 * scene.extent();
    std::vector<std::uint8_t> done(scene.size(), 0);
    // A parent polygon whose patches are all mirrors of one s is one reflector (its patches tile it).
    for (const Parent& parent : scene.parents) {
        if (parent.patchCount < 2) continue;
        const double s = scene.patches[parent.firstPatch].specular;
        bool uniform = s > 0.0;
        for (PatchId j = parent.firstPatch; j < parent.firstPatch + parent.patchCount && uniform; ++j)
            uniform = scene.patches[j].specular == s;
        if (!uniform) continue;
        std::vector<Vec3> polygon;
        for (std::uint32_t k = 0; k < parent.cornerCount; ++k)
            polygon.push_back(scene.vertices[scene.parentCorners[parent.firstCorner + k]]);
        const PolygonMeasures m = measurePolygon(polygon);
        if (!(m.area > 0.0) || m.planarDeviation > flat || !m.convex) continue;  // its patches on their own below
        add(polygon, s);
        for (PatchId j = parent.firstPatch; j < parent.firstPatch + parent.patchCount; ++j) {
            done[j] = 1;
            out.back().patches.push_back(j);
        }
    }
    for (PatchId j = 0; j < scene.size(); ++j) {
        if (done[j] || scene.patches[j].specular <= 0.0) continue;
        const PolygonMeasures m = add(scene.polygon(j), scene.patches[j].specular);
        out.back().patches.push_back(j);
        if (!(m.area > 0.0)) {
            out.pop_back();  // a degenerate patch reflects nothing
            continue;
        }
        if (m.planarDeviation > flat) return describe(j, "not planar");
        if (!m.convex) return describe(j, "not convex");
    }
    return {};
}

void clipToCone(const Vec3& apex, const std::vector<Vec3>& aperture, std::vector<Vec3>& polygon,
                std::vector<Vec3>& scratch) {
    const Vec3 middle = vertexMean(aperture.data(), aperture.size());
    for (std::size_t k = 0; k < aperture.size() && !polygon.empty(); ++k) {
        const Vec3& a = aperture[k];
        const Vec3& b = aperture[(k + 1) % aperture.size()];
        Vec3 n = (a - apex).cross(b - apex);
        if (n.dot(middle - apex) < 0.0) n = -n;
        clipAbovePlane(apex, n, polygon.data(), polygon.size(), scratch);
        polygon.swap(scratch);
    }
}

bool partlyInFront(const Reflector& m, const std::vector<Vec3>& polygon) {
    const double tolerance = 1e-9 * std::max(m.radius, 1e-300);
    for (const Vec3& p : polygon)
        if (m.normal.dot(p) - m.offset > tolerance) return true;
    return false;
}

}  // namespace hemirad
