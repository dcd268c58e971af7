// Mesh neighbours of the analytic estimator's patches (silhouettes, merged blockers).
#include "preprocess/hemisphere/patch_geometry.hpp"

#include "preprocess/hemisphere/point_grid.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

void PatchGeometry::buildNeighbours(const Scene& scene) {
    // Patches sharing a corner position, within a tolerance of the scene's scale: generators repeat
    // vertices and compute shared corners by different float expressions (0.1 * 3 != 0.3).
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const double tolerance = std::max(1e-9 * (hi - lo).norm(), 1e-300);
    PointGrid<std::pair<PatchId, Vec3>> grid(tolerance);
    for (PatchId j = 0; j < scene.size(); ++j)
        for (std::uint32_t k = 0; k < shapes[j].count; ++k) {
            const Vec3& p = corners[shapes[j].first + k];
            grid.add(p, {j, p});
        }
    std::vector<std::vector<PatchId>> lists(scene.size());
    for (PatchId j = 0; j < scene.size(); ++j)
        for (std::uint32_t k = 0; k < shapes[j].count; ++k) {
            const Vec3& p = corners[shapes[j].first + k];
            grid.nearby(p, [&](const std::pair<PatchId, Vec3>& item) {
                if (item.first != j && (item.second - p).norm() <= tolerance) lists[j].push_back(item.first);
            });
        }
    neighbourStart.assign(1, 0);
    neighbours.clear();
    for (std::vector<PatchId>& list : lists) {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        neighbours.insert(neighbours.end(), list.begin(), list.end());
        neighbourStart.push_back(static_cast<std::uint32_t>(neighbours.size()));
    }
    // An edge is shared when a neighbour has corners at both of its ends.
    auto hasCorner = [&](PatchId o, const Vec3& p) {
        for (std::uint32_t k = 0; k < shapes[o].count; ++k)
            if ((corners[shapes[o].first + k] - p).norm() <= tolerance) return true;
        return false;
    };
    openEdge.assign(scene.size(), 0);
    for (PatchId j = 0; j < scene.size(); ++j) {
        const std::uint32_t count = shapes[j].count;
        for (std::uint32_t k = 0; k < count && !openEdge[j]; ++k) {
            const Vec3& a = corners[shapes[j].first + k];
            const Vec3& b = corners[shapes[j].first + (k + 1) % count];
            bool shared = false;
            for (std::uint32_t e = neighbourStart[j]; e < neighbourStart[j + 1] && !shared; ++e)
                shared = hasCorner(neighbours[e], a) && hasCorner(neighbours[e], b);
            openEdge[j] = !shared;
        }
    }
}

}  // namespace hemirad
