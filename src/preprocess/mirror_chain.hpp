// Following a ray through its chain of mirror reflections (Sillion & Puech 1989), shared by the
// hemisphere back end and the hemicube's ray-traced mirror variant.
#pragma once

#include "engine/scene.hpp"
#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemisphere/embree_scene.hpp"
#include "preprocess/row_accumulator.hpp"

namespace hemirad {

struct MirrorChainLimits {
    std::uint32_t maxDepth = 8;
    double minWeight = 1e-4;  ///< relative to the weight the chain started with
};

/// The ray origin + t dir has hit mirror patch `mirror` (its full weight already deposited there).
/// Reflects it again and again: each patch reached gets weight x (product of the s met); the chain
/// ends on a diffuse patch, a miss or back face (lost), or at the limits (cut off). `weight` is in
/// the accumulator's units; `toRow` converts them to fractions of the row for `counts`.
void followMirrorChain(const Scene& scene, const RayScene& rays, Vec3 origin, Vec3 dir, PatchId mirror, float t,
                       double weight, double toRow, const MirrorChainLimits& limits, RowAccumulator& row,
                       RayCounts& counts);

}  // namespace hemirad
