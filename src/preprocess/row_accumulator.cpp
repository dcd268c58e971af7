// Collecting a dense row into sorted entries.
#include "preprocess/row_accumulator.hpp"

#include <algorithm>

namespace hemirad {

std::vector<FormFactors::Entry> RowAccumulator::take(double countScale, double weightScale) {
    // Columns in order: sorting the touched list costs O(t log t); when a row touches more than
    // 1/16 of all patches, a scan of the dense arrays is cheaper (measured on the 12,696-patch box).
    const std::size_t n = m_count.size();
    if (m_touched.size() * 16 > n) {
        m_touched.clear();
        for (std::uint32_t j = 0; j < n; ++j)
            if (m_count[j] != 0 || m_weight[j] != 0.0) m_touched.push_back(j);
    } else {
        std::sort(m_touched.begin(), m_touched.end());
    }
    std::vector<FormFactors::Entry> entries;
    entries.reserve(m_touched.size());
    for (const std::uint32_t j : m_touched) {
        const double value = m_count[j] * countScale + m_weight[j] * weightScale;
        m_count[j] = 0;
        m_weight[j] = 0.0;
        if (value > 0.0) entries.push_back({j, static_cast<float>(value)});
    }
    m_touched.clear();
    return entries;
}

}  // namespace hemirad
