// Mesh neighbours of the analytic estimator's patches (silhouettes, merged blockers).
#include "preprocess/hemisphere/patch_geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

namespace hemirad {

void PatchGeometry::buildNeighbours(const Scene& scene) {
    // Patches sharing a corner position, within a tolerance of the scene's scale: generators repeat
    // vertices and compute shared corners by different float expressions (0.1 * 3 != 0.3).
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const double tolerance = std::max(1e-9 * (hi - lo).norm(), 1e-300);
    auto cell = [&](const Vec3& p) {
        return std::array<std::int64_t, 3>{std::llround(p.x() / tolerance / 4), std::llround(p.y() / tolerance / 4),
                                           std::llround(p.z() / tolerance / 4)};
    };
    struct Hash {
        std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
            return std::size_t(k[0]) * 0x9e3779b97f4a7c15ULL ^ std::size_t(k[1]) * 0xc2b2ae3d27d4eb4fULL ^ std::size_t(k[2]);
        }
    };
    // Cells 4 tolerances wide: two corners within the tolerance lie in the same or adjacent cells.
    std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::pair<PatchId, Vec3>>, Hash> grid;
    for (PatchId j = 0; j < scene.size(); ++j)
        for (std::uint32_t k = 0; k < shapes[j].count; ++k) {
            const Vec3& p = corners[shapes[j].first + k];
            grid[cell(p)].emplace_back(j, p);
        }
    std::vector<std::vector<PatchId>> lists(scene.size());
    for (PatchId j = 0; j < scene.size(); ++j)
        for (std::uint32_t k = 0; k < shapes[j].count; ++k) {
            const Vec3& p = corners[shapes[j].first + k];
            const auto c = cell(p);
            for (std::int64_t dx = -1; dx <= 1; ++dx)
                for (std::int64_t dy = -1; dy <= 1; ++dy)
                    for (std::int64_t dz = -1; dz <= 1; ++dz) {
                        const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
                        if (it == grid.end()) continue;
                        for (const auto& [other, q] : it->second)
                            if (other != j && (q - p).norm() <= tolerance) lists[j].push_back(other);
                    }
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
