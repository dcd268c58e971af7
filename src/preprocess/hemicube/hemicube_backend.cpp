// Hemicube back end: worker threads, each with its own GL context and renderer.
#include "preprocess/hemicube/hemicube_backend.hpp"

#include "engine/error.hpp"
#include "engine/threads.hpp"
#include "preprocess/backend_registry.hpp"
#include "gl/gl_api.hpp"
#include "gl/gl_context.hpp"
#include "preprocess/hemicube/hemicube_renderer.hpp"
#include "preprocess/hemicube/hemicube_row_pool.hpp"
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

/// Hemicubes per pass and passes in flight on a software renderer (llvmpipe): see bench/BENCHMARKS.md.
constexpr std::uint32_t kSoftwareLayers = 1;
constexpr std::uint32_t kSoftwareInFlight = 1;

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

Reduction hemicubeReduction(std::string_view renderer, Reduction requested) {
    if (requested != Reduction::Auto) return requested;
    return isSoftwareRenderer(renderer) ? Reduction::Cpu : Reduction::Gpu;
}

bool hemicubeSerializesContexts(std::string_view renderer) { return isSoftwareRenderer(renderer); }

std::uint32_t hemicubeInFlight(std::string_view renderer, std::uint32_t requested) {
    if (requested > 0) return requested;
    return isSoftwareRenderer(renderer) ? kSoftwareInFlight : 3u;
}

int hemicubeRowThreads(std::string_view renderer, int requested, int cores, int workers) {
    if (requested >= 0) return requested;
    return isSoftwareRenderer(renderer) ? 0 : std::max(0, cores - workers) / std::max(1, workers);
}

std::uint32_t hemicubeLayers(std::string_view renderer, std::uint32_t requested, std::uint32_t resolution,
                             std::size_t patches, bool gpuReduction, std::uint32_t points, std::uint32_t maxLayers,
                             std::uint32_t inFlight, bool stencil, double maxBlockBytes) {
    const std::uint32_t wanted = requested > 0 ? requested : isSoftwareRenderer(renderer) ? kSoftwareLayers : 256u;
    if (wanted <= 1) return 1;
    // Per layer: ids and depth (with the mirrors' stencil, 8 bytes); per pass in flight the
    // read-back ids (CPU reduction) or the pairs and header (GPU reduction, which also keeps a
    // dense row and a touched list per layer).
    const double pixels = 3.0 * resolution * resolution;
    const double capacity = std::min(double(patches), pixels);
    const double slots = std::max(1u, inFlight);
    const double bytes = (stencil ? 12.0 : 8.0) * pixels +
                         (gpuReduction ? 4.0 * double(patches) + 4.0 * capacity + 28.0 + slots * (8.0 * capacity + 24.0)
                                       : slots * 4.0 * pixels);
    const auto fit = std::uint32_t(std::clamp(256.0 * 1024 * 1024 / bytes, 1.0, 65536.0));
    // No shader storage block may exceed the driver's limit: the GPU reduction's dense rows, touched
    // lists and each slot are one block each (the CPU reduction's slots are read-back buffers).
    const double block = gpuReduction ? std::max({4.0 * double(patches), 4.0 * (5.0 + capacity), 8.0 * capacity + 24.0})
                                      : 0.0;
    const auto blockFit = block > 0.0 && maxBlockBytes > 0.0
                              ? std::uint32_t(std::clamp(maxBlockBytes / block, 1.0, 65536.0))
                              : 65536u;
    const std::uint32_t hardLimit = std::min(std::max(1u, maxLayers), blockFit);
    const std::uint32_t layers = std::min({wanted, fit, hardLimit});
    if (layers <= 1) return 1;
    // A row's points in one pass when the driver allows it (the budget is a soft limit); else its
    // rows go point by point.
    return points > layers && points <= hardLimit ? points : layers;
}

std::vector<bool> rowsThatMaySeeMirrors(const Scene& scene, double extent) {
    std::vector<bool> rows(scene.size(), false);
    if (!scene.hasMirrors()) return rows;
    const MirrorGroups groups = groupMirrors(scene);
    // Per group: its plane (the representative's) and the bounding box of its members' corners.
    struct Group {
        Vec3 normal, point, low, high;
    };
    std::vector<Group> boxes(groups.representative.size());
    for (std::size_t g = 0; g < boxes.size(); ++g) {
        const Patch& m = scene.patches[groups.representative[g]];
        boxes[g] = {m.normal, m.centroid, Vec3::Constant(1e300), Vec3::Constant(-1e300)};
    }
    for (PatchId j = 0; j < scene.size(); ++j) {
        if (!groups.groupOfPatch[j]) continue;
        Group& g = boxes[groups.groupOfPatch[j] - 1];
        const Patch& p = scene.patches[j];
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            g.low = g.low.cwiseMin(scene.corner(p, k));
            g.high = g.high.cwiseMax(scene.corner(p, k));
        }
    }
    // The draw drops triangles within 1e-6 x extent of a hemicube's plane (float). Group members
    // are coplanar with the representative within 1e-6 x extent and their normals within 1e-9 in
    // cosine (4.5e-5 rad), so an eye up to 4.5e-5 x extent behind the representative's plane may
    // still see a member's front. A hemicube's eye is any point of the patch (--origins): heights
    // are taken from the patch's lowest corner.
    const double above = 0.5e-6 * extent, front = -5e-5 * extent;
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        double lowest = 1e300;
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) lowest = std::min(lowest, p.normal.dot(scene.corner(p, k)));
        for (const Group& g : boxes) {
            double height = -1e300;
            for (int c = 0; c < 8; ++c) {
                const Vec3 x((c & 1 ? g.high : g.low).x(), (c & 2 ? g.high : g.low).y(), (c & 4 ? g.high : g.low).z());
                height = std::max(height, p.normal.dot(x) - lowest);
            }
            if (height <= above) continue;
            bool inFront = false;
            for (std::uint32_t k = 0; k < p.cornerCount && !inFront; ++k)
                inFront = g.normal.dot(scene.corner(p, k) - g.point) > front;
            if (inFront) {
                rows[i] = true;
                break;
            }
        }
    }
    return rows;
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
    GLint64 maxBlock = 0;
    gl::GetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    context->release();
    m_workers = hemicubeWorkers(m_renderer, m_common.threads, resolveThreads(0));
    m_reduction = hemicubeReduction(m_renderer, m_options.reduce);
    m_inFlight = hemicubeInFlight(m_renderer, m_options.inFlight);
    m_rowThreads = hemicubeRowThreads(m_renderer, m_options.rowThreads, resolveThreads(0), m_workers);
    m_points = originPoints(m_options.origins);
    if (m_reduction == Reduction::Gpu && 4.0 * double(scene.size()) > double(maxBlock)) {
        if (m_options.reduce != Reduction::Auto)
            throw Error("--reduce gpu: a row of " + std::to_string(scene.size()) + " patches (" +
                        std::to_string(4 * scene.size() >> 20) + " MiB) exceeds the driver's largest shader storage block (" +
                        std::to_string(std::int64_t(maxBlock) >> 20) + " MiB, " + m_renderer + "); use --reduce cpu");
        m_reduction = Reduction::Cpu;
    }
    m_layers = hemicubeLayers(m_renderer, m_options.batch, m_options.resolution, scene.size(),
                              m_reduction == Reduction::Gpu, m_points, std::uint32_t(maxLayers), m_inFlight,
                              scene.hasMirrors(), double(maxBlock));
    // Rows that may see a mirror go row by row: their portal passes depend on what each hemicube saw.
    m_mirrorRows = rowsThatMaySeeMirrors(scene, m_geometry.extent);
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
    const auto mirrorRows = std::size_t(std::count(m_mirrorRows.begin(), m_mirrorRows.end(), true));
    return {{"max_depth", std::to_string(m_common.maxDepth)},
            {"mirrors", text("--mirrors")},
            {"min_weight", std::to_string(m_common.minWeight)},
            {"resolution", std::to_string(m_options.resolution)},
            {"origins", std::to_string(m_points)},
            {"batch", std::to_string(m_layers) +
                          (mirrorRows ? " (" + std::to_string(mirrorRows) + " of " +
                                                  std::to_string(m_scene->size()) + " rows may see a mirror: row by row)"
                                            : "")},
            {"in_flight", std::to_string(m_inFlight)},
            {"row_threads", std::to_string(m_rowThreads)},
            {"reduce", std::string(m_reduction == Reduction::Gpu ? "gpu" : "cpu") +
                           (m_options.reduce == Reduction::Auto ? " (by renderer)" : "")},
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
           (m_workers > 1 && hemicubeSerializesContexts(m_renderer) ? " taking turns at the driver" : "") + ", " + std::to_string(m_layers) + (m_layers == 1 ? " hemicube per pass, " : " hemicubes per pass, ") +
           std::to_string(m_inFlight) + " in flight, reduction on the " + (m_reduction == Reduction::Gpu ? "GPU" : "CPU") +
           (m_rowThreads > 0 ? ", " + std::to_string(m_rowThreads) + " row threads" : "");
}

void HemicubeBackend::computeRows(RowSource& rows, FormFactorBuilder& builder) {
    if (!m_scene) throw Error("hemicube back end: prepare() was not called");
    const Reduction reduction = m_reduction;
    const GlApiKind api = m_options.gl;
    std::exception_ptr failure;
    std::mutex failureMutex;
    HemicubeStats total;
    std::mutex totalMutex;
    std::mutex* const exclusive = hemicubeSerializesContexts(m_renderer) ? &sharedDriverMutex() : nullptr;
    auto worker = [&] {
        try {
            auto context = createHeadlessContext(api);
            context->makeCurrent();
            {
                const MirrorLimits limits{m_common.maxDepth, m_common.minWeight, m_rays.get()};
                HemicubeRenderer renderer(*m_scene, m_geometry, *m_layout, reduction, limits, m_layers, m_inFlight,
                                          exclusive);
                RowAccumulator row(m_scene->size(), RowAccumulator::Mode::Weights);
                HemicubeStats stats;
                // A summed row into F (the GL thread's, or a row thread's with its own accumulator).
                auto handOver = [&builder](PatchId i, RowAccumulator& r, HemicubeStats& s) {
                    const auto t0 = std::chrono::steady_clock::now();
                    // Each stats object sums one row at a time (one accumulator): the row's loss is what
                    // came since the last row it handed over.
                    builder.setRow(i, r.take(1.0), s.lostWeight - s.lostHandedOver);
                    s.lostHandedOver = s.lostWeight;
                    s.collect += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                };
                auto rowDone = [&](PatchId i) { handOver(i, row, stats); };
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
                // Declared after the renderer: destroyed (joined) before it, as its slots' memory goes.
                std::unique_ptr<HemicubeRowPool> pool;
                if (m_rowThreads > 0) {
                    pool = std::make_unique<HemicubeRowPool>(std::size_t(m_rowThreads), m_scene->size(), handOver);
                    renderer.useRowPool(pool.get());
                }
                // Whole rows into passes of up to m_layers hemicubes, several passes in flight; a row
                // that may see a mirror, or has more hemicubes than a pass, is drawn at once, point by
                // point, after the passes (each waits for everything drawn before it).
                std::vector<HemicubeItem> batch;
                std::vector<PatchId> oneByOne;
                PatchId i = 0;
                while (!stopped() && rows.next(i)) {
                    origins(i);
                    if (m_mirrorRows[i] || points.size() > m_layers) {
                        oneByOne.push_back(i);
                        continue;
                    }
                    if (batch.size() + points.size() > m_layers) {
                        renderer.computeBatch(batch, row, rowDone, stats);
                        batch.clear();
                    }
                    for (std::size_t k = 0; k < points.size(); ++k) batch.push_back({i, points[k], weights[k]});
                }
                if (!stopped()) {
                    if (!batch.empty()) renderer.computeBatch(batch, row, rowDone, stats);
                    renderer.drain(row, rowDone, stats);
                    for (const PatchId r : oneByOne) {
                        if (stopped()) break;
                        origins(r);
                        for (std::size_t k = 0; k < points.size(); ++k)
                            renderer.computeRow(r, points[k], weights[k], row, stats);
                        rowDone(r);
                    }
                    if (pool) {
                        pool->drain();
                        stats += pool->stats();
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
    if (total.gpuDraw + total.gpuFinish > 0) {  // passes filled while others drew: waited for and timed
        builder.addStageSeconds("hemicube wait", total.wait);
        builder.addStageSeconds("hemicube gpu draw", total.gpuDraw);
        builder.addStageSeconds("hemicube gpu results", total.gpuFinish);
    }
    builder.addStageSeconds("row collect", total.collect);
    if (m_scene->hasMirrors())
        builder.addStageSeconds(m_options.mirrors == HemicubeMirrors::Rays ? "mirror rays" : "mirror portals", total.mirrors);
}

}  // namespace hemirad
