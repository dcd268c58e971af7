// CSR form factors: construction, lookup, statistics, reciprocity enforcement and validation.
#include "engine/form_factors.hpp"

#include "engine/interleaved_rows.hpp"

#include "engine/wide_kernels.hpp"

#include "engine/error.hpp"
#include "engine/parallel_failure.hpp"
#include "engine/scene.hpp"
#include "engine/text_reader.hpp"

#include <omp.h>
#ifdef __GLIBC__
#include <malloc.h>  // malloc_trim
#endif

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace hemirad {

std::size_t FormFactors::memoryBytes() const {
    return m_rowStart.size() * sizeof(std::uint64_t) + m_columns.size() * sizeof(std::uint32_t) +
           m_values.size() * sizeof(double) + m_computed.size();
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
    // Reserved, not resized: the arrays' pages are touched only as rows move in, while the rows
    // move out and their pages go back to the system, so the peak stays near one copy of F
    // rather than two (freed rows stay in the allocator's heap until trimmed).
    F.m_columns.reserve(nnz);
    F.m_values.reserve(nnz);
    std::size_t freed = 0;
    for (std::vector<Entry>& row : rows) {
        const std::size_t at = F.m_columns.size();  // within the capacity reserved: no reallocation
        F.m_columns.resize(at + row.size());
        F.m_values.resize(at + row.size());
        std::uint32_t* columns = F.m_columns.data() + at;
        double* values = F.m_values.data() + at;
        for (std::size_t k = 0; k < row.size(); ++k) {
            columns[k] = row[k].column;
            values[k] = row[k].value;
        }
        freed += row.capacity() * sizeof(Entry);
        std::vector<Entry>().swap(row);
#ifdef __GLIBC__
        if (freed >= (std::size_t(32) << 20)) {
            malloc_trim(0);
            freed = 0;
        }
#endif
    }
    F.m_computed = std::move(computed);
    return F;
}

FormFactors FormFactors::fromCsr(std::vector<std::uint64_t>&& rowStart, std::vector<std::uint32_t>&& columns,
                                 std::vector<double>&& values, std::vector<std::uint8_t>&& computed) {
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
    const FormFactorProvenance kept = provenance;
    *this = fromRows(std::move(rows), std::move(computed));
    sceneHash = hash;
    provenance = kept;
    parameters = std::move(params);
}

TransposedFormFactors transpose(const FormFactors& F) {
    // Parallel counting sort: thread t owns a contiguous block of rows and, for every column, a
    // slot range after the earlier threads' entries, so each column lists its rows in order.
    const std::size_t n = F.size();
    const int threads = std::max(1, std::min(omp_get_max_threads(), int(n / 1024) + 1));
    std::vector<std::size_t> bounds(threads + 1);
    for (int t = 0; t <= threads; ++t) bounds[t] = n * std::size_t(t) / threads;
    std::vector<std::uint64_t> counts(std::size_t(threads) * n, 0);
#pragma omp parallel for num_threads(threads) schedule(static, 1)
    for (int t = 0; t < threads; ++t) {
        std::uint64_t* mine = &counts[std::size_t(t) * n];
        for (std::uint64_t k = F.rowBegin(bounds[t]); k < F.rowBegin(bounds[t + 1]); ++k) ++mine[F.columns()[k]];
    }
    TransposedFormFactors out;
    out.start.assign(n + 1, 0);
    for (std::size_t j = 0; j < n; ++j) {
        std::uint64_t offset = out.start[j];
        for (int t = 0; t < threads; ++t) {
            const std::uint64_t c = counts[std::size_t(t) * n + j];
            counts[std::size_t(t) * n + j] = offset;  // becomes thread t's next slot in column j
            offset += c;
        }
        out.start[j + 1] = offset;
    }
    out.rows.resize(F.nonZeros());
    out.values.resize(F.nonZeros());
#pragma omp parallel for num_threads(threads) schedule(static, 1)
    for (int t = 0; t < threads; ++t) {
        std::uint64_t* next = &counts[std::size_t(t) * n];
        for (std::size_t i = bounds[t]; i < bounds[t + 1]; ++i)
            for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
                const std::uint64_t slot = next[F.columns()[k]]++;
                out.rows[slot] = static_cast<std::uint32_t>(i);
                out.values[slot] = F.values()[k];
            }
    }
    return out;
}

RowBlock nonZeroBlock(const FormFactors& F, std::size_t block, std::size_t blocks) {
    const std::uint64_t* starts = F.rowStarts().data();
    const std::size_t n = F.size();
    // Block b starts at the first row whose entries start at or past b / blocks of all.
    auto boundary = [&](std::size_t b) {
        if (b == 0) return std::size_t(0);
        if (b >= blocks) return n;
        const std::uint64_t target = F.nonZeros() * b / blocks;
        return std::size_t(std::lower_bound(starts, starts + n, target) - starts);
    };
    return {boundary(block), boundary(block + 1)};
}

FormFactorStats computeStats(const FormFactors& F, const Scene& scene) {
    FormFactorStats s;
    s.rows = F.size();
    s.nonZeros = F.nonZeros();
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0.0, violation = 0.0, exchanged = 0.0;
    double worst = 0.0;
    std::size_t computed = 0, self = 0;
    // F_ji by MirrorCursors, each thread over its block of rows.
    // A pair with both entries is visited from each of its rows; one with a single entry only from
    // that row, so it counts twice there: the sums are those of a walk over rows and columns.
    ParallelFailure failure;  // a thread's cursors failing to allocate: rethrown after the region
#pragma omp parallel reduction(min : lo) reduction(max : hi, worst) reduction(+ : sum, violation, exchanged, computed, self)
    failure.run([&] {
        const RowBlock block = nonZeroBlock(F, std::size_t(omp_get_thread_num()), std::size_t(omp_get_num_threads()));
        if (block.first == block.last) return;
        MirrorCursors mirror(F);
        for (std::size_t i = block.first; i < block.last; ++i) {
            if (!F.rowComputed(i)) continue;
            ++computed;
            const double r = F.rowSum(i);
            lo = std::min(lo, r);
            hi = std::max(hi, r);
            sum += r;
            const double Ai = scene.patches[i].area;
            for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
                const std::uint32_t j = F.columns()[k];
                const double fij = F.values()[k];
                if (j == std::uint32_t(i)) {
                    self += fij > 0.0;
                    continue;
                }
                if (!F.rowComputed(j) || !(fij > 0.0)) continue;
                const std::uint64_t at = mirror.find(j, std::uint32_t(i));
                const double fji = at == MirrorCursors::kNone ? 0.0 : F.values()[at];
                const double a = Ai * fij, b = scene.patches[j].area * fji;
                const double visits = fji > 0.0 ? 1.0 : 2.0;
                const double diff = std::abs(a - b);
                worst = std::max(worst, diff / std::max(a, b));
                violation += visits * diff;
                exchanged += visits * (a + b);
            }
        }
    });
    failure.rethrowIfFailed();
    s.computedRows = computed;
    s.selfFactors = self;
    s.rowSumMin = computed ? lo : 0.0;
    s.rowSumMax = computed ? hi : 0.0;
    s.rowSumMean = computed ? sum / double(computed) : 0.0;
    s.reciprocityMax = worst;
    s.reciprocityMean = exchanged > 0 ? violation / exchanged : 0.0;
    return s;
}

double normalizeRows(FormFactors& F) {
    double worst = 0.0;
    for (std::size_t i = 0; i < F.size(); ++i) {
        if (!F.rowComputed(i)) continue;
        const double sum = F.rowSum(i);
        if (!(sum > 0.0)) continue;
        worst = std::max(worst, std::abs(sum - 1.0));
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k)
            F.values()[k] = F.values()[k] / sum;
    }
    F.parameters["rows"] = "normalised to sum 1";
    return worst;
}

double rowSumBound(const FormFactors& F) { return rowSumBound(F.provenance); }
double rowSumBound(const FormFactorProvenance& provenance) { return provenance.rowSumBound + 1e-3; }

namespace {

/// The estimator's kind: the value's first word ("analytic: Lambert ..." -> "analytic").
std::string estimatorKind(const std::string& text) { return text.substr(0, text.find_first_of(": ")); }

}  // namespace

FormFactorProvenance takeProvenance(std::map<std::string, std::string>& parameters, const std::string& source) {
    FormFactorProvenance p;
    if (auto it = parameters.find("method"); it != parameters.end()) {
        p.method = it->second;
        parameters.erase(it);
    }
    if (auto it = parameters.find("estimator"); it != parameters.end()) {
        p.estimator = estimatorKind(it->second);
        if (it->second == p.estimator) parameters.erase(it);  // no description beyond the kind
    }
    if (auto it = parameters.find("row_sum_bound"); it != parameters.end()) {
        char* end = nullptr;
        const double value = std::strtod(it->second.c_str(), &end);
        if (it->second.empty() || *end != '\0' || !std::isfinite(value) || value < 1.0)
            throw Error(source, 0, "bad parameter row_sum_bound '" + it->second + "' (a number >= 1)");
        p.rowSumBound = value;
        parameters.erase(it);
    }
    if (auto it = parameters.find("scene_hash"); it != parameters.end()) {
        if (it->second != "unknown") throw Error(source, 0, "bad parameter scene_hash '" + it->second + "' (only 'unknown')");
        p.sceneHashKnown = false;
        parameters.erase(it);
    }
    return p;
}

std::map<std::string, std::string> withProvenance(const FormFactorProvenance& provenance,
                                                  std::map<std::string, std::string> parameters) {
    if (!provenance.method.empty()) parameters["method"] = provenance.method;
    if (!provenance.estimator.empty()) {
        auto it = parameters.find("estimator");
        if (it == parameters.end() || estimatorKind(it->second) != provenance.estimator)
            parameters["estimator"] = provenance.estimator;
    }
    char bound[32];
    std::snprintf(bound, sizeof bound, "%.9g", provenance.rowSumBound);
    parameters["row_sum_bound"] = bound;
    if (!provenance.sceneHashKnown) parameters["scene_hash"] = "unknown";
    return parameters;
}

namespace {

bool holdsControl(const std::string& text) {
    return std::any_of(text.begin(), text.end(), [](char c) { return static_cast<unsigned char>(c) < 32 || c == 127; });
}

/// Why an F file cannot store `key` as it is, or null.
const char* keyProblem(const std::string& key) {
    if (key.empty()) return "is empty";
    if (holdsControl(key)) return "holds a control character";
    if (key.find('=') != std::string::npos) return "holds '='";
    if (key.find(' ') != std::string::npos) return "holds a space";
    return nullptr;
}

/// Why an F file cannot store `value` as it is, or null.
const char* valueProblem(const std::string& value) {
    if (holdsControl(value)) return "holds a control character";
    if (value.empty()) return nullptr;
    if (value.front() == ' ' || value.back() == ' ') return "starts or ends with a space";
    if (value.find("  ") != std::string::npos) return "holds two spaces in a row";
    if (value.back() == '\\') return "ends with a backslash";
    return nullptr;
}

}  // namespace

void checkParameters(const std::map<std::string, std::string>& parameters, const std::string& file) {
    for (const auto& [key, value] : parameters) {
        if (const char* problem = keyProblem(key))
            throw Error(file, 0, "parameter key " + quote(key) + " " + problem + "; F files cannot store it");
        if (const char* problem = valueProblem(value))
            throw Error(file, 0, "parameter " + quote(key) + ": value " + quote(value) + " " + problem +
                                     "; F files cannot store it");
    }
}

void validateFormFactors(const FormFactors& F, std::size_t patchCount, const std::string& source,
                         double maxRowSum) {
    if (F.size() != patchCount)
        throw Error(source, 0, "form factors are for " + std::to_string(F.size()) + " patches, the scene has " +
                                   std::to_string(patchCount));
    for (std::size_t i = 0; i < F.size(); ++i) {
        double sum = 0.0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            const double v = F.values()[k];
            if (!std::isfinite(v) || v < 0.0) {
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

namespace {

/// Rows [first, last) of Y = F X for one tile of `width` (at most interleaved::kChunk) columns,
/// interleaved (interleaved_rows.hpp).
HEMIRAD_WIDE_KERNEL void multiplyRows(const FormFactors& F, int width, const double* X, double* Y, std::size_t first,
                                      std::size_t last) {
    const std::size_t w = std::size_t(width);
    for (std::size_t i = first; i < last; ++i) interleaved::rowSums(F, i, F.rowEnd(i), X, w, width, Y + i * w);
}

}  // namespace

void multiplyTiled(const FormFactors& F, const std::vector<int>& widths, const double* X, double* Y) {
    const std::size_t n = F.size();
    std::vector<std::size_t> offsets(widths.size());
    for (std::size_t t = 1; t < widths.size(); ++t) offsets[t] = offsets[t - 1] + n * std::size_t(widths[t - 1]);
    constexpr std::size_t kRows = interleaved::kBlockRows;
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t block = 0; block < std::int64_t((n + kRows - 1) / kRows); ++block) {
        const std::size_t first = std::size_t(block) * kRows, last = std::min(n, first + kRows);
        for (std::size_t t = 0; t < widths.size(); ++t) multiplyRows(F, widths[t], X + offsets[t], Y + offsets[t], first, last);
    }
}

void multiplyInterleaved(const FormFactors& F, std::size_t width, const double* X, std::vector<double>& Y) {
    const std::size_t n = F.size();
    Y.resize(n * width);
    if (width == 0 || n == 0) return;
    if (width <= std::size_t(interleaved::kChunk)) return multiplyTiled(F, {int(width)}, X, Y.data());
    // Wider than a chunk: the columns are copied into tiles of at most kChunk (multiplyTiled), so a
    // row's gathers read a tile's few values per patch from whole cache lines (in place, a stride
    // of `width` spreads them over the whole N x width array: 2.3 times slower on street64k's ray
    // F at 157 columns). Each column's sums are the same either way.
    const std::vector<int> widths = interleaved::tileWidths(int(width), interleaved::kChunk, false);
    const std::size_t count = widths.size();
    std::vector<double> tiles(n * width), products(n * width);
    auto each = [&](auto&& copy) {
        for (std::size_t t = 0, c0 = 0; t < count; c0 += std::size_t(widths[t]), ++t)
            for (std::size_t i = 0; i < n; ++i) copy(i * width + c0, n * c0 + i * std::size_t(widths[t]), std::size_t(widths[t]));
    };
    each([&](std::size_t at, std::size_t tiled, std::size_t w) { std::copy_n(X + at, w, tiles.data() + tiled); });
    multiplyTiled(F, widths, tiles.data(), products.data());
    each([&](std::size_t at, std::size_t tiled, std::size_t w) { std::copy_n(products.data() + tiled, w, Y.data() + at); });
}

}  // namespace hemirad
