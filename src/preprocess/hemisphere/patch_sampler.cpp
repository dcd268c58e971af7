// Stratified origins on patches.
#include "preprocess/hemisphere/patch_sampler.hpp"

#include "preprocess/hemisphere/point_polygon.hpp"

#include <cmath>

namespace hemirad {

std::vector<Vec3> patchOrigins(const Scene& scene, PatchId id, std::uint32_t K, Random& random) {
    const Patch& p = scene.patches[id];
    if (K <= 1) return {p.centroid};
    const std::vector<Vec3> c = scene.polygon(id);
    const double shiftU = random.uniform(), shiftV = random.uniform();
    constexpr double kGolden = 0.61803398874989484820;  // generator of the Fibonacci lattice
    std::vector<Vec3> out;
    out.reserve(K);
    for (std::uint32_t k = 0; k < K; ++k)
        out.push_back(pointOnPolygon(c.data(), c.size(), std::fmod((k + 0.5) / K + shiftU, 1.0),
                                     std::fmod(k * kGolden + shiftV, 1.0)));
    return out;
}

}  // namespace hemirad
