// Following a ray through its chain of mirror reflections (Sillion & Puech 1989), shared by the
// hemisphere back end and the hemicube's ray-traced mirror variant.
#pragma once

#include "engine/scene.hpp"
#include "rays/ray_scene.hpp"

#include <cstdint>

namespace hemirad {

struct MirrorChainLimits {
    std::uint32_t maxDepth = 8;
    double minWeight = 1e-4;  ///< relative to the weight the chain started with
};

/// The ray origin + t dir has hit mirror patch `mirror` (its full weight already deposited there).
/// Reflects it again and again: each patch reached gets deposit(patch, weight x the product of the
/// s met); the chain ends on a diffuse patch, a miss or back face (lost), or at the limits (cut off).
/// `weight` is in the deposit's units; `toRow` converts them to fractions of the row for `counts`,
/// any struct with bounces, misses, backfaces, lostWeight and cutoffWeight (e.g. RayCounts).
template <class Deposit, class Counts>
void followMirrorChain(const Scene& scene, const RayScene& rays, Vec3 origin, Vec3 dir, PatchId mirror, float t,
                       double weight, double toRow, const MirrorChainLimits& limits, Deposit&& deposit, Counts& counts) {
    const double start = weight;
    for (std::uint32_t depth = 1;; ++depth) {
        const Patch& m = scene.patches[mirror];
        weight *= m.specular;
        if (depth > limits.maxDepth || weight < limits.minWeight * start) {
            counts.cutoffWeight += weight * toRow;
            return;
        }
        const Vec3 hitPoint = origin + double(t) * dir;
        dir = (dir - 2.0 * dir.dot(m.normal) * m.normal).normalized();
        origin = hitPoint + rays.originOffset() * m.normal;
        const RayScene::Hit hit = rays.intersect(origin, dir);
        ++counts.bounces;
        if (hit.patch == RayScene::kNoHit) {
            ++counts.misses;
            counts.lostWeight += weight * toRow;
            return;
        }
        const Patch& receiver = scene.patches[hit.patch];
        if (dir.dot(receiver.normal) >= 0.0) {
            ++counts.backfaces;
            counts.lostWeight += weight * toRow;
            return;
        }
        deposit(hit.patch, weight);
        if (receiver.specular <= 0.0) return;
        mirror = hit.patch;
        t = hit.t;
    }
}

}  // namespace hemirad
