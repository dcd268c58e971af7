// The convexity test behind skipping shadow rays: every patch plane against every corner, by plane.
#include "preprocess/hemisphere/obstruction.hpp"

#include "engine/scene.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <vector>

namespace hemirad {

bool somePatchCanObstruct(const Scene& scene, double budget) {
    if (scene.size() < 2) return false;
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
    std::unordered_set<std::array<std::int64_t, 4>, Hash> seen;
    std::vector<Plane> planes;
    for (const Patch& p : scene.patches) {
        const double offset = p.normal.dot(p.centroid);
        const std::array<std::int64_t, 4> key{std::llround(p.normal.x() * 1e9), std::llround(p.normal.y() * 1e9),
                                              std::llround(p.normal.z() * 1e9),
                                              std::llround(offset / std::max(tolerance, 1e-300))};
        if (seen.insert(key).second) planes.push_back({p.normal, offset});
        // A patch that is not flat has corners behind its own plane: that counts as a blocker below.
    }
    std::vector<std::uint32_t> used(scene.corners.begin(), scene.corners.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    if (double(planes.size()) * double(used.size()) > budget) return true;
    std::atomic<bool> found{false};
    const auto count = static_cast<std::ptrdiff_t>(planes.size());
#pragma omp parallel for schedule(dynamic, 16)
    for (std::ptrdiff_t k = 0; k < count; ++k) {
        if (found.load(std::memory_order_relaxed)) continue;
        const Plane& plane = planes[std::size_t(k)];
        for (const std::uint32_t v : used)
            if (plane.normal.dot(scene.vertices[v]) - plane.offset < -tolerance) {
                found.store(true, std::memory_order_relaxed);
                break;
            }
    }
    return found.load();
}

}  // namespace hemirad
