// Scenes and closed forms for the thermal tests: explicit F from closed-form factors, faceted
// spheres (subdivided icosahedra), the two-surface and three-surface networks (Siegel & Howell).
#pragma once

#include "support.hpp"

#include "engine/form_factors.hpp"
#include "thermal/thermal_model.hpp"

#include <array>
#include <map>

namespace hemirad::test {

/// F from dense rows (double values stored as F stores them, in float).
inline FormFactors denseF(const std::vector<std::vector<double>>& rows) {
    std::vector<std::vector<FormFactors::Entry>> entries(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t j = 0; j < rows[i].size(); ++j)
            if (rows[i][j] != 0.0) entries[i].push_back({std::uint32_t(j), rows[i][j]});
    return FormFactors::fromRows(std::move(entries), std::vector<std::uint8_t>(rows.size(), 1));
}

/// Appends a sphere of `radius` about `centre` as a subdivided icosahedron (20 * 4^level triangles),
/// normals outward or inward, under object `object` and material `material`.
inline void addSphere(Scene& scene, const Vec3& centre, double radius, int level, bool outward, std::uint32_t object,
                      std::uint32_t material) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                                   {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                   {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                                   {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (Vec3& p : v) p.normalize();
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto middle = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back((v[a] + v[b]).normalized());
            return mid[key] = std::uint32_t(v.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> next;
        for (const auto& tri : f) {
            const std::uint32_t ab = middle(tri[0], tri[1]), bc = middle(tri[1], tri[2]), ca = middle(tri[2], tri[0]);
            next.push_back({tri[0], ab, ca});
            next.push_back({tri[1], bc, ab});
            next.push_back({tri[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        f = std::move(next);
    }
    const std::uint32_t base = std::uint32_t(scene.vertices.size());
    for (const Vec3& p : v) scene.vertices.push_back(centre + radius * p);
    for (const auto& tri : f) {
        std::vector<std::uint32_t> ids = {base + tri[0], base + tri[1], base + tri[2]};
        if (!outward) std::swap(ids[1], ids[2]);
        scene.addPatch(ids, material, object);
    }
}

/// Sum of the areas of an object's patches.
inline double objectArea(const Scene& scene, std::uint32_t object) {
    double a = 0.0;
    for (const Patch& p : scene.patches) a += p.object == object ? p.area : 0.0;
    return a;
}

/// sigma T^4.
inline double blackbody(double T) { return thermal::kStefanBoltzmann * T * T * T * T; }

}  // namespace hemirad::test
