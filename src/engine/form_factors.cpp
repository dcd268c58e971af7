// CSR form factors: construction, lookup, statistics, reciprocity enforcement and validation.
#include "engine/form_factors.hpp"

#include "engine/error.hpp"
#include "engine/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace hemirad {

std::size_t FormFactors::memoryBytes() const {
    return m_rowStart.size() * sizeof(std::uint64_t) + m_columns.size() * sizeof(std::uint32_t) +
           m_values.size() * sizeof(float) + m_computed.size();
}

std::size_t FormFactors::computedRows() const {
    return static_cast<std::size_t>(std::count(m_computed.begin(), m_computed.end(), 1));
}

double FormFactors::rowSum(std::size_t i) const {
    double sum = 0.0;
    for (std::uint64_t k = m_rowStart[i]; k < m_rowStart[i + 1]; ++k) sum += m_values[k];
    return sum;
}

double FormFactors::at(std::size_t i, std::size_t j) const {
    const std::uint32_t* first = m_columns.data() + m_rowStart[i];
    const std::uint32_t* last = m_columns.data() + m_rowStart[i + 1];
    const std::uint32_t* it = std::lower_bound(first, last, static_cast<std::uint32_t>(j));
    return (it != last && *it == j) ? m_values[it - m_columns.data()] : 0.0;
}

FormFactors FormFactors::fromRows(std::vector<std::vector<Entry>>&& rows, std::vector<std::uint8_t> computed) {
    FormFactors F(rows.size());
    std::uint64_t nnz = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        F.m_rowStart[i] = nnz;
        nnz += rows[i].size();
    }
    F.m_rowStart[rows.size()] = nnz;
    F.m_columns.resize(nnz);
    F.m_values.resize(nnz);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        std::uint64_t k = F.m_rowStart[i];
        for (const Entry& e : rows[i]) {
            F.m_columns[k] = e.column;
            F.m_values[k++] = e.value;
        }
        std::vector<Entry>().swap(rows[i]);  // release as we go: peak memory stays near one copy
    }
    F.m_computed = std::move(computed);
    return F;
}

FormFactors FormFactors::fromCsr(std::vector<std::uint64_t>&& rowStart, std::vector<std::uint32_t>&& columns,
                                 std::vector<float>&& values, std::vector<std::uint8_t>&& computed) {
    FormFactors F;
    F.m_rowStart = std::move(rowStart);
    F.m_columns = std::move(columns);
    F.m_values = std::move(values);
    F.m_computed = std::move(computed);
    return F;
}

void FormFactors::replaceRows(const FormFactors& other) {
    if (other.size() != size()) throw Error("replaceRows: matrices of different sizes");
    std::vector<std::vector<Entry>> rows(size());
    std::vector<std::uint8_t> computed = m_computed;
    for (std::size_t i = 0; i < size(); ++i) {
        const FormFactors& src = other.rowComputed(i) ? other : *this;
        for (std::uint64_t k = src.rowBegin(i); k < src.rowEnd(i); ++k)
            rows[i].push_back({src.m_columns[k], src.m_values[k]});
        computed[i] = m_computed[i] | other.m_computed[i];
    }
    const std::uint64_t hash = sceneHash;
    auto params = parameters;
    *this = fromRows(std::move(rows), std::move(computed));
    sceneHash = hash;
    parameters = std::move(params);
}

FormFactorStats computeStats(const FormFactors& F, const Scene& scene) {
    FormFactorStats s;
    s.rows = F.size();
    s.nonZeros = F.nonZeros();
    s.rowSumMin = std::numeric_limits<double>::infinity();
    s.rowSumMax = -s.rowSumMin;
    double sum = 0.0, violation = 0.0, exchanged = 0.0;
    for (std::size_t i = 0; i < F.size(); ++i) {
        if (!F.rowComputed(i)) continue;
        ++s.computedRows;
        const double r = F.rowSum(i);
        s.rowSumMin = std::min(s.rowSumMin, r);
        s.rowSumMax = std::max(s.rowSumMax, r);
        sum += r;
        const double Ai = scene.patches[i].area;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            const std::size_t j = F.columns()[k];
            if (j == i) {
                ++s.selfFactors;
                continue;
            }
            if (!F.rowComputed(j)) continue;
            const double a = Ai * F.values()[k];
            const double b = scene.patches[j].area * F.at(j, i);
            const double diff = std::abs(a - b);
            s.reciprocityMax = std::max(s.reciprocityMax, diff / std::max(a, b));
            violation += diff;
            exchanged += a + b;
        }
        // Entries F_ji > 0 with F_ij = 0 are counted from row j's side when it is visited.
    }
    if (s.computedRows == 0) s.rowSumMin = s.rowSumMax = 0.0;
    s.rowSumMean = s.computedRows ? sum / static_cast<double>(s.computedRows) : 0.0;
    s.reciprocityMean = exchanged > 0 ? violation / exchanged : 0.0;
    return s;
}

std::size_t enforceReciprocity(FormFactors& F, const Scene& scene) {
    const std::size_t n = F.size();
    std::vector<std::vector<FormFactors::Entry>> rows(n);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!F.rowComputed(i)) continue;
        const double Ai = scene.patches[i].area;
        rows[i].reserve(F.rowEnd(i) - F.rowBegin(i));
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            const std::uint32_t j = F.columns()[k];
            double v = F.values()[k];
            if (j != i && F.rowComputed(j)) {
                const double mean = 0.5 * (Ai * v + scene.patches[j].area * F.at(j, i));
                const double nv = mean / Ai;
                if (nv != v) ++changed;
                v = nv;
            }
            rows[i].push_back({j, static_cast<float>(v)});
        }
    }
    // Partners: F_ji > 0 where F_ij is absent gets F_ij = A_j F_ji / (2 A_i).
    std::vector<std::vector<FormFactors::Entry>> extra(n);
    for (std::size_t j = 0; j < n; ++j) {
        if (!F.rowComputed(j)) continue;
        for (std::uint64_t k = F.rowBegin(j); k < F.rowEnd(j); ++k) {
            const std::uint32_t i = F.columns()[k];
            if (i == j || !F.rowComputed(i) || F.at(i, j) != 0.0) continue;
            const double v = 0.5 * scene.patches[j].area * F.values()[k] / scene.patches[i].area;
            extra[i].push_back({static_cast<std::uint32_t>(j), static_cast<float>(v)});
            ++changed;
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (extra[i].empty()) continue;
        rows[i].insert(rows[i].end(), extra[i].begin(), extra[i].end());
        std::sort(rows[i].begin(), rows[i].end(),
                  [](const FormFactors::Entry& a, const FormFactors::Entry& b) { return a.column < b.column; });
    }
    const std::uint64_t hash = F.sceneHash;
    auto params = F.parameters;
    F = FormFactors::fromRows(std::move(rows), F.computedFlags());
    F.sceneHash = hash;
    F.parameters = std::move(params);
    F.parameters["reciprocity"] = "enforced";
    return changed;
}

double rowSumBound(const FormFactors& F) {
    double bound = 1.0;
    const auto it = F.parameters.find("row_sum_bound");
    if (it != F.parameters.end()) {
        char* end = nullptr;
        const double value = std::strtod(it->second.c_str(), &end);
        if (*end != '\0' || !(value >= 1.0) || !std::isfinite(value))
            throw Error("form factors: bad parameter row_sum_bound '" + it->second + "'");
        bound = value;
    }
    return bound + 1e-3;
}

void validateFormFactors(const FormFactors& F, std::size_t patchCount, const std::string& source,
                         double maxRowSum) {
    if (F.size() != patchCount)
        throw Error(source, 0, "form factors are for " + std::to_string(F.size()) + " patches, the scene has " +
                                   std::to_string(patchCount));
    for (std::size_t i = 0; i < F.size(); ++i) {
        double sum = 0.0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            const float v = F.values()[k];
            if (!std::isfinite(v) || v < 0.0f) {
                std::ostringstream msg;
                msg << "F(" << i << ", " << F.columns()[k] << ") = " << v << " is not a finite non-negative number";
                throw Error(source, 0, msg.str());
            }
            sum += v;
        }
        if (sum > maxRowSum) {
            std::ostringstream msg;
            msg << "row " << i << " of F sums to " << sum << ", above the bound " << maxRowSum
                << ": more power arrives than leaves";
            throw Error(source, 0, msg.str());
        }
    }
}

}  // namespace hemirad
