// Hemicube back end: worker threads, each with its own GL context and renderer.
#include "preprocess/hemicube/hemicube_backend.hpp"

#include "engine/error.hpp"
#include "engine/threads.hpp"
#include "preprocess/backend_registry.hpp"
#include "gl/gl_api.hpp"
#include "gl/gl_context.hpp"
#include "preprocess/hemicube/hemicube_renderer.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"
#include "preprocess/row_accumulator.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

namespace hemirad {
namespace {

/// Hemicubes per pass on a software renderer (llvmpipe): see bench/BENCHMARKS.md.
constexpr std::uint32_t kSoftwareLayers = 1;

}  // namespace

bool isSoftwareRenderer(std::string_view renderer) {
    for (const std::string_view name : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer"})
        if (renderer.find(name) != std::string_view::npos) return true;
    return false;
}

int hemicubeWorkers(std::string_view renderer, int requested, int cores) {
    if (requested > 0) return requested;
    return isSoftwareRenderer(renderer) ? std::max(1, cores) : 1;
}

std::uint32_t hemicubeLayers(std::string_view renderer, std::uint32_t requested, std::uint32_t resolution,
                             std::size_t patches, bool gpuReduction, std::uint32_t points, std::uint32_t maxLayers) {
    const std::uint32_t wanted = requested > 0 ? requested : isSoftwareRenderer(renderer) ? kSoftwareLayers : 256u;
    if (wanted <= 1) return 1;
    // Per layer: ids and depth, the read-back copy; the GPU reduction's dense row, touched list and pairs.
    const double pixels = 3.0 * resolution * resolution;
    const double capacity = std::min(double(patches), pixels);
    const double bytes = 12.0 * pixels + (gpuReduction ? 4.0 * double(patches) + 12.0 * capacity + 20.0 : 0.0);
    const auto fit = std::uint32_t(std::clamp(256.0 * 1024 * 1024 / bytes, 1.0, 65536.0));
    const std::uint32_t layers = std::min({wanted, fit, std::max(1u, maxLayers)});
    return layers <= 1 ? 1 : std::max(layers, points);
}

HemicubeBackend::HemicubeBackend(const HemicubeOptions& options, const CommonOptions& common)
    : m_options(options), m_common(common) {
    m_layout = std::make_unique<HemicubeLayout>(options.resolution);
    if (options.origins > 1) gaussLegendre(farOrder(options.origins), m_nodes, m_nodeWeights);
}

HemicubeBackend::~HemicubeBackend() = default;

void HemicubeBackend::prepare(const Scene& scene) {
    m_scene = &scene;
    m_geometry = HemicubeGeometry::build(scene, m_options.parentPolygons);
    if (scene.hasMirrors() && m_options.mirrors == HemicubeMirrors::Rays) m_rays = std::make_unique<RayScene>(scene, m_common.threads);
    // Fail here, before any work, if no context can be made; the renderer decides the worker count.
    auto context = createHeadlessContext(m_options.gl);
    context->makeCurrent();
    const auto* renderer = reinterpret_cast<const char*>(gl::GetString(GL_RENDERER));
    m_renderer = renderer ? renderer : "unknown";
    GLint maxLayers = 1;
    gl::GetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    context->release();
    m_workers = hemicubeWorkers(m_renderer, m_common.threads, resolveThreads(0));
    m_points = originPoints(m_options.origins);
    // Mirrors go row by row: their portal passes depend on what each hemicube saw.
    m_layers = scene.hasMirrors() ? 1
                                  : hemicubeLayers(m_renderer, m_options.batch, m_options.resolution, scene.size(),
                                                   m_options.reduce == Reduction::Gpu, m_points, std::uint32_t(maxLayers));
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
            {"origins", std::to_string(m_points)},
            {"batch", std::to_string(m_layers) + (m_layers == 1 && m_scene->hasMirrors() ? " (mirrors: row by row)" : "")},
            {"reduce", text("--reduce")},
            {"gl", text("--gl")},
            {"gl_renderer", m_renderer},
            {"parent_polygons", m_geometry.patchesInParents ? "yes" : "no"},
            {"delta_form_factors", "Cohen-Greenberg, normalised"}};
}

std::string HemicubeBackend::device() const {
    return m_renderer + ", " + std::to_string(m_workers) + (m_workers == 1 ? " GL context" : " GL contexts") +
           (m_common.threads > 0                ? " (--threads)"
            : isSoftwareRenderer(m_renderer) ? " (software renderer: one per core)"
                                             : " (GPU: one context)") +
           ", " + std::to_string(m_layers) + (m_layers == 1 ? " hemicube per pass" : " hemicubes per pass");
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
                HemicubeRenderer renderer(*m_scene, m_geometry, *m_layout, reduction, limits, m_layers);
                RowAccumulator row(m_scene->size(), RowAccumulator::Mode::Weights);
                HemicubeStats stats;
                auto rowDone = [&](PatchId i) {
                    const auto t0 = std::chrono::steady_clock::now();
                    builder.setRow(i, row.take(1.0));
                    stats.collect += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                };
                std::vector<Vec3> corners, points;
                std::vector<double> weights;
                // The hemicubes of row i: its centroid, or the --origins rule's points.
                auto origins = [&](PatchId i) {
                    const Patch& p = m_scene->patches[i];
                    points.clear();
                    weights.clear();
                    if (m_nodes.empty()) {
                        points.push_back(p.centroid);
                        weights.push_back(1.0);
                        return;
                    }
                    corners.clear();
                    for (std::uint32_t k = 0; k < p.cornerCount; ++k) corners.push_back(m_scene->corner(p, k));
                    polygonQuadrature(corners.data(), corners.size(), m_nodes, m_nodeWeights, points, weights);
                };
                auto stopped = [&] {
                    std::lock_guard<std::mutex> lock(failureMutex);
                    return failure || builder.cancelled();
                };
                PatchId i = 0;
                if (m_layers == 1) {  // row by row; scenes with mirrors take this path
                    while (!stopped() && rows.next(i)) {
                        origins(i);
                        for (std::size_t k = 0; k < points.size(); ++k)
                            renderer.computeRow(i, points[k], weights[k], row, stats);
                        rowDone(i);
                    }
                } else {
                    // Whole rows into passes of up to m_layers hemicubes (m_layers >= a row's points);
                    // a row that does not fit waits for the next pass.
                    std::vector<HemicubeItem> batch;
                    bool pending = false, more = true;
                    while (!stopped() && (more || pending)) {
                        batch.clear();
                        for (;;) {
                            if (!pending) {
                                if (!(more = more && rows.next(i))) break;
                                origins(i);
                                pending = true;
                            }
                            if (batch.size() + points.size() > m_layers) break;
                            for (std::size_t k = 0; k < points.size(); ++k) batch.push_back({i, points[k], weights[k]});
                            pending = false;
                        }
                        if (batch.empty() && pending)
                            throw Error("internal: a row's " + std::to_string(points.size()) + " hemicubes exceed a pass of " +
                                        std::to_string(m_layers));
                        if (!batch.empty()) renderer.computeBatch(batch, row, rowDone, stats);
                    }
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
