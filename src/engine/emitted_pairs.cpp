// Receiver entries from their emitting rows: values in place, then the entries one side lacks.
#include "engine/emitted_pairs.hpp"

#include "engine/parallel_failure.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hemirad {

namespace {

/// Entries that differ by less than this (relative) differ by rounding alone: the receiver's row
/// and this pass each scale the pair's value by a ratio of areas in double.
constexpr double kRounding = 1e-12;

struct Insertion {
    std::uint32_t row, column;
    double value;
};

/// A_e F_er / A_r: the receiver's entry as the emitting row's value gives it.
double receiverValue(const Scene& scene, double fer, PatchId e, PatchId r) {
    return fer * scene.patches[e].area / scene.patches[r].area;
}

}  // namespace

EmittedPairsReport takePairsFromEmitters(FormFactors& F, const Scene& scene) {
    const std::size_t n = F.size();
    EmittedPairsReport report;
    // One walk over the rows, the other entry of each pair found by MirrorCursors:
    // - a received entry (r, e) takes its emitting row's value; an emitting row without the pair
    //   gives 0, removed below;
    // - an emitted entry (e, r) whose receiver's row lacks the pair is kept for insertion.
    // Emitted entries are never written, so the threads' blocks may be visited in any order.
    std::size_t pairs = 0, changed = 0, zeroed = 0;
    double largest = 0.0;
    std::vector<std::vector<Insertion>> perThread(static_cast<std::size_t>(omp_get_max_threads()));
    ParallelFailure failure;  // a thread's cursors or list failing to grow: rethrown after the region
#pragma omp parallel reduction(+ : pairs, changed, zeroed) reduction(max : largest)
    failure.run([&] {
        const RowBlock block = nonZeroBlock(F, std::size_t(omp_get_thread_num()), std::size_t(omp_get_num_threads()));
        if (block.first == block.last) return;
        std::vector<Insertion>& mine = perThread[std::size_t(omp_get_thread_num())];
        MirrorCursors mirror(F);
        for (std::size_t i = block.first; i < block.last; ++i) {
            if (!F.rowComputed(i)) continue;
            for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
                const PatchId j = F.columns()[k];
                if (j == PatchId(i) || !F.rowComputed(j)) continue;
                const std::uint64_t at = mirror.find(j, std::uint32_t(i));
                if (emitsFor(scene, j, PatchId(i))) {
                    const double fer = at == MirrorCursors::kNone ? 0.0 : F.values()[at];
                    const double value = receiverValue(scene, fer, j, PatchId(i));
                    ++pairs;
                    const double change = std::abs(value - F.values()[k]);
                    if (change > kRounding * std::max(value, F.values()[k])) ++changed;
                    largest = std::max(largest, change);
                    zeroed += value == 0.0;
                    F.values()[k] = value;
                } else if (at == MirrorCursors::kNone) {
                    const double value = receiverValue(scene, F.values()[k], PatchId(i), j);
                    if (value > 0.0) mine.push_back({j, std::uint32_t(i), value});
                }
            }
        }
    });
    failure.rethrowIfFailed();
    std::vector<Insertion> insertions;
    for (std::vector<Insertion>& list : perThread) insertions.insert(insertions.end(), list.begin(), list.end());
    report.pairs = pairs + insertions.size();
    report.changed = changed + insertions.size();
    report.added = insertions.size();
    report.removed = zeroed;
    for (const Insertion& add : insertions) largest = std::max(largest, add.value);
    report.largestChange = largest;
    if (insertions.empty() && zeroed == 0) {
        scaleRowsAboveBound(F, report);
        return report;
    }

    // Rebuild the CSR with the insertions and without the zeros.
    std::sort(insertions.begin(), insertions.end(),
              [](const Insertion& a, const Insertion& b) { return a.row != b.row ? a.row < b.row : a.column < b.column; });
    std::vector<std::uint64_t> start(n + 1, 0);
    std::vector<std::uint32_t> columns;
    std::vector<double> values;
    columns.reserve(F.nonZeros() + insertions.size() - zeroed);
    values.reserve(columns.capacity());
    std::size_t next = 0;
    for (std::size_t r = 0; r < n; ++r) {
        start[r] = columns.size();
        std::uint64_t k = F.rowBegin(r);
        const std::uint64_t end = F.rowEnd(r);
        while (k < end || (next < insertions.size() && insertions[next].row == r)) {
            const bool takeOld =
                k < end && !(next < insertions.size() && insertions[next].row == r && insertions[next].column < F.columns()[k]);
            if (takeOld) {
                if (F.values()[k] != 0.0) {
                    columns.push_back(F.columns()[k]);
                    values.push_back(F.values()[k]);
                }
                ++k;
            } else {
                columns.push_back(insertions[next].column);
                values.push_back(insertions[next].value);
                ++next;
            }
        }
    }
    start[n] = columns.size();
    FormFactors rebuilt = FormFactors::fromCsr(std::move(start), std::move(columns), std::move(values),
                                               std::vector<std::uint8_t>(F.computedFlags()));
    rebuilt.sceneHash = F.sceneHash;
    rebuilt.provenance = F.provenance;
    rebuilt.parameters = F.parameters;
    F = std::move(rebuilt);
    scaleRowsAboveBound(F, report);
    return report;
}

void scaleRowsAboveBound(FormFactors& F, EmittedPairsReport& report) {
    const double bound = F.provenance.rowSumBound;
    for (std::size_t i = 0; i < F.size(); ++i) {
        if (!F.rowComputed(i)) continue;
        const double sum = F.rowSum(i);
        if (!(sum > bound + kRowSumExcess)) continue;
        const double scale = bound / sum;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) F.values()[k] = F.values()[k] * scale;
        ++report.rescaledRows;
        report.largestRowSum = std::max(report.largestRowSum, sum);
    }
}

}  // namespace hemirad
