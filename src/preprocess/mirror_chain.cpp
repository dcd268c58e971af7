// Mirror chains.
#include "preprocess/mirror_chain.hpp"

namespace hemirad {

void followMirrorChain(const Scene& scene, const RayScene& rays, Vec3 origin, Vec3 dir, PatchId mirror, float t,
                       double weight, double toRow, const MirrorChainLimits& limits, RowAccumulator& row,
                       RayCounts& counts) {
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
        row.addWeight(hit.patch, weight);
        if (receiver.specular <= 0.0) return;
        mirror = hit.patch;
        t = hit.t;
    }
}

}  // namespace hemirad
