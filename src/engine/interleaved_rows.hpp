// Row products of the CSR F with many interleaved right-hand sides (a year's hours, a sky's
// cells): X holds value (j, c) at X[j * stride + c]. The columns go in chunks of fixed width, so
// each chunk's sums stay in registers while the row's entries stream past, and rows go in blocks,
// so a block's entries are read from cache again for each chunk (neighbouring rows meet much the
// same patches). Each column's sum takes the row's entries in order whatever the chunking: a
// column's sums do not depend on how many columns (or threads) share the pass. (A solver may still
// share choices across its columns: SOR's factor, its stopping sweep.)
#pragma once

#include "engine/form_factors.hpp"
#include "engine/wide_kernels.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hemirad::interleaved {

/// Rows a block: its entries (about 1,000 a row on a large scene, 12 bytes each) stay in a core's
/// cache while every chunk of columns passes over them. Measured on street64k's ray F (59 M
/// nonzeros, 106 columns, 2 threads, AVX2) in a stand-alone sweep: 0.78 s with 128 rows and 16
/// columns, 0.91 s with 32 rows, 1.06 s row by row with the sums in memory; 32 columns a chunk
/// spill registers (1.2 s).
constexpr std::size_t kBlockRows = 128;
constexpr int kChunk = 16;

/// out[c] = sum of F_ik X[col(k) * stride + c] for c < W over the row's entries [begin, end) but
/// `skip` (begin <= skip <= end; end: none), in the row's order. W is known to the compiler, and
/// the sums stay in registers.
template <int W>
HEMIRAD_INLINE_KERNEL void chunkSums(const double* val, const std::uint32_t* col, std::uint64_t begin, std::uint64_t skip,
                                     std::uint64_t end, const double* X, std::size_t stride, double* out) {
    static_assert(W > 0 && W <= kChunk);
    double sum[W] = {};
    auto run = [&](std::uint64_t from, std::uint64_t to) {
        for (std::uint64_t k = from; k < to; ++k) {
            const double v = val[k];
            const double* x = X + std::size_t(col[k]) * stride;
            for (int c = 0; c < W; ++c) sum[c] += v * x[c];
        }
    };
    run(begin, skip);
    run(skip < end ? skip + 1 : end, end);
    for (int c = 0; c < W; ++c) out[c] = sum[c];
}

namespace detail {
template <int W>
HEMIRAD_INLINE_KERNEL void rowSumsOf(const double* val, const std::uint32_t* col, std::uint64_t begin, std::uint64_t skip,
                                     std::uint64_t end, const double* X, std::size_t stride, int width, double* out) {
    if constexpr (W < kChunk) {
        if (width != W) return rowSumsOf<W + 1>(val, col, begin, skip, end, X, stride, width, out);
    }
    chunkSums<W>(val, col, begin, skip, end, X, stride, out);
}
}  // namespace detail

/// Row i's sums for `width` columns (1 to kChunk) from X's first: out[0, width). `skip` as
/// chunkSums takes it. Every width has its own fixed-width loop: a narrow chunk (the last of a
/// batch) in a loop over a run-time width took twice the time of a full one (street64k's ray F).
HEMIRAD_INLINE_KERNEL void rowSums(const FormFactors& F, std::size_t i, std::uint64_t skip, const double* X,
                                   std::size_t stride, int width, double* out) {
    detail::rowSumsOf<1>(F.values(), F.columns(), F.rowBegin(i), skip, F.rowEnd(i), X, stride, width, out);
}

/// Eight floats in one vector (GCC's vector extension: one AVX register, two SSE ones in the
/// baseline clone). Written out, because GCC vectorised the plain float loop along the row instead
/// (3 times slower than double on street64k's ray F); this way a float pass takes about 0.45 of a
/// double one at 32 to 48 columns a tile (2.0-2.6 against 4.5-5.5 ms a column, 2 threads).
typedef float Floats8 __attribute__((vector_size(32)));

/// out[0, 8Q) = sum of F_ik X[col(k) * 8Q + c] over the row's entries [begin, end) but `skip`, in
/// the row's order, in float (iterative refinement's correction sweeps).
template <int Q>
HEMIRAD_INLINE_KERNEL void floatSums(const double* val, const std::uint32_t* col, std::uint64_t begin, std::uint64_t skip,
                                     std::uint64_t end, const float* X, float* out) {
    Floats8 sum[Q] = {};
    auto run = [&](std::uint64_t from, std::uint64_t to) {
        for (std::uint64_t k = from; k < to; ++k) {
            const float v = float(val[k]);
            const float* x = X + std::size_t(col[k]) * (8 * Q);
            for (int q = 0; q < Q; ++q) {
                Floats8 a;
                __builtin_memcpy(&a, x + 8 * q, sizeof a);
                sum[q] += v * a;
            }
        }
    };
    run(begin, skip);
    run(skip < end ? skip + 1 : end, end);
    __builtin_memcpy(out, sum, sizeof sum);
}

/// Row i's float sums for `lanes` columns (8, 16, ..., 48) of X, as floatSums.
HEMIRAD_INLINE_KERNEL void floatRowSums(const FormFactors& F, std::size_t i, std::uint64_t skip, const float* X, int lanes,
                                        float* out) {
    const double* val = F.values();
    const std::uint32_t* col = F.columns();
    switch (lanes) {
    case 8: return floatSums<1>(val, col, F.rowBegin(i), skip, F.rowEnd(i), X, out);
    case 16: return floatSums<2>(val, col, F.rowBegin(i), skip, F.rowEnd(i), X, out);
    case 24: return floatSums<3>(val, col, F.rowBegin(i), skip, F.rowEnd(i), X, out);
    case 32: return floatSums<4>(val, col, F.rowBegin(i), skip, F.rowEnd(i), X, out);
    case 40: return floatSums<5>(val, col, F.rowBegin(i), skip, F.rowEnd(i), X, out);
    default: return floatSums<6>(val, col, F.rowBegin(i), skip, F.rowEnd(i), X, out);
    }
}

/// The widths of the tiles `m` columns go in: at most `most` each, as even as can be; with `pairs`,
/// an even number of tiles (for two threads to split) from 4 columns on. They follow m alone, never
/// the thread count: a column meets the same fixed-width loops on any number of threads.
inline std::vector<int> tileWidths(int m, int most, bool pairs) {
    int count = (m + most - 1) / most;
    if (pairs && m > 3) count = std::min(m, (count + 1) / 2 * 2);
    std::vector<int> widths;
    for (int t = 0; t < count; ++t) widths.push_back(int(std::int64_t(m) * (t + 1) / count - std::int64_t(m) * t / count));
    return widths;
}

/// The entry of row i's self factor F_ii, or the row's end when it has none.
inline std::uint64_t selfEntry(const FormFactors& F, std::size_t i) {
    const std::uint32_t* col = F.columns();
    for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k)
        if (col[k] == i) return k;
    return F.rowEnd(i);
}

}  // namespace hemirad::interleaved
