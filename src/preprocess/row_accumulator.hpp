// A dense per-thread accumulator for one row of F, collected into sorted sparse entries.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/math.hpp"

#include <vector>

namespace hemirad {

/// Sums deposits on patches j for one emitting patch. Integer counts serve equal-weight rays
/// (exact, no rounding); weights serve everything else. Memory: 12 bytes per patch.
class RowAccumulator {
public:
    explicit RowAccumulator(std::size_t patches) : m_count(patches, 0), m_weight(patches, 0.0) {}

    void addCount(PatchId j) {
        if (m_count[j]++ == 0 && m_weight[j] == 0.0) m_touched.push_back(j);
    }
    void addWeight(PatchId j, double w) {
        if (m_weight[j] == 0.0 && m_count[j] == 0) m_touched.push_back(j);
        m_weight[j] += w;
    }
    /// Entries F_ij = count * countScale + weight * weightScale, sorted by j; clears the accumulator.
    std::vector<FormFactors::Entry> take(double countScale, double weightScale);

private:
    std::vector<std::uint32_t> m_count;
    std::vector<double> m_weight;
    std::vector<std::uint32_t> m_touched;
};

}  // namespace hemirad
