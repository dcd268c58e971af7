// Hemisphere back end. Rows run in parallel (OpenMP); each thread accumulates a dense row.
#include "preprocess/hemisphere/hemisphere_backend.hpp"

#include "engine/error.hpp"
#include "preprocess/hemisphere/beckers.hpp"
#include "preprocess/hemisphere/patch_sampler.hpp"
#include "preprocess/mirror_chain.hpp"
#include "preprocess/row_accumulator.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

namespace hemirad {

/// Per-thread scratch: the row being accumulated and the rotated directions and their hits.
struct HemisphereBackend::Workspace {
    Workspace(std::size_t patches, bool mirrors)
        : row(patches, mirrors ? RowAccumulator::Mode::Weights : RowAccumulator::Mode::Counts) {}
    RowAccumulator row;
    std::vector<float> jittered;  // this origin's cell directions when jittering
    std::vector<float> dirs;
    std::vector<PatchId> hits;
    std::vector<float> distances;
};

HemisphereBackend::HemisphereBackend(const BackendOptions& options) : m_options(options) {
    m_directions = beckersDirections(options.samples);
    m_rings = beckersDiskCounts(options.samples);
}

HemisphereBackend::~HemisphereBackend() = default;

void HemisphereBackend::prepare(const Scene& scene) {
    m_scene = &scene;
    m_rays = std::make_unique<RayScene>(scene, m_options.threads);
    m_normals.resize(3 * scene.size());
    for (PatchId i = 0; i < scene.size(); ++i)
        for (int k = 0; k < 3; ++k) m_normals[3 * i + k] = static_cast<float>(scene.patches[i].normal[k]);
    m_mirrors = scene.hasMirrors();
}

std::map<std::string, std::string> HemisphereBackend::parameters() const {
    return {{"method", "hemisphere"},
            {"row_sum_bound", rowSumBoundText(*m_scene, m_options.maxDepth, m_options.minWeight)},
            {"samples", std::to_string(m_options.samples)},
            {"origins", std::to_string(m_options.origins)},
            {"max_depth", std::to_string(m_options.maxDepth)},
            {"min_weight", std::to_string(m_options.minWeight)},
            {"seed", std::to_string(m_options.seed)},
            {"directions", std::string(m_options.jitter ? "beckers-disk jittered in cells" : "beckers-disk area-median") +
                               (m_options.fixedDirections ? ", fixed" : ", rotated per origin")}};
}

void HemisphereBackend::computeRows(const std::vector<PatchId>& rows, FormFactorBuilder& builder) {
    if (!m_scene) throw Error("hemisphere back end: prepare() was not called");
    const int threads = m_options.threads > 0 ? m_options.threads : omp_get_max_threads();
    std::exception_ptr failure;
    const auto count = static_cast<std::ptrdiff_t>(rows.size());
#pragma omp parallel num_threads(threads)
    {
        Workspace ws(m_scene->size(), m_mirrors);
        ws.dirs.resize(m_directions.size());
        ws.hits.resize(m_options.samples);
        ws.distances.resize(m_options.samples);
        RayCounts counts;
#pragma omp for schedule(dynamic, 4)
        for (std::ptrdiff_t r = 0; r < count; ++r) {
            if (builder.cancelled() || failure) continue;
            try {
                const PatchId i = rows[r];
                if (m_mirrors) computeRow<true>(i, ws, counts);
                else computeRow<false>(i, ws, counts);
                const double scale = 1.0 / (double(m_options.origins) * m_options.samples);
                builder.setRow(i, ws.row.take(scale));
            } catch (...) {
#pragma omp critical(hemirad_failure)
                if (!failure) failure = std::current_exception();
            }
        }
        builder.addCounts(counts);
    }
    if (failure) std::rethrow_exception(failure);
}

template <bool Mirrors>
void HemisphereBackend::computeRow(PatchId i, Workspace& ws, RayCounts& counts) const {
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
            if (j == RayScene::kNoHit) {
                ++counts.misses;
                ++lost;
                continue;
            }
            const float* d = &ws.dirs[3 * k];
            const float* n = &m_normals[3 * j];
            if (d[0] * n[0] + d[1] * n[1] + d[2] * n[2] >= 0.0f) {
                ++counts.backfaces;
                ++lost;
                continue;
            }
            if constexpr (Mirrors) {
                ws.row.addWeight(j, 1.0);
                if (m_scene->patches[j].specular > 0.0)
                    followMirrorChain(*m_scene, *m_rays, lifted, Vec3(d[0], d[1], d[2]), j, ws.distances[k], 1.0,
                                      rowWeight, {m_options.maxDepth, m_options.minWeight}, ws.row, counts);
            } else {
                ws.row.addCount(j);
            }
        }
    }
    counts.rays += std::uint64_t(N) * origins.size();
    counts.lostWeight += double(lost) * rowWeight;
}

}  // namespace hemirad
