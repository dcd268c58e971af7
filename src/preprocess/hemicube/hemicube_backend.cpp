// Hemicube back end: worker threads, each with its own GL context and renderer.
#include "preprocess/hemicube/hemicube_backend.hpp"

#include "engine/error.hpp"
#include "engine/threads.hpp"
#include "preprocess/backend_registry.hpp"
#include "gl/gl_context.hpp"
#include "preprocess/hemicube/hemicube_renderer.hpp"
#include "preprocess/row_accumulator.hpp"

#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

namespace hemirad {

HemicubeBackend::HemicubeBackend(const HemicubeOptions& options, const CommonOptions& common)
    : m_options(options), m_common(common) {
    m_layout = std::make_unique<HemicubeLayout>(options.resolution);
}

HemicubeBackend::~HemicubeBackend() = default;

void HemicubeBackend::prepare(const Scene& scene) {
    m_scene = &scene;
    m_geometry = HemicubeGeometry::build(scene, m_options.parentPolygons);
    if (scene.hasMirrors() && m_options.mirrors == HemicubeMirrors::Rays) m_rays = std::make_unique<RayScene>(scene, m_common.threads);
    m_workers = resolveThreads(m_common.threads);
    // Fail here, before any work, if no context can be made.
    auto context = createHeadlessContext(m_options.gl);
    context->makeCurrent();
    context->release();
}

FormFactorProvenance HemicubeBackend::provenance() const {
    FormFactorProvenance p;
    p.method = HemicubeOptions::kMethod;
    p.rowSumBound = extendedRowSumBound(*m_scene, m_common.maxDepth, m_common.minWeight);
    return p;
}

std::map<std::string, std::string> HemicubeBackend::parameters() const {
    const MethodSettings settings = MethodSettings::of(m_options, m_common);
    auto text = [&](const char* flag) { return hemicubeDescriptor().option(flag)->get(settings); };
    return {{"max_depth", std::to_string(m_common.maxDepth)},
            {"mirrors", text("--mirrors")},
            {"min_weight", std::to_string(m_common.minWeight)},
            {"resolution", std::to_string(m_options.resolution)},
            {"reduce", text("--reduce")},
            {"gl", text("--gl")},
            {"parent_polygons", m_geometry.patchesInParents ? "yes" : "no"},
            {"delta_form_factors", "Cohen-Greenberg, normalised"}};
}

void HemicubeBackend::computeRows(RowSource& rows, FormFactorBuilder& builder) {
    if (!m_scene) throw Error("hemicube back end: prepare() was not called");
    const Reduction reduction = m_options.reduce;
    const GlApiKind api = m_options.gl;
    std::exception_ptr failure;
    std::mutex failureMutex;
    HemicubeStats total;
    std::mutex totalMutex;
    auto worker = [&] {
        try {
            auto context = createHeadlessContext(api);
            context->makeCurrent();
            {
                const MirrorLimits limits{m_common.maxDepth, m_common.minWeight, m_rays.get()};
                HemicubeRenderer renderer(*m_scene, m_geometry, *m_layout, reduction, limits);
                RowAccumulator row(m_scene->size(), RowAccumulator::Mode::Weights);
                HemicubeStats stats;
                PatchId i = 0;
                for (;;) {
                    {
                        std::lock_guard<std::mutex> lock(failureMutex);
                        if (failure) break;
                    }
                    if (builder.cancelled() || !rows.next(i)) break;
                    renderer.computeRow(i, row, stats);
                    const auto t0 = std::chrono::steady_clock::now();
                    builder.setRow(i, row.take(1.0));
                    stats.collect += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                }
                std::lock_guard<std::mutex> lock(totalMutex);
                total += stats;
            }
            context->release();
        } catch (...) {
            std::lock_guard<std::mutex> lock(failureMutex);
            if (!failure) failure = std::current_exception();
        }
    };
    const int workers = std::max(1, std::min<int>(m_workers, int(std::min<std::size_t>(rows.sizeHint(), 1u << 20))));
    std::vector<std::thread> threads;
    for (int w = 1; w < workers; ++w) threads.emplace_back(worker);
    worker();
    for (std::thread& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
    RayCounts counts;
    counts.rays = total.pixels;
    counts.misses = total.missed;
    counts.backfaces = total.backfaces;
    counts.lostWeight = total.lostWeight;
    counts.cutoffWeight = total.cutoffWeight;
    counts.bounces = total.portals;
    builder.addCounts(counts);
    builder.addStageSeconds("hemicube render", total.render);
    builder.addStageSeconds("hemicube readback", total.readback);
    builder.addStageSeconds("hemicube reduce", total.reduce);
    builder.addStageSeconds("row collect", total.collect);
    if (m_scene->hasMirrors())
        builder.addStageSeconds(m_options.mirrors == HemicubeMirrors::Rays ? "mirror rays" : "mirror portals", total.mirrors);
}

}  // namespace hemirad
