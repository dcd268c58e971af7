// Collecting a dense row into sorted entries.
#include "preprocess/row_accumulator.hpp"

#include <algorithm>

namespace hemirad {
namespace {

/// Columns in order: sorting the touched list costs O(t log t); when a row touches more than 1/16
/// of all patches, one pass over the dense array is cheaper (measured on the 12,696-patch box).
template <class T>
std::vector<FormFactors::Entry> collect(std::vector<T>& dense, std::vector<std::uint32_t>& touched, double scale) {
    // A touched patch whose weight came back to 0 (deposits that cancel) gets no entry.
    std::vector<FormFactors::Entry> entries(touched.size());
    FormFactors::Entry* out = entries.data();
    const auto n = static_cast<std::uint32_t>(dense.size());
    std::size_t k = 0;
    if (touched.size() * 16 > n) {
        // Branch-free compaction: write every slot, advance only past nonzeros (rows here are ~75%
        // dense, where a branch mispredicts often).
        for (std::uint32_t j = 0; j < n && k < entries.size(); ++j) {
            const T value = dense[j];
            out[k] = {j, static_cast<double>(value * scale)};
            k += value != T(0);
            dense[j] = T(0);
        }
    } else {
        std::sort(touched.begin(), touched.end());
        for (const std::uint32_t j : touched) {
            out[k] = {j, static_cast<double>(dense[j] * scale)};
            k += dense[j] != T(0);
            dense[j] = T(0);
        }
    }
    entries.resize(k);
    touched.clear();
    return entries;
}

}  // namespace

std::vector<FormFactors::Entry> RowAccumulator::take(double scale) {
    return m_mode == Mode::Counts ? collect(m_count, m_touched, scale) : collect(m_weight, m_touched, scale);
}

}  // namespace hemirad
