// The hemisphere back end's registry entry: its flags, work estimate and run description.
#include "preprocess/backend_registry.hpp"

#include "engine/memory.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"
#include "preprocess/hemisphere/hemisphere_backend.hpp"
#include "preprocess/hemisphere/reflectors.hpp"

#include <cmath>
#include <cstdio>

namespace hemirad {

bool usesAnalyticEstimator(const HemisphereOptions& options, std::size_t) {
    return options.estimator != Estimator::Rays;  // auto: the exact estimator unless resolveAuto chose rays
}

namespace {

using H = HemisphereOptions;

/// Whether the analytic estimator's mirror terms come from virtual images (else rays carry them);
/// `why` says why not where images were asked for.
bool mirrorImages(const Scene& scene, const H& o, std::string* why = nullptr) {
    if (!scene.hasMirrors() || o.mirrorEstimator != MirrorEstimator::Images) return false;
    std::vector<Reflector> reflectors;
    const std::string refused = findReflectors(scene, reflectors);
    if (why) *why = refused;
    return refused.empty();
}

/// Rays one row costs: samples x origins, or one shadow ray per patch and origin point for the
/// analytic estimator (plus the directions when rays carry the mirror chains).
double workPerRow(const Scene& scene, const MethodSettings& s) {
    const H& o = s.as<H>();
    const double rays = double(o.samples) * o.origins;
    if (!usesAnalyticEstimator(o, scene.size())) return rays;
    const bool chainRays = scene.hasMirrors() && !mirrorImages(scene, o);
    return double(scene.size()) * originPoints(o.origins) + (chainRays ? rays : 0.0);
}

/// Scratch one worker thread holds (the estimators' and the mirror images' workspaces):
/// dense per-patch arrays, lists that can reach one entry per patch, and one origin's directions.
double bytesPerThread(const Scene& scene, const MethodSettings& s) {
    const H& o = s.as<H>();
    const bool analytic = usesAnalyticEstimator(o, scene.size());
    // The row: its sums (double weights, or 32-bit counts for plain rays) and the patches touched.
    double perPatch = (analytic || scene.hasMirrors() ? 8.0 : 4.0) + 4.0;
    if (analytic) {
        perPatch += 1.0 + 1.0 + 8.0 + 8.0;        // ruled, status, published, unsplit
        perPatch += 4.0 + 4.0 + 8.0 + 4.0 + 12.0;  // by order, candidates, factors, touched, outgoing
        perPatch += 4.0 + 8.0 + 8.0 + 8.0;        // as a receiver: emitters, their sums, entries, term ranges
        // The mirror images' workspaces, the row's and a pair's: status, summed, sums, published.
        if (mirrorImages(scene, o)) perPatch += 2.0 * (1.0 + 1.0 + 8.0 + 8.0);
    }
    const double directions = (o.jitter ? 24.0 : 12.0) + 4.0 + 4.0;  // rotated (and jittered), hits, distances
    return perPatch * double(scene.size()) + directions * double(o.samples);
}

RunDescription describe(const Scene& scene, const MethodSettings& s) {
    const H& o = s.as<H>();
    RunDescription d;
    const bool analytic = usesAnalyticEstimator(o, scene.size());
    if (analytic) {
        std::string refused;
        const bool images = mirrorImages(scene, o, &refused);
        d.settings = std::string("analytic estimator (Lambert factors; where some patch can obstruct, the exact visible part for "
                                 "terms above 1e-") + std::to_string(o.pairDigits + 1) + " and one shadow ray for the rest" +
                     (o.pairs == PairMethod::Whole ? std::string("; every pair whole (--pairs whole), hidden parts to 1e-") +
                                                         std::to_string(o.pairDigits + 2)
                                                   : std::string()) +
                     (images ? std::string("; mirror terms by virtual images, no directions cast")
                      : scene.hasMirrors()
                          ? "; " + std::to_string(o.samples) + " directions carry the mirror chains" +
                                (refused.empty() ? std::string() : " (" + refused + ")")
                          : std::string("; no directions cast: --samples only chose the estimator")) +
                     "), " +
                     (o.origins == 1 ? std::string("centroid")
                                     : std::to_string(originPoints(o.origins)) +
                                           " Gauss-Legendre origins per quad (--origins " + std::to_string(o.origins) + ")");
        d.lossFromRays = false;  // no ray tells misses from hidden patches: 1 - row sum reached no patch
    } else {
        d.settings = std::to_string(o.samples) + " directions x " + std::to_string(o.origins) +
                     (o.origins == 1 ? " origin (centroid)" : " origins");
    }
    if (o.jitter) d.settings += ", jittered";
    d.record = {{"samples", std::to_string(o.samples)},
                {"origins", std::to_string(o.origins)},
                {"rays_per_patch", std::to_string(double(o.samples) * o.origins)},
                {"directions", o.fixedDirections ? "fixed" : "rotated"},
                {"estimator", analytic ? "analytic" : "rays"},
                {"mirror_estimator", o.mirrorEstimator == MirrorEstimator::Images ? "images" : "rays"}};
    return d;
}

// Why an option changes nothing in this run (empty: it matters), shown next to its field.

bool castsNoDirections(const Scene& scene, const H& o) {
    return usesAnalyticEstimator(o, scene.size()) && !(scene.hasMirrors() && !mirrorImages(scene, o));
}

std::string unusedSamples(const Scene& scene, const MethodSettings& s) {
    const H& o = s.as<H>();
    if (!castsNoDirections(scene, o)) return {};
    return o.estimator == Estimator::Auto ? "unused: the analytic estimator casts no directions (auto falls back to the "
                                            "rays, which cast them, only where the exact F would not fit in memory)"
                                          : "unused: the analytic estimator casts no directions";
}

std::string unusedFixedDirections(const Scene& scene, const MethodSettings& s) {
    return castsNoDirections(scene, s.as<H>()) ? "unused: the analytic estimator casts no directions" : "";
}

std::string unusedPairDigits(const Scene& scene, const MethodSettings& s) {
    return usesAnalyticEstimator(s.as<H>(), scene.size()) ? "" : "unused: only the analytic estimator has a pair rule";
}

std::string unusedMirrorTerms(const Scene& scene, const MethodSettings& s) {
    if (!scene.hasMirrors()) return "unused: the scene has no mirrors";
    return usesAnalyticEstimator(s.as<H>(), scene.size()) ? "" : "unused: the rays estimator follows its rays";
}

/// --estimator auto: the exact (analytic) estimator wherever its F fits in the memory budget, from
/// the bound or, when that is too loose, 64 sample rows; the rays only where it would not fit.
std::string resolveAuto(const Scene& /*scene*/, MethodSettings& s, const std::function<MemoryPrediction(const MethodSettings&)>& predict,
                        double budget) {
    H& o = s.as<H>();
    if (o.estimator != Estimator::Auto) return {};
    o.estimator = Estimator::Analytic;
    if (!(budget > 0.0)) return "estimator auto: analytic (exact factors; the available memory is unknown)";
    const MemoryPrediction p = predict(s);
    char perRow[64];
    std::snprintf(perRow, sizeof perRow, "%.0f nonzeros per row", p.nonzerosPerRow);
    const std::string basis = p.sampledRows ? std::string(perRow) + " measured on " + std::to_string(p.sampledRows) + " rows"
                                            : std::string("at most one entry per patch");
    if (p.bytes <= budget)
        return "estimator auto: analytic (exact factors): F needs about " + bytesText(p.bytes) + " (" + basis +
               ") of the " + bytesText(budget) + " available";
    o.estimator = Estimator::Rays;
    const MemoryPrediction rays = predict(s);
    return "estimator auto: rays, because the exact F would need about " + bytesText(p.bytes) + " (" + basis +
           "), more than the " + bytesText(budget) + " available (the rays' F: about " + bytesText(rays.bytes) +
           "); --estimator analytic insists";
}

BackendDescriptor make() {
    BackendDescriptor d;
    d.name = H::kMethod;
    d.summary = "Embree rays along Beckers directions, or Lambert's exact factors with shadow rays";
    d.workUnit = "rays";
    d.options = {
        integerOption<H>("--samples", "Directions", "N", "Beckers directions per origin (default 3072)", &H::samples, 1,
                         1 << 24),
        integerOption<H>("--origins", "Origins", "K", "ray origins per patch, stratified over its area (default 1 = centroid)",
                         &H::origins, 1, 1 << 16),
        integerOption<H>("--seed", "Seed", "S", "seed for origin jitter and pattern rotation (default 1)", &H::seed, 0,
                         0x7fffffffffffffffL),
        switchOption<H>("--fixed-directions", "Fixed directions",
                        "no random rotation of the pattern (the reference system's method)", &H::fixedDirections, true),
        switchOption<H>("--jitter", "Jitter",
                        "a random direction within each Beckers cell (unbiased, stratified); with the analytic "
                        "estimator, shadow rays to random points instead of centres",
                        &H::jitter, true),
        choiceOption<H, Estimator>("--estimator", "Estimator",
                                   "direct factors from ray counts, or Lambert's exact point-to-polygon factor for each "
                                   "patch a shadow ray finds visible; auto (default): analytic wherever its F fits in "
                                   "memory (predicted from 64 sample rows when the bound is too loose), rays only where "
                                   "it would not (the report says which and why)",
                                   &H::estimator,
                                   {{"auto", Estimator::Auto}, {"rays", Estimator::Rays}, {"analytic", Estimator::Analytic}}),
        choiceOption<H, MirrorEstimator>("--mirror-estimator", "Mirror terms",
                                         "the analytic estimator's factors through mirrors: exact from virtual images "
                                         "(default; a mirror that is not planar and convex falls back to rays, said in "
                                         "the report) or Monte Carlo along the directions; the ray estimator always "
                                         "follows its rays",
                                         &H::mirrorEstimator,
                                         {{"images", MirrorEstimator::Images}, {"rays", MirrorEstimator::Rays}}),
        integerOption<H>("--pair-digits", "Pair digits", "D",
                         "the analytic estimator's rule over each pair aims at a relative error of 10^-D (default 2: "
                         "wall-to-wall factors of a subdivided cube within 1e-6; 4 for reference F, ~2x the time there, more where "
                         "close pairs have blockers between them: their hidden parts go to 10^-(D+2)); terms above "
                         "10^-(D+1) get the exact visible part past blockers instead of one shadow ray",
                         &H::pairDigits, 1, 8),
        choiceOption<H, PairMethod>("--pairs", "Pairs",
                                    "the analytic estimator's pairs: rules (default: each pair integrated over the "
                                    "emitter's points, close pairs and pairs across a shadow's edge whole) or whole "
                                    "(every pair by its double contour integral less the hidden part, refined to "
                                    "10^-(D+2) of the pair: a converged reference F, O(n^2) contour integrals; "
                                    "with --pair-digits 4 for 1e-6)",
                                    &H::pairs, {{"rules", PairMethod::Rules}, {"whole", PairMethod::Whole}}),
    };
    for (BackendOption& option : d.options) {
        if (option.flag == "--samples") option.unusedBecause = unusedSamples;
        if (option.flag == "--fixed-directions") option.unusedBecause = unusedFixedDirections;
        if (option.flag == "--pair-digits" || option.flag == "--pairs") option.unusedBecause = unusedPairDigits;
        if (option.flag == "--mirror-estimator") option.unusedBecause = unusedMirrorTerms;
    }
    d.defaults = [] { return std::any(H{}); };
    d.validate = [](const MethodSettings& s) {
        const H& o = s.as<H>();
        if (o.samples < 1) throw Error("--samples must be at least 1");
        if (o.origins < 1) throw Error("--origins must be at least 1");
    };
    d.create = [](const MethodSettings& s) -> std::unique_ptr<FormFactorBackend> {
        return std::make_unique<HemisphereBackend>(s.as<H>(), s.common);
    };
    d.workPerRow = workPerRow;
    d.bytesPerThread = bytesPerThread;
    d.describe = describe;
    d.resolve = resolveAuto;
    return d;
}

}  // namespace

const BackendDescriptor& hemisphereDescriptor() {
    static const BackendDescriptor descriptor = make();
    return descriptor;
}

}  // namespace hemirad
