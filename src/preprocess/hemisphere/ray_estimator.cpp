#include "preprocess/hemisphere/ray_estimator.hpp"

#include "preprocess/hemisphere/beckers.hpp"
#include "preprocess/hemisphere/patch_sampler.hpp"
#include "rays/mirror_chain.hpp"

#include <cmath>

namespace hemirad {

RayEstimator::RayEstimator(const HemisphereOptions& options, const CommonOptions& common)
    : m_options(options), m_common(common) {
    m_directions = beckersDirections(options.samples);
    m_rings = beckersDiskCounts(options.samples);
}

void RayEstimator::prepare(const Scene& scene, const RayScene& rays) {
    m_scene = &scene;
    m_rays = &rays;
    m_mirrors = scene.hasMirrors();
    m_normals.resize(3 * scene.size());
    for (PatchId i = 0; i < scene.size(); ++i)
        for (int k = 0; k < 3; ++k) m_normals[3 * i + k] = static_cast<float>(scene.patches[i].normal[k]);
}

RayEstimator::Workspace RayEstimator::workspace() const {
    Workspace ws;
    ws.dirs.resize(m_directions.size());
    ws.hits.resize(m_options.samples);
    ws.distances.resize(m_options.samples);
    return ws;
}

void RayEstimator::addRow(PatchId i, Deposit deposit, RowAccumulator& row, Workspace& ws, RayCounts& counts) const {
    if (deposit == Deposit::MirrorChainsOnly) castRays<true, false>(i, row, ws, counts);
    else if (m_mirrors) castRays<true, true>(i, row, ws, counts);
    else castRays<false, true>(i, row, ws, counts);
}

template <bool Mirrors, bool Direct>
void RayEstimator::castRays(PatchId i, RowAccumulator& row, Workspace& ws, RayCounts& counts) const {
    const Patch& patch = m_scene->patches[i];
    const std::uint32_t N = m_options.samples;
    Random random(m_options.seed * 0x9e3779b97f4a7c15ULL ^ (std::uint64_t(i) << 20));
    const std::vector<Vec3> origins = patchOrigins(*m_scene, i, m_options.origins, random);
    Vec3 t, b;
    orthonormalBasis(patch.normal, t, b);
    const double rowWeight = 1.0 / (double(m_options.origins) * N);
    std::uint64_t lost = 0;
    for (const Vec3& point : origins) {
        // A random rotation of the pattern about the normal per origin breaks aliasing between origins.
        const double angle = m_options.fixedDirections ? 0.0 : 2.0 * kPi * random.uniform();
        const Vec3 tr = std::cos(angle) * t + std::sin(angle) * b;
        const Vec3 br = patch.normal.cross(tr);
        const float T[3] = {float(tr.x()), float(tr.y()), float(tr.z())};
        const float Bv[3] = {float(br.x()), float(br.y()), float(br.z())};
        const float Nn[3] = {float(patch.normal.x()), float(patch.normal.y()), float(patch.normal.z())};
        const float* base = m_directions.data();
        if (m_options.jitter) {
            ws.jittered.resize(m_directions.size());
            beckersJitteredDirections(m_rings, [&] { return random.uniform(); }, ws.jittered.data());
            base = ws.jittered.data();
        }
        for (std::uint32_t k = 0; k < N; ++k) {
            const float* d = base + 3 * k;
            for (int c = 0; c < 3; ++c) ws.dirs[3 * k + c] = d[0] * T[c] + d[1] * Bv[c] + d[2] * Nn[c];
        }
        const Vec3 lifted = point + m_rays->originOffset() * patch.normal;
        float o[3];
        m_rays->toLocal(lifted, o);
        if (Mirrors) m_rays->intersectFan(o, ws.dirs.data(), N, ws.hits.data(), ws.distances.data());
        else m_rays->intersectFan(o, ws.dirs.data(), N, ws.hits.data());
        for (std::uint32_t k = 0; k < N; ++k) {
            const PatchId j = ws.hits[k];
            if constexpr (!Direct) {  // only mirror chains: the analytic estimator has the rest
                if (j == RayScene::kNoHit || m_scene->patches[j].specular <= 0.0) continue;
            }
            if (j == RayScene::kNoHit) {
                ++counts.misses;
                ++lost;
                continue;
            }
            const float* d = &ws.dirs[3 * k];
            const float* n = &m_normals[3 * j];
            if (d[0] * n[0] + d[1] * n[1] + d[2] * n[2] >= 0.0f) {
                if constexpr (!Direct) continue;
                ++counts.backfaces;
                ++lost;
                continue;
            }
            if constexpr (Mirrors) {
                if constexpr (Direct) row.addWeight(j, 1.0);
                if (m_scene->patches[j].specular > 0.0)
                    followMirrorChain(*m_scene, *m_rays, lifted, Vec3(d[0], d[1], d[2]), j, ws.distances[k], 1.0,
                                      rowWeight, {m_common.maxDepth, m_common.minWeight},
                                      [&row](PatchId p, double w) { row.addWeight(p, w); }, counts);
            } else {
                row.addCount(j);
            }
        }
    }
    counts.rays += std::uint64_t(N) * origins.size();
    counts.lostWeight += double(lost) * rowWeight;
}

}  // namespace hemirad
