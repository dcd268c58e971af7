// Hemisphere back end: Beckers rays (the "rays" estimator) or Lambert's point-to-polygon factors
// with shadow rays (the "analytic" estimator; Wallace, Elmquist & Haines 1989 cast rays for
// visibility of analytic point-to-area factors, Baum, Rushmeier & Winget 1989 give the exact
// polygon form). Rows run in parallel (OpenMP); each thread accumulates a dense row.
#include "preprocess/hemisphere/hemisphere_backend.hpp"

#include "engine/error.hpp"
#include "engine/parallel_failure.hpp"
#include "engine/threads.hpp"
#include "preprocess/hemisphere/beckers.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"
#include "preprocess/hemisphere/obstruction.hpp"
#include "preprocess/hemisphere/patch_sampler.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"
#include "rays/mirror_chain.hpp"
#include "preprocess/row_accumulator.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <array>
#include <limits>
#include <unordered_map>

namespace hemirad {

/// Analytic rows whose direct factors sum above 1 + this are scaled to 1 (rowSumBound's tolerance).
constexpr double kRescaleAbove = 1e-3;
/// The emitter rules aim at the pair tolerance divided by this. Their error estimates (C rho^-2m,
/// the far kernel's constant) are fits, not bounds, and a low-order rule underestimates a convex
/// kernel (Jensen), so the errors of a row's pairs share a sign and add up along a wall: with the
/// tolerance alone a subdivided cube's adjacent walls were 3.2e-6 off at n = 16, with half 6.1e-7
/// (0.27 -> 0.30 s).
constexpr double kRuleMargin = 2.0;
/// A reversed term without a shadow ray (its visibility came from shadow polygons).
constexpr std::uint32_t kNoRay = ~std::uint32_t(0);

/// Per-thread scratch: the row being accumulated and the rotated directions and their hits.
struct HemisphereBackend::Workspace {
    Workspace(std::size_t patches, bool weights)
        : row(patches, weights ? RowAccumulator::Mode::Weights : RowAccumulator::Mode::Counts) {}
    RowAccumulator row;
    // Analytic estimator: receivers by the order of their emitter rule, and the visible-candidate
    // batch of one point.
    std::vector<std::vector<PatchId>> byOrder;
    std::vector<std::uint8_t> ruled;  // per patch: in byOrder or a close pair (not in the centroid pass)
    std::vector<PatchId> contacts;    // this row's close pairs (contactPair)
    ContactPairs::Scratch contactScratch;
    std::vector<Vec3> quadPoints;  // a quadrature rule over the emitter
    std::vector<double> quadWeights;
    std::vector<PatchId> candidates;
    std::vector<double> factors;
    std::vector<float> targets;
    // Pairs emitted by the other patch: their patches, the range of their terms, the terms' weights
    // and segment origins.
    std::vector<PatchId> reversed;
    std::vector<std::uint32_t> termBegin, termEnd;
    std::vector<double> termWeights;
    std::vector<float> origins;
    std::vector<std::uint8_t> blocked;
    std::vector<PatchId> far;  // the far rule's receivers with a shadow ray from the centroid
    std::vector<double> farFactors;
    std::vector<std::uint8_t> farBlocked;
    std::vector<std::uint32_t> rayOf;  // per reversed term: its shadow ray, or kNoRay (shadow polygons)
    std::vector<Vec3> termPoint;       // per reversed term: the emitter's point
    std::vector<std::uint32_t> termIndex;  // and its index in the emitter's rule (aimPoint's `point`)
    std::vector<double> reversedTerm;  // per reversed emitter: its terms for this row, in ray units
    std::vector<float> handed;  // and its entry as the exchange hands it over (-1: split here, use the terms)
    std::vector<std::uint32_t> silhouette;  // the reversed emitters on a silhouette seen from this row
    std::vector<std::uint32_t> pieceOf;  // per silhouette piece ray: its reversed emitter
    std::vector<double> pieceValue;      // and its term (factor times the point's weight)
    // Pairs handed between rows: the exchange, this row's entries from it and for it, per patch the
    // entry of its row for this one (-1: none), and per receiver this row's unsplit sum (-1: no term).
    PairExchange* exchange = nullptr;
    std::vector<PairExchange::Entry> taken, outgoing;
    std::vector<float> published;
    std::vector<double> unsplit;
    std::vector<PatchId> touched;
    // One point's receivers with exact visibility: their visible and whole factors.
    std::vector<PatchId> exact;
    std::vector<double> exactVisible, exactWhole;
    ShadowPolygons::Scratch shadow;
    std::vector<Vec3> clipped;
    std::vector<std::uint8_t> status;  // per patch for one origin: 0 not aimed at, 1 visible, 2 blocked
    std::vector<PatchId> split;        // silhouette patches of one origin
    std::vector<Vec3> pieces, finer;   // their pieces, 4 corners each
    std::vector<float> jittered;  // this origin's cell directions when jittering
    std::vector<float> dirs;
    std::vector<PatchId> hits;
    std::vector<float> distances;
};

namespace {

/// This row's term for receiver r (its value when visible, 0 when hidden) into the sum that row r
/// recomputes in addReversedPairs, added in the same order, so that the exchange hands over equal bits.
void keepTerm(std::vector<double>& unsplit, std::vector<PatchId>& touched, PatchId r, double visibleValue) {
    if (unsplit[r] < 0.0) {
        unsplit[r] = 0.0;
        touched.push_back(r);
    }
    if (visibleValue > 0.0) unsplit[r] += visibleValue;
}

}  // namespace

HemisphereBackend::HemisphereBackend(const HemisphereOptions& options, const CommonOptions& common)
    : m_options(options), m_common(common) {
    m_directions = beckersDirections(options.samples);
    m_rings = beckersDiskCounts(options.samples);
}

HemisphereBackend::~HemisphereBackend() = default;

void HemisphereBackend::prepare(const Scene& scene) {
    m_scene = &scene;
    m_rays = std::make_unique<RayScene>(scene, m_common.threads);
    m_normals.resize(3 * scene.size());
    for (PatchId i = 0; i < scene.size(); ++i)
        for (int k = 0; k < 3; ++k) m_normals[3 * i + k] = static_cast<float>(scene.patches[i].normal[k]);
    m_mirrors = scene.hasMirrors();
    m_analytic = usesAnalyticEstimator(m_options, scene.size());
    if (!m_analytic) return;
    const std::vector<std::uint8_t> blocks = obstructingPatches(scene);
    m_visibility = std::find(blocks.begin(), blocks.end(), 1) != blocks.end();
    m_images.reset();
    m_imagesRefused.clear();
    // Per pair, the lowest order good for --pair-digits: at least ceil(sqrt(K)) for --origins K,
    // the near-field order within kNearDistance.
    const double tolerance = std::pow(10.0, -double(m_options.pairDigits));
    m_orders = EmitterOrders(tolerance / kRuleMargin, farOrder(m_options.origins), nearOrder(m_options.origins));
    // The far rule is the default's: --origins K > 1 asks for at least ceil(sqrt(K))^2 points over the emitter.
    m_farRatio = m_options.origins == 1 ? std::pow(FarRule::kErrorConstant * kRuleMargin / tolerance, 0.25) : 0.0;
    m_ruleNodes.assign(std::size_t(m_orders.highest()) + 1, {});
    m_ruleWeights.assign(m_ruleNodes.size(), {});
    for (int m = m_orders.lowest(); m <= m_orders.highest(); ++m) gaussLegendre(m, m_ruleNodes[m], m_ruleWeights[m]);
    m_splitLevels = m_options.jitter ? 2 : 1;
    m_geometry.build(scene);
    if (m_farRatio > 0.0) m_far.build(m_geometry);
    m_geometry.buildNeighbours(scene);
    // Exact partial visibility where one shadow ray's verdict could move the pair by more than a
    // tenth of the pair tolerance in absolute terms (each row sums to at most 1).
    m_shadows.build(m_geometry, blocks);
    m_contacts.build(m_geometry, m_shadows, m_visibility);
    m_exactAbove = m_visibility ? 0.1 * tolerance : std::numeric_limits<double>::infinity();
    if (m_mirrors && m_options.mirrorEstimator == MirrorEstimator::Images) {
        std::vector<Reflector> reflectors;
        m_imagesRefused = findReflectors(scene, reflectors);
        if (m_imagesRefused.empty()) {
            MirrorImages::Settings settings;
            settings.limits = {m_common.maxDepth, m_common.minWeight};
            settings.visibility = m_visibility;
            settings.origins = m_options.origins;
            m_images = std::make_unique<MirrorImages>(scene, m_geometry, std::move(reflectors), *m_rays, settings);
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
    if (m_analytic)
        p["estimator"] = std::string("analytic: Lambert point-to-polygon factors from ") +
                         "m x m Gauss-Legendre points over the smaller patch of each pair (the centroid for m = 1, m >= " +
                         std::to_string(m_orders.lowest()) + "), m chosen from the pair's distance and size for an estimated relative error of " +
                         "1e-" + std::to_string(m_options.pairDigits) + " / 2, the 2 x 2 x 2 x 2 point rule for pairs far from each other's horizon, " +
                         "pairs within " + std::to_string(int(kNearDistance)) +
                         " radii exact by contour integrals (touching or not) less their hidden part (adaptive over the emitter)" +
                         ", each pair computed once for both rows (reciprocal: the other row takes the emitting row's value)" +
                         (m_visibility ? ", the exact visible part (shadow polygons of the " + std::to_string(m_shadows.size()) +
                                             " patches that can obstruct) where a point's factor exceeds 1e-" +
                                             std::to_string(m_options.pairDigits + 1) + ", elsewhere shadow rays to " +
                                             (m_options.jitter ? "random points" : "centres") +
                                             ", silhouette patches split in " + std::to_string(m_splitLevels) +
                                             (m_splitLevels == 1 ? " level" : " levels")
                                       : std::string(", no shadow rays (no patch can obstruct: a convex scene)"));
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
        Workspace ws(m_scene->size(), m_mirrors || m_analytic);
        const std::unique_ptr<MirrorImages::Workspace> imageSpace = m_images ? m_images->workspace() : nullptr;
        if (m_analytic) {
            ws.ruled.assign(m_scene->size(), 0);
            ws.byOrder.resize(std::size_t(m_orders.highest()) + 1);  // [0]: the far rule
            ws.status.assign(m_scene->size(), 0);
            ws.exchange = exchange.get();
            ws.published.assign(m_scene->size(), -1.0f);
            ws.unsplit.assign(m_scene->size(), -1.0);
        }
        ws.dirs.resize(m_directions.size());
        ws.hits.resize(m_options.samples);
        ws.distances.resize(m_options.samples);
        RayCounts counts;
        PatchId i = 0;
        while (!builder.cancelled() && !failure.failed() && rows.next(i)) {
            if (m_analytic) {
                const double direct = addAnalyticRow(i, ws, counts);
                counts.lostWeight += std::max(0.0, 1.0 - direct);
                counts.largestDirectSum = std::max(counts.largestDirectSum, direct);
                // Visibility from a few shadow rays can count a partly hidden patch whole; no
                // row may send out more than it emits. Quadrature alone stays within 1e-3 (and
                // scaling would break the pairs' reciprocity).
                if (direct > 1.0 + kRescaleAbove) {
                    ws.row.scaleWeights(1.0 / direct);
                    ++counts.rescaledRows;
                }
                if (m_images) m_images->addRow(i, ws.row, double(m_options.origins) * m_options.samples, *imageExchange, *imageSpace,
                                              counts);
                else if (m_mirrors) castRays<true, false>(i, ws, counts);
            } else if (m_mirrors) {
                castRays<true, true>(i, ws, counts);
            } else {
                castRays<false, true>(i, ws, counts);
            }
            const double scale = 1.0 / (double(m_options.origins) * m_options.samples);
            builder.setRow(i, ws.row.take(scale));
        }
        builder.addCounts(counts);
    });
    failure.rethrowIfFailed();
}

void HemisphereBackend::orderRows(std::vector<PatchId>& rows) const {
    if (m_analytic) std::sort(rows.begin(), rows.end(), [this](PatchId a, PatchId b) { return emitsFor(a, b); });
}

template <bool Mirrors, bool Direct>
void HemisphereBackend::castRays(PatchId i, Workspace& ws, RayCounts& counts) const {
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
                if constexpr (Direct) ws.row.addWeight(j, 1.0);
                if (m_scene->patches[j].specular > 0.0)
                    followMirrorChain(*m_scene, *m_rays, lifted, Vec3(d[0], d[1], d[2]), j, ws.distances[k], 1.0,
                                      rowWeight, {m_common.maxDepth, m_common.minWeight},
                                      [&ws](PatchId p, double w) { ws.row.addWeight(p, w); }, counts);
            } else {
                ws.row.addCount(j);
            }
        }
    }
    counts.rays += std::uint64_t(N) * origins.size();
    counts.lostWeight += double(lost) * rowWeight;
}

double HemisphereBackend::addAnalyticRow(PatchId i, Workspace& ws, RayCounts& counts) const {
    // Pairs whose other patch emits first: their terms come from that patch's points, and their
    // visibility is the neighbours' status for the silhouette test below.
    double direct = addReversedPairs(i, ws, counts);
    // Receivers by the order of their rule over i (0: the far rule); order 1 (the centroid) takes
    // the rest in one pass.
    for (auto& list : ws.byOrder) list.clear();
    ws.contacts.clear();
    for (PatchId j = 0; j < m_geometry.shapes.size(); ++j) {
        if (j == i || !emitsFor(i, j)) continue;
        if (contactPair(i, j)) {  // computed as a whole below
            ws.contacts.push_back(j);
            ws.ruled[j] = 1;
            continue;
        }
        const int m = pairOrder(i, j);
        if (m == 1) continue;
        ws.byOrder[m].push_back(j);
        ws.ruled[j] = 1;
    }
    // The far rule's shadow rays from the centroid; their terms are added by the centroid pass,
    // once it has the statuses of its own receivers for the silhouette test (the far rule exists
    // with one origin only, where the centroid pass does too).
    castFarRays(i, ws, counts);
    // The accumulator holds ray units (take() scales by 1 / (origins samples)): F = value / unit.
    const double unit = double(m_options.origins) * m_options.samples;
    const PatchShape& emitter = m_geometry.shapes[i];
    if (m_orders.lowest() == 1) direct += addAnalyticFrom(i, emitter.centroid, 0, nullptr, unit, ws, counts);
    for (int m = std::max(2, m_orders.lowest()); m <= m_orders.highest(); ++m) {
        if (ws.byOrder[m].empty()) continue;
        emitterRule(i, m, ws);
        for (std::size_t q = 0; q < ws.quadPoints.size(); ++q)
            direct += addAnalyticFrom(i, ws.quadPoints[q], std::uint32_t(q), &ws.byOrder[m], unit * ws.quadWeights[q], ws,
                                      counts);
        for (const PatchId j : ws.byOrder[m]) ws.ruled[j] = 0;
    }
    for (const PatchId j : ws.contacts) {
        bool viewed = false;
        const double value = contactValue(i, j, ws, counts, viewed);
        ws.ruled[j] = 0;
        if (!viewed) continue;  // as the other row finds it: no term
        keepTerm(ws.unsplit, ws.touched, j, value);
        if (!(value > 0.0)) continue;
        ws.row.addWeight(j, value);
        direct += value;
    }
    for (const PatchId j : ws.byOrder[0]) ws.ruled[j] = ws.status[j] = 0;
    for (const PatchId j : ws.reversed) ws.status[j] = 0;
    ws.outgoing.clear();
    for (const PatchId j : ws.touched) {
        ws.outgoing.push_back({j, handedValue(ws.unsplit[j], i, j)});
        ws.unsplit[j] = -1.0;
    }
    ws.exchange->publish(i, ws.outgoing);
    ws.touched.clear();
    return direct / unit;
}

double HemisphereBackend::contactValue(PatchId e, PatchId r, Workspace& ws, RayCounts& counts, bool& viewed) const {
    ContactPairs::Cost cost;
    double unoccluded = 0.0;
    const double exchange = m_contacts.exchange(e, r, ws.contactScratch, cost, unoccluded);
    viewed = unoccluded > 0.0;
    ++counts.contactPairs;
    counts.contactShafts += cost.shafts;
    counts.contactEvaluations += cost.evaluations;
    return exchange / m_scene->patches[e].area * (double(m_options.origins) * m_options.samples);
}

void HemisphereBackend::emitterRule(PatchId e, int m, Workspace& ws) const {
    ws.quadPoints.clear();
    ws.quadWeights.clear();
    if (m == 1) {
        ws.quadPoints.push_back(m_geometry.shapes[e].centroid);
        ws.quadWeights.push_back(1.0);
        return;
    }
    polygonQuadrature(m_geometry.polygon(e), m_geometry.shapes[e].count, m_ruleNodes[m], m_ruleWeights[m], ws.quadPoints,
                      ws.quadWeights);
}

void HemisphereBackend::castFarRays(PatchId i, Workspace& ws, RayCounts& counts) const {
    const double offset = m_rays->originOffset();
    ws.far.clear();  // the pairs with a shadow ray
    ws.farFactors.clear();
    ws.targets.clear();
    for (const PatchId j : ws.byOrder[0]) {
        const double f = m_far.factor(m_geometry, i, j, m_scene->patches[j].area);
        if (f > m_exactAbove) {  // too large for one shadow ray: the rule's points with exact visibility
            const int m = ruleOrder(i, j);
            if (m == 1)
                ws.ruled[j] = 0;
            else
                ws.byOrder[std::size_t(m)].push_back(j);
            continue;
        }
        ws.far.push_back(j);
        ws.farFactors.push_back(f);
        if (!m_visibility) continue;  // no shadow ray: no target
        float local[3];
        const Vec3 aim = aimPoint(m_geometry.polygon(j), m_geometry.shapes[j].count, i, j, 0, 0);
        m_rays->toLocal(aim + offset * m_geometry.shapes[j].normal, local);
        ws.targets.insert(ws.targets.end(), local, local + 3);
    }
    ws.farBlocked.assign(ws.far.size(), 0);
    if (m_visibility && !ws.far.empty()) {
        float origin[3];
        m_rays->toLocal(m_geometry.shapes[i].centroid + offset * m_geometry.shapes[i].normal, origin);
        m_rays->occludedSegments(origin, ws.targets.data(), ws.far.size(), ws.farBlocked.data());
        counts.rays += ws.far.size();
    }
    for (std::size_t k = 0; k < ws.far.size(); ++k) ws.status[ws.far[k]] = ws.farBlocked[k] ? 2 : 1;
}

double HemisphereBackend::addFarPairs(double weight, Workspace& ws) const {
    double sum = 0.0;
    for (std::size_t k = 0; k < ws.far.size(); ++k) {
        const PatchId j = ws.far[k];
        if (!(ws.farFactors[k] > 0.0)) continue;  // facing away: nothing to split either
        keepTerm(ws.unsplit, ws.touched, j, ws.farBlocked[k] ? 0.0 : ws.farFactors[k] * weight);
        if (m_geometry.onSilhouette(j, ws.status)) {  // split by the centroid pass, as its own receivers
            ws.split.push_back(j);
            continue;
        }
        if (ws.farBlocked[k]) continue;
        ws.row.addWeight(j, ws.farFactors[k] * weight);
        sum += ws.farFactors[k] * weight;
    }
    return sum;
}

double HemisphereBackend::addReversedPairs(PatchId i, Workspace& ws, RayCounts& counts) const {
    // For every j that emits for i, the terms row j sums for i (addAnalyticFrom with j's rule, in
    // j's order, the same shadow rays), so that A_i F_ij = A_j F_ji to rounding wherever the two
    // rows agree about a silhouette (row j splits i where i's neighbours disagree, seen from j; this
    // row splits where j's neighbours disagree, seen from i). Row j hands them over through the
    // exchange when it finished first; the rest are recomputed here.
    const std::uint64_t ticket = ws.exchange->open(i, ws.taken);
    for (const PairExchange::Entry& entry : ws.taken) ws.published[entry.patch] = entry.value;
    ws.reversed.clear();
    ws.reversedTerm.clear();
    ws.handed.clear();
    ws.termBegin.clear();
    ws.termEnd.clear();
    ws.factors.clear();
    ws.termWeights.clear();
    ws.origins.clear();
    ws.targets.clear();
    ws.rayOf.clear();
    ws.termPoint.clear();
    ws.termIndex.clear();
    for (PatchId j = 0; j < m_geometry.shapes.size(); ++j) {
        if (j == i || !emitsFor(j, i)) continue;
        const std::uint32_t begin = std::uint32_t(ws.factors.size());
        double contact = 0.0;  // a close pair's value, computed here (no terms)
        if (ws.published[j] >= 0.0f) {
            ws.handed.push_back(ws.published[j]);
        } else if (ws.exchange->finished(j, ticket)) {
            continue;  // row j had no term for i
        } else if (contactPair(j, i)) {
            bool viewed = false;
            contact = contactValue(j, i, ws, counts, viewed);
            if (!viewed) continue;  // no term (as row j publishes none)
            ws.handed.push_back(handedValue(contact, j, i));
        } else if (!reversedTerms(j, i, true, ws, counts)) {
            continue;  // no point of j has a term for i
        } else {
            ws.handed.push_back(-1.0f);  // from the terms below
        }
        ws.reversedTerm.push_back(contact);
        ws.reversed.push_back(j);
        ws.termBegin.push_back(begin);
        ws.termEnd.push_back(std::uint32_t(ws.factors.size()));
    }
    for (const PairExchange::Entry& entry : ws.taken) ws.published[entry.patch] = -1.0f;
    const std::size_t rays = ws.origins.size() / 3;
    ws.blocked.assign(rays, 0);
    if (m_visibility && rays > 0) {
        m_rays->occludedSegmentPairs(ws.origins.data(), ws.targets.data(), rays, ws.blocked.data());
        counts.rays += rays;
    }
    for (std::size_t p = 0; p < ws.reversed.size(); ++p) {
        if (ws.handed[p] < 0.0f) {
            for (std::uint32_t t = ws.termBegin[p]; t < ws.termEnd[p]; ++t) {  // row j's sum for i, in row j's order
                if (ws.rayOf[t] == kNoRay ? !(ws.factors[t] > 0.0) : ws.blocked[ws.rayOf[t]] != 0) continue;
                ws.reversedTerm[p] += ws.factors[t] * ws.termWeights[t];
            }
            ws.handed[p] = handedValue(ws.reversedTerm[p], ws.reversed[p], i);
        }
        ws.status[ws.reversed[p]] = ws.handed[p] > 0.0f ? 1 : 2;
    }
    if (m_visibility) splitReversedSilhouettes(i, ws, counts);
    double sum = 0.0;
    const double Ai = m_scene->patches[i].area;
    const double unit = double(m_options.origins) * m_options.samples;
    for (std::size_t p = 0; p < ws.reversed.size(); ++p) {
        const PatchId j = ws.reversed[p];
        // The handed-over entry in ray units (exact: a float times an integer below 2^29), or the
        // terms of a pair split here.
        const double value =
            ws.handed[p] >= 0.0f ? double(ws.handed[p]) * unit : ws.reversedTerm[p] * (m_scene->patches[j].area / Ai);
        if (!(value > 0.0)) continue;
        ws.row.addWeight(j, value);
        sum += value;
    }
    return sum;
}

bool HemisphereBackend::reversedTerms(PatchId j, PatchId i, bool rays, Workspace& ws, RayCounts& counts) const {
    const PatchShape& receiver = m_geometry.shapes[i];
    const PatchShape& emitter = m_geometry.shapes[j];
    if (contactPair(j, i)) return false;  // a close pair is computed whole, without terms
    // No point of j has a term when all of i lies below j's plane or all of j behind i's (with a
    // margin of j's radius for the points off its centroid's plane).
    if (emitter.normal.dot(receiver.centroid - emitter.centroid) <= -receiver.radius - emitter.radius ||
        receiver.normal.dot(emitter.centroid - receiver.centroid) + emitter.radius <= 0.0)
        return false;
    const double unit = double(m_options.origins) * m_options.samples;
    const double offset = m_rays->originOffset();
    auto addTerm = [&](const Vec3& x, std::uint32_t q, double f, double weight, bool exact, const Vec3& aim) {
        ws.factors.push_back(f);
        ws.termWeights.push_back(weight);
        ws.termPoint.push_back(x);
        ws.termIndex.push_back(q);
        if (exact) {
            ws.rayOf.push_back(kNoRay);
            return;
        }
        ws.rayOf.push_back(std::uint32_t(ws.origins.size() / 3));
        if (!rays) return;  // the split replaces the ray terms: their verdicts are not needed
        float local[3];
        m_rays->toLocal(x + offset * emitter.normal, local);
        ws.origins.insert(ws.origins.end(), local, local + 3);
        m_rays->toLocal(aim + offset * receiver.normal, local);
        ws.targets.insert(ws.targets.end(), local, local + 3);
    };
    int m = pairOrder(j, i);
    const double far = m == 0 ? m_far.factor(m_geometry, j, i, m_scene->patches[i].area) : 0.0;
    if (far > m_exactAbove) m = ruleOrder(j, i);  // as castFarRays: the rule with exact visibility
    if (m == 0) {  // the far rule: one term, one shadow ray from j's centroid (as addFarPairs)
        if (!(far > 0.0)) return false;
        addTerm(emitter.centroid, 0, far, unit, false, aimPoint(m_geometry.polygon(i), receiver.count, j, i, 0, 0));
        return true;
    }
    emitterRule(j, m, ws);
    const std::size_t before = ws.factors.size();
    for (std::size_t q = 0; q < ws.quadPoints.size(); ++q) {
        const Vec3* polygon;
        std::size_t corners;
        const Vec3& x = ws.quadPoints[q];
        const double f = pointFactor(i, x, emitter.normal, ws.clipped, polygon, corners);
        if (f <= 0.0) continue;
        const double weight = unit * ws.quadWeights[q];  // as row j weighs it (the centroid's weight is 1)
        if (f > m_exactAbove) {  // as addAnalyticFrom: the visible part from shadow polygons
            ++counts.shadowTerms;
            addTerm(x, std::uint32_t(q), m_shadows.visibleFactor(x, emitter.normal, polygon, corners, j, i, f, ws.shadow),
                    weight, true, x);
            continue;
        }
        addTerm(x, std::uint32_t(q), f, weight, false, aimPoint(polygon, corners, j, i, std::uint32_t(q), 0));
    }
    return ws.factors.size() > before;
}

void HemisphereBackend::splitReversedSilhouettes(PatchId i, Workspace& ws, RayCounts& counts) const {
    // An emitter j whose mesh neighbours disagree with it about i sees i past a silhouette, which
    // moves across i as the point on j moves: each of its ray terms takes i in pieces, each with
    // its own factor and shadow ray, as row j does where it finds i on a silhouette (the same
    // pieces, aims and rays: equal values where both rows split). Exact terms stay as they are.
    const PatchShape& receiver = m_geometry.shapes[i];
    const double offset = m_rays->originOffset();
    ws.silhouette.clear();
    for (std::size_t p = 0; p < ws.reversed.size(); ++p) {
        if (!m_geometry.onSilhouette(ws.reversed[p], ws.status)) continue;
        ws.silhouette.push_back(std::uint32_t(p));
        if (ws.termBegin[p] != ws.termEnd[p]) continue;
        // Handed over by row j as a sum: its terms again, without shadow rays.
        ws.termBegin[p] = std::uint32_t(ws.factors.size());
        reversedTerms(ws.reversed[p], i, false, ws, counts);
        ws.termEnd[p] = std::uint32_t(ws.factors.size());
    }
    ws.origins.clear();
    ws.targets.clear();
    ws.pieceOf.clear();
    ws.pieceValue.clear();
    for (const std::uint32_t p : ws.silhouette) {
        const PatchId j = ws.reversed[p];
        const Vec3& n = m_geometry.shapes[j].normal;
        bool split = false;
        for (std::uint32_t t = ws.termBegin[p]; t < ws.termEnd[p]; ++t) {
            if (ws.rayOf[t] == kNoRay) continue;
            if (!split) {  // the exact terms are kept; the ray terms are replaced by their pieces
                ws.handed[p] = -1.0f;
                ws.reversedTerm[p] = 0.0;
                for (std::uint32_t u = ws.termBegin[p]; u < ws.termEnd[p]; ++u)
                    if (ws.rayOf[u] == kNoRay && ws.factors[u] > 0.0) ws.reversedTerm[p] += ws.factors[u] * ws.termWeights[u];
                split = true;
            }
            const Vec3& x = ws.termPoint[t];
            const Vec3* polygon;
            const std::size_t corners = polygonAbove(i, x, n, ws.clipped, polygon);
            piecesOf(polygon, corners, ws);
            float origin[3];
            m_rays->toLocal(x + offset * n, origin);
            for (std::size_t q = 0; q < ws.pieces.size(); q += 4) {
                const double f = pointToPolygonFactor(x, n, &ws.pieces[q], 4);
                if (!(f > 0.0)) continue;
                float local[3];
                m_rays->toLocal(aimPoint(&ws.pieces[q], 4, j, i, ws.termIndex[t], std::uint32_t(q / 4 + 1)) +
                                    offset * receiver.normal,
                                local);
                ws.origins.insert(ws.origins.end(), origin, origin + 3);
                ws.targets.insert(ws.targets.end(), local, local + 3);
                ws.pieceOf.push_back(p);
                ws.pieceValue.push_back(f * ws.termWeights[t]);
            }
        }
    }
    if (ws.pieceOf.empty()) return;
    ws.blocked.assign(ws.pieceOf.size(), 0);
    m_rays->occludedSegmentPairs(ws.origins.data(), ws.targets.data(), ws.pieceOf.size(), ws.blocked.data());
    counts.rays += ws.pieceOf.size();
    for (std::size_t k = 0; k < ws.pieceOf.size(); ++k)
        if (!ws.blocked[k]) ws.reversedTerm[ws.pieceOf[k]] += ws.pieceValue[k];
}

void HemisphereBackend::piecesOf(const Vec3* polygon, std::size_t corners, Workspace& ws) const {
    ws.pieces.clear();
    splitPolygon(polygon, corners, ws.pieces);
    for (int level = 1; level < m_splitLevels; ++level) {
        ws.finer.clear();
        for (std::size_t q = 0; q < ws.pieces.size(); q += 4) splitPolygon(&ws.pieces[q], 4, ws.finer);
        ws.pieces.swap(ws.finer);
    }
}

std::size_t HemisphereBackend::polygonAbove(PatchId j, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer,
                                            const Vec3*& polygon) const {
    const PatchShape& t = m_geometry.shapes[j];
    polygon = &m_geometry.corners[t.first];
    const double height = n.dot(t.centroid - x);
    if (height <= -t.radius) return 0;
    bool below = false;
    if (height < t.radius)
        for (std::uint32_t k = 0; k < t.count && !below; ++k) below = n.dot(polygon[k] - x) < 0.0;
    if (!below) return t.count;
    clipAbovePlane(x, n, polygon, t.count, buffer);
    polygon = buffer.data();
    return buffer.size();
}

double HemisphereBackend::pointFactor(PatchId r, const Vec3& x, const Vec3& n, std::vector<Vec3>& buffer,
                                      const Vec3*& polygon, std::size_t& corners) const {
    const PatchShape& t = m_geometry.shapes[r];
    corners = 0;
    if (t.normal.dot(x - t.centroid) <= 1e-9 * t.radius) return 0.0;  // x must lie in front of r
    corners = polygonAbove(r, x, n, buffer, polygon);
    return corners == 0 ? 0.0 : pointToPolygonFactor(x, n, polygon, corners);
}

Vec3 HemisphereBackend::aimPoint(const Vec3* polygon, std::size_t corners, PatchId e, PatchId r, std::uint32_t point,
                                 std::uint32_t piece) const {
    if (!m_options.jitter) return vertexMean(polygon, corners);
    // Drawn from the pair alone, so both rows of a pair aim their shadow rays alike.
    Random random(((m_options.seed * 0x9e3779b97f4a7c15ULL ^ (std::uint64_t(e) << 32 | r)) + 0xa5a5a5a5deadbeefULL) ^
                  (std::uint64_t(point) << 40 | std::uint64_t(piece) << 8));
    const double u = random.uniform(), v = random.uniform();
    return pointOnPolygon(polygon, corners, u, v);
}

double HemisphereBackend::addAnalyticFrom(PatchId i, const Vec3& x, std::uint32_t point,
                                          const std::vector<PatchId>* candidates, double weight, Workspace& ws,
                                          RayCounts& counts) const {
    const Vec3& n = m_geometry.shapes[i].normal;
    const double offset = m_rays->originOffset();
    auto aim = [&](const Vec3* polygon, std::size_t corners, std::uint32_t piece, PatchId j, double f) {
        ws.candidates.push_back(j);
        ws.factors.push_back(f);
        if (!m_visibility) return;  // no shadow ray: no target
        float local[3];
        m_rays->toLocal(aimPoint(polygon, corners, i, j, point, piece) + offset * m_geometry.shapes[j].normal,
                        local);  // lifted off j towards x
        ws.targets.insert(ws.targets.end(), local, local + 3);
    };
    float origin[3];
    m_rays->toLocal(x + offset * n, origin);
    auto shoot = [&] {
        if (!m_visibility) {
            ws.blocked.assign(ws.candidates.size(), 0);
            return;
        }
        ws.blocked.resize(ws.candidates.size());
        m_rays->occludedSegments(origin, ws.targets.data(), ws.candidates.size(), ws.blocked.data());
        counts.rays += ws.candidates.size();
    };
    ws.candidates.clear();
    ws.factors.clear();
    ws.targets.clear();
    ws.exact.clear();
    ws.exactVisible.clear();
    ws.exactWhole.clear();
    const std::size_t count = candidates ? candidates->size() : m_geometry.shapes.size();
    for (std::size_t c = 0; c < count; ++c) {
        const PatchId j = candidates ? (*candidates)[c] : PatchId(c);
        if (j == i || (!candidates && (ws.ruled[j] || !emitsFor(i, j)))) continue;
        const Vec3* polygon;
        std::size_t corners;
        const double f = pointFactor(j, x, n, ws.clipped, polygon, corners);
        if (!(f > 0.0)) continue;
        if (f > m_exactAbove) {  // too large for one shadow ray's verdict: the visible part, exactly
            ws.exact.push_back(j);
            ws.exactVisible.push_back(m_shadows.visibleFactor(x, n, polygon, corners, i, j, f, ws.shadow));
            ws.exactWhole.push_back(f);
            ++counts.shadowTerms;
            continue;
        }
        aim(polygon, corners, 0, j, f);
    }
    shoot();
    // Visibility of each patch from its shadow ray; a patch whose mesh neighbours disagree with it
    // sits on a silhouette and is split into pieces, each with its own factor and shadow ray.
    for (std::size_t k = 0; k < ws.candidates.size(); ++k) ws.status[ws.candidates[k]] = ws.blocked[k] ? 2 : 1;
    double sum = 0.0;
    for (std::size_t k = 0; k < ws.exact.size(); ++k) {
        ws.status[ws.exact[k]] = ws.exactVisible[k] >= 0.5 * ws.exactWhole[k] ? 1 : 2;  // as its centre's ray would say
        keepTerm(ws.unsplit, ws.touched, ws.exact[k], ws.exactVisible[k] > 0.0 ? ws.exactVisible[k] * weight : 0.0);
        if (!(ws.exactVisible[k] > 0.0)) continue;
        ws.row.addWeight(ws.exact[k], ws.exactVisible[k] * weight);
        sum += ws.exactVisible[k] * weight;
    }
    ws.split.clear();
    for (std::size_t k = 0; k < ws.candidates.size(); ++k) {
        const PatchId j = ws.candidates[k];
        keepTerm(ws.unsplit, ws.touched, j, ws.blocked[k] ? 0.0 : ws.factors[k] * weight);
        if (m_geometry.onSilhouette(j, ws.status)) {
            ws.split.push_back(j);
        } else if (!ws.blocked[k]) {
            ws.row.addWeight(j, ws.factors[k] * weight);
            sum += ws.factors[k] * weight;
        }
    }
    if (!candidates) sum += addFarPairs(weight, ws);  // the centroid stands for the far rule's point too
    for (const PatchId j : ws.candidates) ws.status[j] = 0;
    for (const PatchId j : ws.exact) ws.status[j] = 0;
    if (ws.split.empty()) return sum;
    ws.candidates.clear();
    ws.factors.clear();
    ws.targets.clear();
    for (const PatchId j : ws.split) {
        const Vec3* polygon;
        const std::size_t corners = polygonAbove(j, x, n, ws.clipped, polygon);
        piecesOf(polygon, corners, ws);
        for (std::size_t q = 0; q < ws.pieces.size(); q += 4) {
            const double f = pointToPolygonFactor(x, n, &ws.pieces[q], 4);
            if (f > 0.0) aim(&ws.pieces[q], 4, std::uint32_t(q / 4 + 1), j, f);
        }
    }
    shoot();
    for (std::size_t k = 0; k < ws.candidates.size(); ++k) {
        if (ws.blocked[k]) continue;
        ws.row.addWeight(ws.candidates[k], ws.factors[k] * weight);
        sum += ws.factors[k] * weight;
    }
    return sum;
}

}  // namespace hemirad
