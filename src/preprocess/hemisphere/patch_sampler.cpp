// Stratified origins on patches.
#include "preprocess/hemisphere/patch_sampler.hpp"

#include <cmath>

namespace hemirad {
namespace {

/// Area-uniform map of the unit square onto triangle (a, b, c) by folding the upper half.
Vec3 onTriangle(const Vec3& a, const Vec3& b, const Vec3& c, double u, double v) {
    if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
    }
    return a + u * (b - a) + v * (c - a);
}

}  // namespace

std::vector<Vec3> patchOrigins(const Scene& scene, PatchId id, std::uint32_t K, Random& random) {
    const Patch& p = scene.patches[id];
    if (K <= 1) return {p.centroid};
    const std::vector<Vec3> c = scene.polygon(id);
    const double shiftU = random.uniform(), shiftV = random.uniform();
    constexpr double kGolden = 0.61803398874989484820;  // generator of the Fibonacci lattice
    const bool parallelogram =
        c.size() == 4 && (c[0] + c[2] - c[1] - c[3]).norm() <= 1e-9 * (c[2] - c[0]).norm();
    std::vector<double> cumulative;
    if (!parallelogram) {
        double sum = 0.0;
        for (std::size_t k = 1; k + 1 < c.size(); ++k) {
            sum += 0.5 * (c[k] - c[0]).cross(c[k + 1] - c[0]).norm();
            cumulative.push_back(sum);
        }
        for (double& value : cumulative) value /= sum;
    }
    std::vector<Vec3> out;
    out.reserve(K);
    for (std::uint32_t k = 0; k < K; ++k) {
        double u = std::fmod((k + 0.5) / K + shiftU, 1.0);
        double v = std::fmod(k * kGolden + shiftV, 1.0);
        if (parallelogram) {
            out.push_back(c[0] + u * (c[1] - c[0]) + v * (c[3] - c[0]));
            continue;
        }
        // u picks the fan triangle by area and is rescaled to [0, 1) within it.
        std::size_t t = 0;
        while (t + 1 < cumulative.size() && u >= cumulative[t]) ++t;
        const double low = t == 0 ? 0.0 : cumulative[t - 1];
        u = (u - low) / (cumulative[t] - low);
        out.push_back(onTriangle(c[0], c[t + 1], c[t + 2], std::min(u, 1.0), v));
    }
    return out;
}

}  // namespace hemirad
