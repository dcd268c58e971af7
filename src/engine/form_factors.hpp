// Sparse form-factor matrix F in row-major CSR (double values, 32-bit columns), its builder and statistics.
#pragma once

#include "engine/math.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hemirad {

class Scene;

/// How an F was computed, typed. F files keep it under parameter keys that people read too:
/// method, estimator (its first word; the rest describes the estimator), row_sum_bound, and
/// scene_hash=unknown for a file without a Hemirad scene hash.
struct FormFactorProvenance {
    std::string method;          ///< the back end; "" when the file does not say (foreign .mtx)
    std::string estimator;       ///< "rays", "analytic", ...; "" when the method has no estimator choice
    /// The largest row sum the method allows: 1, or more with mirror chains (a ray deposits its weight
    /// on every patch of its chain: up to 1 + s + ... + s^depth, Sillion & Puech 1989).
    double rowSumBound = 1.0;
    bool sceneHashKnown = true;  ///< false: only the patch count can be checked against a scene

    bool operator==(const FormFactorProvenance& o) const {
        return method == o.method && estimator == o.estimator && rowSumBound == o.rowSumBound &&
               sceneHashKnown == o.sceneHashKnown;
    }
};

/// The provenance stored in `parameters`, which loses those keys (the text that describes the
/// estimator stays). Missing keys give the defaults (old files still load). Throws hemirad::Error
/// naming `source` for a value that does not parse (a row_sum_bound that is not a number >= 1).
FormFactorProvenance takeProvenance(std::map<std::string, std::string>& parameters, const std::string& source);

/// `parameters` with the provenance written into its keys, as F files store them.
std::map<std::string, std::string> withProvenance(const FormFactorProvenance& provenance,
                                                  std::map<std::string, std::string> parameters);

/// Throws hemirad::Error naming `file` and the parameter unless every F file format stores it as it
/// is and reads it back unchanged; every writer (.hff, .mtx, shard manifest) calls it on
/// withProvenance()'s map before writing anything. Odd characters are refused rather than escaped, so
/// that the files keep their plain "key=value" (.hff, manifest) and "% hemirad param key value"
/// (.mtx) text, which older readers and people read as it is. A key must be non-empty, without '='
/// (.hff and manifests split at the first one), spaces or control characters (.mtx separates key and
/// value by a space). A value must hold no control character (LF ends a line, CR and tabs are
/// whitespace to the text readers, NUL is refused by them), neither start nor end with a space nor
/// hold two in a row (.mtx joins its words with single spaces), and not end with a backslash (the
/// text readers join such a line with the next). Anything else goes, UTF-8 included.
void checkParameters(const std::map<std::string, std::string>& parameters, const std::string& file);

/// F(i, j) = fraction of the power leaving patch i diffusely that arrives at patch j (directly or,
/// with mirrors, through chains of specular reflections; Sillion & Puech 1989).
/// Memory: 12 bytes per nonzero + 9 bytes per row.
class FormFactors {
public:
    /// Packed: 12 bytes as in F's arrays, not 16 (the rows of a job are all held as lists before
    /// F is packed from them, and that peak sets the memory a job needs).
    struct __attribute__((packed, aligned(4))) Entry {
        std::uint32_t column;
        double value;
    };
    static_assert(sizeof(Entry) == 12);

    FormFactors() = default;
    explicit FormFactors(std::size_t n) : m_rowStart(n + 1, 0), m_computed(n, 0) {}

    std::size_t size() const { return m_computed.size(); }
    std::size_t nonZeros() const { return m_columns.size(); }
    std::size_t memoryBytes() const;

    std::uint64_t rowBegin(std::size_t i) const { return m_rowStart[i]; }
    std::uint64_t rowEnd(std::size_t i) const { return m_rowStart[i + 1]; }
    const std::uint32_t* columns() const { return m_columns.data(); }
    const double* values() const { return m_values.data(); }
    double* values() { return m_values.data(); }
    /// Whether row i was computed (rows of black patches are skipped unless asked for).
    bool rowComputed(std::size_t i) const { return m_computed[i] != 0; }
    std::size_t computedRows() const;
    double rowSum(std::size_t i) const;
    /// F(i, j) by binary search in row i (columns are sorted); 0 when absent.
    double at(std::size_t i, std::size_t j) const;

    /// Scene hash (geometry + specular) this F belongs to, and how it was computed: typed, and the
    /// back end's parameters as text for people ("samples", "origins", "estimator", ...).
    std::uint64_t sceneHash = 0;
    FormFactorProvenance provenance;
    std::map<std::string, std::string> parameters;

    /// Builds from per-row entry lists (columns sorted, unique); rows with computed[i] == 0 must be empty.
    static FormFactors fromRows(std::vector<std::vector<Entry>>&& rows, std::vector<std::uint8_t> computed);
    /// Builds from raw CSR arrays (taking ownership); callers validate.
    static FormFactors fromCsr(std::vector<std::uint64_t>&& rowStart, std::vector<std::uint32_t>&& columns,
                               std::vector<double>&& values, std::vector<std::uint8_t>&& computed);

    const std::vector<std::uint64_t>& rowStarts() const { return m_rowStart; }
    const std::vector<std::uint8_t>& computedFlags() const { return m_computed; }
    const std::vector<std::uint32_t>& columnVector() const { return m_columns; }
    const std::vector<double>& valueVector() const { return m_values; }

    /// Takes every row that `other` computed (e.g. rows needed after a material edit); keeps the rest.
    void replaceRows(const FormFactors& other);

private:
    std::vector<std::uint64_t> m_rowStart;
    std::vector<std::uint32_t> m_columns;
    std::vector<double> m_values;
    std::vector<std::uint8_t> m_computed;
};

/// F^T in CSR: row j lists the patches i with F_ij > 0 (column j of F), sorted by i.
struct TransposedFormFactors {
    std::vector<std::uint64_t> start;
    std::vector<std::uint32_t> rows;
    std::vector<double> values;
};
/// Builds F^T (parallel counting sort, O(nnz); 12 bytes per nonzero).
TransposedFormFactors transpose(const FormFactors& F);

/// Y = F X for `width` right-hand sides interleaved per patch (value (i, c) at [i width + c]): one
/// pass over F for all of them, rows in parallel (OpenMP), the inner loop in wide vectors where the
/// processor has them (engine/wide_kernels.hpp). Y is resized to N x width.
void multiplyInterleaved(const FormFactors& F, std::size_t width, const double* X, std::vector<double>& Y);
/// Y = F X for columns in tiles, one after the other: tile t holds widths[t] (at most
/// interleaved::kChunk) columns interleaved per patch, from X + N (widths[0] + ... + widths[t-1]);
/// Y is laid out the same. One pass over F for every tile.
void multiplyTiled(const FormFactors& F, const std::vector<int>& widths, const double* X, double* Y);

/// Visits, for row i, every column j of row i or of column i (ascending, each once) with F_ij and
/// F_ji (0 where absent): the O(nnz) walk behind reciprocity statistics and the symmetric form.
template <class Visit>
void mergeRowAndColumn(const FormFactors& F, const TransposedFormFactors& Ft, std::size_t i, Visit&& visit) {
    std::uint64_t a = F.rowBegin(i), b = Ft.start[i];
    const std::uint64_t aEnd = F.rowEnd(i), bEnd = Ft.start[i + 1];
    while (a < aEnd || b < bEnd) {
        const std::uint32_t ja = a < aEnd ? F.columns()[a] : UINT32_MAX;
        const std::uint32_t jb = b < bEnd ? Ft.rows[b] : UINT32_MAX;
        const std::uint32_t j = ja < jb ? ja : jb;
        const double fij = ja == j ? F.values()[a++] : 0.0;
        const double fji = jb == j ? Ft.values[b++] : 0.0;
        visit(j, fij, fji);
    }
}

/// The rows of F's block `block` of `blocks`: contiguous, each with about its share of the nonzeros
/// (rows [first, last)). For splitting a walk over F's entries between threads.
struct RowBlock {
    std::size_t first = 0, last = 0;
};
RowBlock nonZeroBlock(const FormFactors& F, std::size_t block, std::size_t blocks);

/// F_ji beside F_ij without F^T (which would be F's size again): a cursor per row j that only moves
/// forward while the rows i that ask grow, so a walk over a block of rows in order costs O(nnz) plus
/// one binary search per row j met, and the loads of one row are independent (a binary search per
/// entry was slower than F^T on cornell13k). One per thread; n x 4 bytes.
class MirrorCursors {
public:
    static constexpr std::uint64_t kNone = UINT64_MAX;
    explicit MirrorCursors(const FormFactors& F) : m_F(F), m_cursor(F.size(), kUnset) {}
    /// The position of entry (j, i) in F's arrays, kNone when row j lacks column i. Within one
    /// MirrorCursors, i must not decrease between calls (walk the rows in order).
    std::uint64_t find(std::uint32_t j, std::uint32_t i) {
        const std::uint32_t* row = m_F.columns() + m_F.rowBegin(j);
        const auto length = std::uint32_t(m_F.rowEnd(j) - m_F.rowBegin(j));
        std::uint32_t& c = m_cursor[j];
        if (c == kUnset) c = std::uint32_t(std::lower_bound(row, row + length, i) - row);
        while (c < length && row[c] < i) ++c;
        return c < length && row[c] == i ? m_F.rowBegin(j) + c : kNone;
    }

private:
    static constexpr std::uint32_t kUnset = UINT32_MAX;
    const FormFactors& m_F;
    std::vector<std::uint32_t> m_cursor;  ///< offsets into row j
};

/// Diagnostics of an F against its scene (computed rows only).
struct FormFactorStats {
    std::size_t rows = 0, computedRows = 0, nonZeros = 0;
    double rowSumMin = 0, rowSumMean = 0, rowSumMax = 0;
    /// max over pairs (both rows computed) of |A_i F_ij - A_j F_ji| / max(A_i F_ij, A_j F_ji).
    double reciprocityMax = 0;
    /// sum |A_i F_ij - A_j F_ji| / sum (A_i F_ij + A_j F_ji): the area-weighted mean violation.
    double reciprocityMean = 0;
    std::size_t selfFactors = 0;  ///< rows with F_ii > 0 (legitimate only with mirrors)
};

FormFactorStats computeStats(const FormFactors& F, const Scene& scene);

/// Rescales every computed row with a positive sum to sum exactly 1 (closed scenes without mirrors:
/// removes the closure error that high albedo amplifies, physics.md). Returns the largest |sum - 1|
/// corrected.
double normalizeRows(FormFactors& F);

/// Checks F before use: size, finite and >= 0 values, row sums <= maxRowSum. Without mirrors a row
/// sums to at most 1; with mirrors a ray deposits its weight on every patch of its chain, so rows
/// may reach 1 / (1 - s_max). Throws hemirad::Error naming `source`, the row and value.
void validateFormFactors(const FormFactors& F, std::size_t patchCount, const std::string& source,
                         double maxRowSum);

/// The largest row sum F may have: its provenance's bound plus a tolerance of 1e-3 for accumulation.
double rowSumBound(const FormFactors& F);
double rowSumBound(const FormFactorProvenance& provenance);

}  // namespace hemirad
