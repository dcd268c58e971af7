// Hemisphere back end: the ray estimator (ray_estimator.hpp) or the analytic one
// (analytic_estimator.hpp), with mirror terms by rays or virtual images (mirror_images.hpp). Rows
// run in parallel (OpenMP); each thread accumulates a dense row.
#include "preprocess/hemisphere/hemisphere_backend.hpp"

#include "engine/error.hpp"
#include "engine/parallel_failure.hpp"
#include "engine/threads.hpp"
#include "preprocess/row_accumulator.hpp"

#include <omp.h>

#include <algorithm>
#include <optional>
#include <string>

namespace hemirad {

/// Analytic rows whose direct factors sum above 1 + this are scaled to 1 (rowSumBound's tolerance).
constexpr double kRescaleAbove = 1e-3;

HemisphereBackend::HemisphereBackend(const HemisphereOptions& options, const CommonOptions& common)
    : m_options(options), m_common(common), m_rayEstimator(options, common), m_analyticEstimator(options) {}

HemisphereBackend::~HemisphereBackend() = default;

void HemisphereBackend::prepare(const Scene& scene) {
    m_scene = &scene;
    m_rays = std::make_unique<RayScene>(scene, m_common.threads);
    m_rayEstimator.prepare(scene, *m_rays);
    m_mirrors = scene.hasMirrors();
    m_analytic = usesAnalyticEstimator(m_options, scene.size());
    if (!m_analytic) return;
    m_images.reset();
    m_imagesRefused.clear();
    m_analyticEstimator.prepare(scene, *m_rays);
    if (m_mirrors && m_options.mirrorEstimator == MirrorEstimator::Images) {
        std::vector<Reflector> reflectors;
        m_imagesRefused = findReflectors(scene, reflectors);
        if (m_imagesRefused.empty()) {
            MirrorImages::Settings settings;
            settings.limits = {m_common.maxDepth, m_common.minWeight};
            settings.visibility = m_analyticEstimator.rules().visibility();
            settings.origins = m_options.origins;
            m_images = std::make_unique<MirrorImages>(scene, m_analyticEstimator.rules().geometry(), std::move(reflectors),
                                                      *m_rays, settings);
        }
    }
}

FormFactorProvenance HemisphereBackend::provenance() const {
    FormFactorProvenance p;
    p.method = HemisphereOptions::kMethod;
    p.estimator = m_analytic ? "analytic" : "rays";
    p.rowSumBound = extendedRowSumBound(*m_scene, m_common.maxDepth, m_common.minWeight);
    return p;
}

std::map<std::string, std::string> HemisphereBackend::parameters() const {
    std::map<std::string, std::string> p = {
        {"samples", std::to_string(m_options.samples)},
        {"origins", std::to_string(m_options.origins)},
        {"max_depth", std::to_string(m_common.maxDepth)},
        {"min_weight", std::to_string(m_common.minWeight)},
        {"seed", std::to_string(m_options.seed)},
        {"directions", std::string(m_options.jitter ? "beckers-disk jittered in cells" : "beckers-disk area-median") +
                           (m_options.fixedDirections ? ", fixed" : ", rotated per origin")}};
    // The analytic estimator described for people (the provenance holds its kind).
    const PairRules& rules = m_analyticEstimator.rules();
    if (m_analytic)
        p["estimator"] = std::string("analytic: Lambert point-to-polygon factors from ") +
                         "m x m Gauss-Legendre points over the smaller patch of each pair (the centroid for m = 1, m >= " +
                         std::to_string(rules.orders().lowest()) + "), m chosen from the pair's distance and size for an estimated relative error of " +
                         "1e-" + std::to_string(m_options.pairDigits) + " / 2, the 2 x 2 x 2 x 2 point rule for pairs far from each other's horizon, " +
                         "pairs within " + std::to_string(int(kNearDistance)) +
                         " radii exact by contour integrals (touching or not) less their hidden part (adaptive over the emitter)" +
                         ", each pair computed once for both rows (reciprocal: the other row takes the emitting row's value)" +
                         (rules.visibility() ? ", the exact visible part (shadow polygons of the " + std::to_string(rules.blockers()) +
                                             " patches that can obstruct) where a point's factor exceeds 1e-" +
                                             std::to_string(m_options.pairDigits + 1) + ", elsewhere shadow rays to " +
                                             (m_options.jitter ? "random points" : "centres") +
                                             ", receivers on a silhouette (their mesh neighbours' verdicts differ) their "
                                             "exact visible part above 5e-" + std::to_string(m_options.pairDigits + 2) +
                                             ", below it split in " + std::to_string(rules.splitLevels()) +
                                             (rules.splitLevels() == 1 ? " level" : " levels") + " with a ray per piece"
                                       : std::string(", no shadow rays (no patch can obstruct: a convex scene)"));
    if (m_analytic && m_options.pairs == PairMethod::Whole)
        p["pairs"] = "every pair whole (--pairs whole): contour integrals less the hidden part to 1e-" +
                     std::to_string(m_options.pairDigits + 2) + " of the pair";
    if (m_analytic && m_mirrors)
        p["mirror_terms"] = m_images ? "virtual images through " + std::to_string(m_images->reflectorCount()) +
                                           " planar mirrors, emitter rule per chain and receiver, a path and its reverse computed once"
                        : m_imagesRefused.empty() ? std::string("rays along the directions (--mirror-estimator rays)")
                                                  : "rays along the directions: " + m_imagesRefused;
    return p;
}

void HemisphereBackend::computeRows(RowSource& rows, FormFactorBuilder& builder) {
    if (!m_scene) throw Error("hemisphere back end: prepare() was not called");
    const int threads = resolveThreads(m_common.threads);
    // Each pair is computed by its emitting row and handed to the other row (pair_exchange.hpp),
    // kept for the rows this source may still hand out.
    const auto wanted = [&rows](PatchId r) { return rows.mayHandOut(r); };
    std::unique_ptr<PairExchange> exchange, imageExchange;  // direct pairs; pairs through mirrors
    if (m_analytic) exchange = std::make_unique<PairExchange>(m_scene->size(), wanted);
    if (m_images) imageExchange = std::make_unique<PairExchange>(m_scene->size(), wanted);
    // Everything a thread does is inside run(), its O(N) workspace included (an out-of-memory there
    // ended in std::terminate): the first failure stops every thread and is rethrown here.
    ParallelFailure failure;
#pragma omp parallel num_threads(threads)
    failure.run([&] {
        RowAccumulator row(m_scene->size(),
                           m_mirrors || m_analytic ? RowAccumulator::Mode::Weights : RowAccumulator::Mode::Counts);
        RayEstimator::Workspace raySpace = m_rayEstimator.workspace();
        std::optional<AnalyticEstimator::Workspace> analyticSpace;
        if (m_analytic) analyticSpace.emplace(m_analyticEstimator.workspace(*exchange));
        const std::unique_ptr<MirrorImages::Workspace> imageSpace = m_images ? m_images->workspace() : nullptr;
        const double unit = double(m_options.origins) * m_options.samples;  // a row's weights per unit of F
        RayCounts counts;
        PatchId i = 0;
        while (!builder.cancelled() && !failure.failed() && rows.next(i)) {
            const double lostBefore = counts.lostWeight;  // what this row loses is what it adds
            if (m_analytic) {
                const double direct = m_analyticEstimator.addRow(i, row, *analyticSpace, counts);
                counts.lostWeight += std::max(0.0, 1.0 - direct);
                counts.largestDirectSum = std::max(counts.largestDirectSum, direct);
                // Visibility from a few shadow rays can count a partly hidden patch whole; no
                // row may send out more than it emits. Quadrature alone stays within 1e-3 (and
                // scaling would break the pairs' reciprocity).
                if (direct > 1.0 + kRescaleAbove) {
                    row.scaleWeights(1.0 / direct);
                    ++counts.rescaledRows;
                }
                if (m_images) m_images->addRow(i, row, unit, *imageExchange, *imageSpace, counts);
                else if (m_mirrors) m_rayEstimator.addRow(i, RayEstimator::Deposit::MirrorChainsOnly, row, raySpace, counts);
            } else {
                m_rayEstimator.addRow(i, RayEstimator::Deposit::All, row, raySpace, counts);
            }
            builder.setRow(i, row.take(1.0 / unit), counts.lostWeight - lostBefore);
        }
        if (m_analytic) {
            counts.convexSolids = m_analyticEstimator.rules().solids();
            counts.solidFaces = m_analyticEstimator.rules().solidFaces();
        }
        builder.addCounts(counts);
    });
    failure.rethrowIfFailed();
}

void HemisphereBackend::orderRows(std::vector<PatchId>& rows) const {
    if (m_analytic) std::sort(rows.begin(), rows.end(), [this](PatchId a, PatchId b) { return emitsFor(*m_scene, a, b); });
}

}  // namespace hemirad
