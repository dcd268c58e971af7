// Back-end factory and the thread-safe row builder.
#include "preprocess/form_factor_backend.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include "preprocess/hemicube/hemicube_backend.hpp"
#include "preprocess/hemisphere/hemisphere_backend.hpp"

namespace hemirad {

RayCounts& RayCounts::operator+=(const RayCounts& o) {
    rays += o.rays;
    bounces += o.bounces;
    misses += o.misses;
    backfaces += o.backfaces;
    lostWeight += o.lostWeight;
    cutoffWeight += o.cutoffWeight;
    rescaledRows += o.rescaledRows;
    largestDirectSum = std::max(largestDirectSum, o.largestDirectSum);
    return *this;
}

FormFactorBuilder::FormFactorBuilder(std::size_t patches) : m_rows(patches), m_computed(patches, 0) {}

void FormFactorBuilder::setRow(PatchId row, std::vector<FormFactors::Entry>&& entries) {
    m_rows[row] = std::move(entries);
    m_computed[row] = 1;
    m_done.fetch_add(1, std::memory_order_relaxed);
}

void FormFactorBuilder::addCounts(const RayCounts& counts) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_counts += counts;
}

RayCounts FormFactorBuilder::counts() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_counts;
}

void FormFactorBuilder::addStageSeconds(const std::string& stage, double seconds) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stageSeconds[stage] += seconds;
}

std::map<std::string, double> FormFactorBuilder::stageSeconds() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_stageSeconds;
}

FormFactors FormFactorBuilder::finish() { return FormFactors::fromRows(std::move(m_rows), std::move(m_computed)); }

std::string rowSumBoundText(const Scene& scene, std::uint32_t maxDepth, double minWeight) {
    double sMax = 0.0;
    for (const Patch& p : scene.patches) sMax = std::max(sMax, p.specular);
    double bound = 1.0, term = 1.0;
    for (std::uint32_t d = 0; d < maxDepth && sMax > 0.0 && term >= minWeight; ++d) bound += term *= sMax;
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", bound);
    return text;
}

bool usesAnalyticEstimator(const BackendOptions& options, std::size_t patches) {
    if (options.estimator == "analytic") return true;
    return options.estimator == "auto" && double(patches) <= kAnalyticRaysFactor * double(options.samples);
}

std::uint32_t analyticOriginPoints(std::uint32_t origins) {
    if (origins <= 1) return 1;
    const auto m = static_cast<std::uint32_t>(std::ceil(std::sqrt(double(origins)) - 1e-9));
    return m * m;
}

double expectedRaysPerRow(const Scene& scene, std::string_view method, const BackendOptions& options) {
    if (method == "hemicube") return 3.0 * options.resolution * options.resolution;
    const double rays = double(options.samples) * options.origins;
    if (!usesAnalyticEstimator(options, scene.size())) return rays;
    return double(scene.size()) * analyticOriginPoints(options.origins) + (scene.hasMirrors() ? rays : 0.0);
}

std::unique_ptr<FormFactorBackend> makeBackend(std::string_view name, const BackendOptions& options) {
    if (options.samples < 1) throw Error("--samples must be at least 1");
    if (options.origins < 1) throw Error("--origins must be at least 1");
    if (!(options.minWeight > 0.0 && options.minWeight < 1.0)) throw Error("minimum ray weight must be in (0, 1)");
    if (options.estimator != "rays" && options.estimator != "analytic" && options.estimator != "auto")
        throw Error("unknown estimator '" + options.estimator + "' (auto, rays, analytic)");
    if (options.estimator == "analytic" && name != "hemisphere")
        throw Error("--estimator analytic needs --method hemisphere");
    if (name == "hemisphere") return std::make_unique<HemisphereBackend>(options);
    if (name == "hemicube") return std::make_unique<HemicubeBackend>(options);
    throw Error("unknown --method '" + std::string(name) + "' (hemisphere, hemicube)");
}

}  // namespace hemirad
