// The convexity test behind skipping shadow rays: every patch plane against every corner, by plane.
#include "preprocess/hemisphere/obstruction.hpp"

#include "engine/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace hemirad {

std::vector<std::uint8_t> obstructingPatches(const Scene& scene, double budget) {
    std::vector<std::uint8_t> flags(scene.size(), 0);
    if (scene.size() < 2) return flags;
    const double tolerance = 1e-9 * scene.extent();
    // Distinct planes (normal, offset) within the tolerance: a subdivided wall is one plane.
    struct Plane {
        Vec3 normal;
        double offset;
    };
    struct Hash {
        std::size_t operator()(const std::array<std::int64_t, 4>& k) const {
            return std::size_t(k[0]) * 0x9e3779b97f4a7c15ULL ^ std::size_t(k[1]) * 0xc2b2ae3d27d4eb4fULL ^
                   std::size_t(k[2]) * 0x165667b19e3779f9ULL ^ std::size_t(k[3]);
        }
    };
    std::unordered_map<std::array<std::int64_t, 4>, std::uint32_t, Hash> index;
    std::vector<Plane> planes;
    std::vector<std::uint32_t> planeOf(scene.size());
    for (PatchId j = 0; j < scene.size(); ++j) {
        const Patch& p = scene.patches[j];
        const double offset = p.normal.dot(p.centroid);
        const std::array<std::int64_t, 4> key{std::llround(p.normal.x() * 1e9), std::llround(p.normal.y() * 1e9),
                                              std::llround(p.normal.z() * 1e9),
                                              std::llround(offset / std::max(tolerance, 1e-300))};
        const auto [it, added] = index.try_emplace(key, std::uint32_t(planes.size()));
        if (added) planes.push_back({p.normal, offset});
        planeOf[j] = it->second;
        // A patch that is not flat has corners on both sides of its own plane: a blocker below.
    }
    std::vector<std::uint32_t> used(scene.corners.begin(), scene.corners.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const std::uint32_t v : used) {
        lo = lo.cwiseMin(scene.vertices[v]);
        hi = hi.cwiseMax(scene.vertices[v]);
    }
    const Vec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    const bool scan = double(planes.size()) * double(used.size()) <= budget;
    std::vector<std::uint8_t> blocks(planes.size(), 0);
    const auto count = static_cast<std::ptrdiff_t>(planes.size());
#pragma omp parallel for schedule(dynamic, 16)
    for (std::ptrdiff_t k = 0; k < count; ++k) {
        const Plane& plane = planes[std::size_t(k)];
        // The bounding box's extreme heights above the plane: one side only means no blocker.
        const double middle = plane.normal.dot(centre) - plane.offset, reach = plane.normal.cwiseAbs().dot(half);
        if (middle - reach >= -tolerance || middle + reach <= tolerance) continue;
        if (!scan) {
            blocks[std::size_t(k)] = 1;
            continue;
        }
        bool behind = false, front = false;
        for (const std::uint32_t v : used) {
            const double h = plane.normal.dot(scene.vertices[v]) - plane.offset;
            behind = behind || h < -tolerance;
            front = front || h > tolerance;
            if (behind && front) break;
        }
        blocks[std::size_t(k)] = behind && front;
    }
    for (PatchId j = 0; j < scene.size(); ++j) flags[j] = blocks[planeOf[j]];
    return flags;
}

bool somePatchCanObstruct(const Scene& scene, double budget) {
    const std::vector<std::uint8_t> flags = obstructingPatches(scene, budget);
    return std::find(flags.begin(), flags.end(), 1) != flags.end();
}

}  // namespace hemirad
