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
/// rounds the pair's double value to float, this pass rounds the emitting row's float.
constexpr double kRounding = 1e-6;

struct Insertion {
    std::uint32_t row, column;
    float value;
};

/// A_e F_er / A_r in F's float: the receiver's entry as the emitting row's value gives it.
float receiverValue(const Scene& scene, double fer, PatchId e, PatchId r) {
    return float(fer * scene.patches[e].area / scene.patches[r].area);
}

}  // namespace

EmittedPairsReport takePairsFromEmitters(FormFactors& F, const Scene& scene) {
    const std::size_t n = F.size();
    EmittedPairsReport report;
    // Received entries take their emitting row's value (emitted entries are never written, so the
    // rows can be visited in any order); an emitting row without the pair gives 0, removed below.
    std::size_t pairs = 0, changed = 0, zeroed = 0;
    double largest = 0.0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : pairs, changed, zeroed) reduction(max : largest)
    for (std::int64_t r = 0; r < std::int64_t(n); ++r) {
        if (!F.rowComputed(std::size_t(r))) continue;
        for (std::uint64_t k = F.rowBegin(std::size_t(r)); k < F.rowEnd(std::size_t(r)); ++k) {
            const PatchId e = F.columns()[k];
            if (e == PatchId(r) || !emitsFor(scene, e, PatchId(r)) || !F.rowComputed(e)) continue;
            const float value = receiverValue(scene, F.at(e, std::size_t(r)), e, PatchId(r));
            ++pairs;
            const double change = std::abs(double(value) - double(F.values()[k]));
            if (change > kRounding * std::max(double(value), double(F.values()[k]))) ++changed;
            largest = std::max(largest, change);
            zeroed += value == 0.0f;
            F.values()[k] = value;
        }
    }
    // Emitted entries whose receiver's row lacks the pair.
    std::vector<std::vector<Insertion>> perThread(static_cast<std::size_t>(omp_get_max_threads()));
    ParallelFailure failure;  // a thread's list failing to grow: rethrown after the loop
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t e = 0; e < std::int64_t(n); ++e) {
        if (!F.rowComputed(std::size_t(e)) || failure.failed()) continue;
        failure.run([&] {
            std::vector<Insertion>& mine = perThread[std::size_t(omp_get_thread_num())];
            for (std::uint64_t k = F.rowBegin(std::size_t(e)); k < F.rowEnd(std::size_t(e)); ++k) {
                const PatchId r = F.columns()[k];
                if (r == PatchId(e) || !emitsFor(scene, PatchId(e), r) || !F.rowComputed(r)) continue;
                const std::uint32_t* first = F.columns() + F.rowBegin(r);
                const std::uint32_t* last = F.columns() + F.rowEnd(r);
                if (std::binary_search(first, last, std::uint32_t(e))) continue;
                const float value = receiverValue(scene, F.values()[k], PatchId(e), r);
                if (value > 0.0f) mine.push_back({r, std::uint32_t(e), value});
            }
        });
    }
    failure.rethrowIfFailed();
    std::vector<Insertion> insertions;
    for (std::vector<Insertion>& list : perThread) insertions.insert(insertions.end(), list.begin(), list.end());
    report.pairs = pairs + insertions.size();
    report.changed = changed + insertions.size();
    report.added = insertions.size();
    report.removed = zeroed;
    for (const Insertion& add : insertions) largest = std::max(largest, double(add.value));
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
    std::vector<float> values;
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
                if (F.values()[k] != 0.0f) {
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
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) F.values()[k] = float(F.values()[k] * scale);
        ++report.rescaledRows;
        report.largestRowSum = std::max(report.largestRowSum, sum);
    }
}

}  // namespace hemirad
