// The thread-safe row builder and the row-sum bound of extended form factors.
#include "preprocess/form_factor_backend.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hemirad {

RayCounts& RayCounts::operator+=(const RayCounts& o) {
    rays += o.rays;
    bounces += o.bounces;
    misses += o.misses;
    backfaces += o.backfaces;
    lostWeight += o.lostWeight;
    lostArea += o.lostArea;
    rowArea += o.rowArea;
    cutoffWeight += o.cutoffWeight;
    rescaledRows += o.rescaledRows;
    shadowTerms += o.shadowTerms;
    shadowProbes += o.shadowProbes;
    cutPairs += o.cutPairs;
    cutWholePairs += o.cutWholePairs;
    contactPairs += o.contactPairs;
    contactShafts += o.contactShafts;
    contactEvaluations += o.contactEvaluations;
    straddlingPairs += o.straddlingPairs;
    penumbralPairs += o.penumbralPairs;
    coveredRows += o.coveredRows;
    largestDirectSum = std::max(largestDirectSum, o.largestDirectSum);
    convexSolids = std::max(convexSolids, o.convexSolids);
    solidFaces = std::max(solidFaces, o.solidFaces);
    return *this;
}

std::string lostPowerText(const RayCounts& counts, bool lossFromRays) {
    char text[192];
    if (lossFromRays)
        std::snprintf(text, sizeof text, "lost %.4g%% of the power (area-weighted; %llu misses, %llu back faces)",
                      100.0 * counts.lostFraction(), static_cast<unsigned long long>(counts.misses),
                      static_cast<unsigned long long>(counts.backfaces));
    else
        std::snprintf(text, sizeof text,
                      "%.4g%% of the power reached no patch (area-weighted; escaped, or behind back faces and shadow-ray misses)",
                      100.0 * counts.lostFraction());
    return text;
}

FormFactorBuilder::FormFactorBuilder(const Scene& scene)
    : m_rows(scene.size()), m_computed(scene.size(), 0), m_lost(scene.size(), -1.0), m_scene(scene) {}

void FormFactorBuilder::setRow(PatchId row, std::vector<FormFactors::Entry>&& entries, double lost) {
    m_rows[row] = std::move(entries);
    m_computed[row] = 1;
    m_lost[row] = std::max(0.0, lost);  // >= 0 marks the row as set (m_computed moves out in finish())
    m_done.fetch_add(1, std::memory_order_relaxed);
}

void FormFactorBuilder::addCounts(const RayCounts& counts) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_counts += counts;
}

RayCounts FormFactorBuilder::counts() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    RayCounts counts = m_counts;
    // Weighting by area here, where every back end hands over its rows, keeps it out of the back ends.
    for (PatchId i = 0; i < m_scene.size(); ++i)
        if (m_lost[i] >= 0.0) counts.lostArea += m_scene.patches[i].area * m_lost[i], counts.rowArea += m_scene.patches[i].area;
    return counts;
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

double extendedRowSumBound(const Scene& scene, std::uint32_t maxDepth, double minWeight) {
    double sMax = 0.0;
    for (const Patch& p : scene.patches) sMax = std::max(sMax, p.specular);
    double bound = 1.0, term = 1.0;
    for (std::uint32_t d = 0; d < maxDepth && sMax > 0.0 && term >= minWeight; ++d) bound += term *= sMax;
    return bound;
}

}  // namespace hemirad
