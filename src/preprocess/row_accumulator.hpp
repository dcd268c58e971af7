// A dense per-thread accumulator for one row of F, collected into sorted sparse entries.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/math.hpp"

#include <vector>

namespace hemirad {

/// Sums deposits on patches j for one emitting patch, in one of two modes: integer counts for
/// equal-weight rays (exact, no rounding) or double weights for everything else.
class RowAccumulator {
public:
    enum class Mode { Counts, Weights };

    RowAccumulator(std::size_t patches, Mode mode)
        : m_mode(mode), m_count(mode == Mode::Counts ? patches : 0, 0),
          m_weight(mode == Mode::Weights ? patches : 0, 0.0) {}

    void addCount(PatchId j) {
        if (m_count[j]++ == 0) m_touched.push_back(j);
    }
    void addWeight(PatchId j, double w) {
        double& x = m_weight[j];
        if (x == 0.0) m_touched.push_back(j);
        x += w;
    }
    /// The weight deposited on j so far (Weights mode).
    double weight(PatchId j) const { return m_weight[j]; }
    /// Multiplies every weight deposited so far by `factor` (Weights mode).
    void scaleWeights(double factor) {
        for (const std::uint32_t j : m_touched) m_weight[j] *= factor;
    }
    /// Entries F_ij = count * scale (Counts) or weight * scale (Weights), sorted by j; clears the row.
    std::vector<FormFactors::Entry> take(double scale);

private:
    Mode m_mode;
    std::vector<std::uint32_t> m_count;
    std::vector<double> m_weight;
    std::vector<std::uint32_t> m_touched;
};

}  // namespace hemirad
