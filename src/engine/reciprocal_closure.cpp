// Reciprocity with closure: symmetric scaling of the pair means by Newton's method and CG.
#include "engine/reciprocal_closure.hpp"

#include "engine/parallel_failure.hpp"
#include "engine/scene.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unordered_map>

namespace hemirad {
namespace {

constexpr double kTolerance = 1e-12;  ///< max |row sum - target| / target at which Newton stops
/// Rows whose target sum is below this are judged absolutely: their miss counts against this sum,
/// not against their own (a floor patch under a block sums to 1.6e-17, whose rounding alone is a
/// relative miss of 6e-6).
constexpr double kSmallestJudgedSum = 1e-9;
constexpr int kMaxNewtonSteps = 50;
constexpr int kMaxCgIterations = 2000;  ///< per Newton step
constexpr int kMaxHalvings = 20;        ///< line search steps per Newton step
constexpr double kNearOne = 1e-2;       ///< closed scenes: estimated row sums within this of 1

/// Sum of a full-length vector in index order: the same bits on every process and split.
double orderedSum(const std::vector<double>& v) {
    double s = 0.0;
    for (const double t : v) s += t;
    return s;
}

}  // namespace

void SymmetricRows::endRow(PatchId i, bool rowComputed, double estimatedSum) {
    rows.push_back(i);
    computed.push_back(rowComputed ? 1 : 0);
    estimated.push_back(estimatedSum);
    start.push_back(columns.size());
}

RowExchange singleProcess() {
    return {[](std::vector<double>&) {}, [](double v) { return v; }};
}

bool isWatertight(const Scene& scene) {
    if (scene.size() == 0) return false;
    const double tolerance = std::max(1e-9 * scene.extent(), 1e-300);
    // Positions snapped to a grid of the tolerance: corners that generators compute by different
    // float expressions meet; a pair split by a cell boundary only makes the scene count as open.
    struct Hash {
        std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
            return std::size_t(k[0]) * 0x9e3779b97f4a7c15ULL ^ std::size_t(k[1]) * 0xc2b2ae3d27d4eb4fULL ^ std::size_t(k[2]);
        }
    };
    std::unordered_map<std::array<std::int64_t, 3>, std::uint32_t, Hash> ids;
    auto idOf = [&](const Vec3& p) {
        const std::array<std::int64_t, 3> key{std::llround(p.x() / tolerance), std::llround(p.y() / tolerance),
                                              std::llround(p.z() / tolerance)};
        return ids.emplace(key, std::uint32_t(ids.size())).first->second;
    };
    std::unordered_map<std::uint64_t, std::uint32_t> edges;
    for (const Patch& p : scene.patches)
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const std::uint32_t a = idOf(scene.corner(p, k)), b = idOf(scene.corner(p, (k + 1) % p.cornerCount));
            if (a == b) continue;
            ++edges[std::uint64_t(std::min(a, b)) << 32 | std::max(a, b)];
        }
    return std::all_of(edges.begin(), edges.end(), [](const auto& e) { return e.second == 2; });
}

bool estimatedNearOne(const SymmetricRows& S) {
    for (std::size_t k = 0; k < S.rows.size(); ++k)
        if (S.computed[k] && std::abs(S.estimated[k] - 1.0) > kNearOne) return false;
    return true;
}

void chooseTargets(const Scene& scene, bool rowSumsNearOne, ReciprocityReport& report) {
    report.closedTargets = false;
    if (scene.hasMirrors())
        report.why = "rows keep their estimated sums (mirrors: extended rows may exceed 1)";
    else if (!isWatertight(scene))
        report.why = "rows keep their estimated sums (an open scene: a patch edge not shared by two patches)";
    else if (!rowSumsNearOne)
        report.why = "rows keep their estimated sums (watertight, but some rows were estimated more than 1e-2 from 1)";
    else {
        report.closedTargets = true;
        report.why = "rows sum to 1 (a closed scene: watertight, no mirrors, every row estimated within 1e-2 of 1)";
    }
}

std::vector<double> closureScaling(const Scene& scene, const SymmetricRows& S, bool closed, const RowExchange& exchange,
                                   ReciprocityReport& report) {
    const std::size_t n = scene.size(), m = S.rows.size();
    const auto held = static_cast<std::ptrdiff_t>(m);
    std::vector<double> x(n, 1.0);
    // (S v)_k over the entries that scale, v of full length.
    auto multiply = [&](const std::vector<double>& v, std::vector<double>& out) {
#pragma omp parallel for schedule(dynamic, 256)
        for (std::ptrdiff_t k = 0; k < held; ++k) {
            double s = 0.0;
            for (std::uint64_t e = S.start[k]; e < S.start[k + 1]; ++e)
                if (S.scales[S.columns[e]]) s += double(S.values[e]) * v[S.columns[e]];
            out[k] = s;
        }
    };
    std::vector<double> full(n), terms(n);
    auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
        std::fill(terms.begin(), terms.end(), 0.0);
        for (std::size_t k = 0; k < m; ++k) terms[S.rows[k]] = a[k] * b[k];
        exchange.share(terms);
        return orderedSum(terms);
    };

    std::vector<double> target(m), judged(m), y(m);  // judged: what a row's miss is measured against
    std::vector<std::uint8_t> active(m);
    multiply(x, y);
    for (std::size_t k = 0; k < m; ++k) {
        const PatchId i = S.rows[k];
        double fixedPart = 0.0;
        for (std::uint64_t e = S.start[k]; e < S.start[k + 1]; ++e)
            if (!S.scales[S.columns[e]]) fixedPart += double(S.values[e]);
        target[k] = scene.patches[i].area * ((closed ? 1.0 : S.estimated[k]) - fixedPart);
        active[k] = S.computed[k] && target[k] > 0.0 && y[k] > 0.0;
        judged[k] = std::max(target[k], scene.patches[i].area * kSmallestJudgedSum);
    }

    std::vector<double> r(m), g(m), u(m), res(m), p(m), q(m), Sw(m), trial(m);
    // sum over rows of (r_i / t_i)^2 (t_i at least A_i kSmallestJudgedSum) for x and y = S x, in one order.
    auto merit = [&](const std::vector<double>& xs, const std::vector<double>& ys) {
        std::vector<double> rel(m);
        for (std::size_t k = 0; k < m; ++k) rel[k] = active[k] ? (target[k] - xs[S.rows[k]] * ys[k]) / judged[k] : 0.0;
        return dot(rel, rel);
    };
    report.converged = false;
    report.newtonSteps = report.cgIterations = 0;
    for (;;) {
        double worst = 0.0;
        for (std::size_t k = 0; k < m; ++k) {
            r[k] = active[k] ? target[k] - x[S.rows[k]] * y[k] : 0.0;
            if (active[k]) worst = std::max(worst, std::abs(r[k]) / judged[k]);
        }
        report.residual = exchange.max(worst);
        if (report.residual <= kTolerance) {
            report.converged = true;
            break;
        }
        if (report.newtonSteps == kMaxNewtonSteps) break;
        ++report.newtonSteps;
        // Newton for x_i (S x)_i = t_i in u = dx / x: M u = x r with M = diag(x S x) + diag(x) S diag(x),
        // symmetric positive semidefinite (u^T M u = sum_ij x_i S_ij x_j (u_i + u_j)^2 / 2), so CG.
        for (std::size_t k = 0; k < m; ++k) g[k] = x[S.rows[k]] * r[k];
        std::fill(u.begin(), u.end(), 0.0);
        res = g;
        p = g;
        double rr = dot(res, res);
        const double stop = std::min(0.1, report.residual) * std::sqrt(rr);
        for (int it = 0; it < kMaxCgIterations && std::sqrt(rr) > stop; ++it) {
            std::fill(full.begin(), full.end(), 0.0);
            for (std::size_t k = 0; k < m; ++k) full[S.rows[k]] = x[S.rows[k]] * p[k];
            exchange.share(full);
            multiply(full, Sw);
            for (std::size_t k = 0; k < m; ++k) {
                const double xi = x[S.rows[k]];
                q[k] = active[k] ? xi * y[k] * p[k] + xi * Sw[k] : 0.0;
            }
            const double pq = dot(p, q);
            ++report.cgIterations;
            if (!(pq > 0.0)) break;
            const double alpha = rr / pq;
            for (std::size_t k = 0; k < m; ++k) {
                u[k] += alpha * p[k];
                res[k] -= alpha * q[k];
            }
            const double next = dot(res, res);
            for (std::size_t k = 0; k < m; ++k) p[k] = res[k] + next / rr * p[k];
            rr = next;
        }
        // A damped step keeps every x_i above half its value; then a backtracking line search on
        // sum (r_i / t_i)^2: targets no scaling can meet (an estimate inconsistent with its
        // neighbours') make Newton's full steps wander, and the best x found is kept.
        double shrink = 0.0;
        for (std::size_t k = 0; k < m; ++k) shrink = std::max(shrink, -u[k]);
        shrink = exchange.max(shrink);
        double theta = shrink > 0.5 ? 0.5 / shrink : 1.0;
        const double before = merit(x, y);
        bool accepted = false;
        for (int halving = 0; halving < kMaxHalvings && !accepted; ++halving, theta *= 0.5) {
            std::fill(full.begin(), full.end(), 0.0);
            for (std::size_t k = 0; k < m; ++k) full[S.rows[k]] = x[S.rows[k]] * (active[k] ? 1.0 + theta * u[k] : 1.0);
            exchange.share(full);
            // Rows nobody holds as computed keep x = 1 (their entries are fixed on the other side).
            multiply(full, trial);
            accepted = merit(full, trial) < (1.0 - 1e-4 * theta) * before;
        }
        if (!accepted) break;  // no descent: the targets are met as closely as they can be
        x.swap(full);
        y.swap(trial);
    }
    return x;
}

std::vector<std::vector<FormFactors::Entry>> closedRows(const Scene& scene, const SymmetricRows& S,
                                                        const std::vector<double>& x, const FormFactors& before,
                                                        ReciprocityReport& report) {
    const std::size_t m = S.rows.size();
    std::vector<std::vector<FormFactors::Entry>> rows(m);
    std::size_t changed = 0;
    double largest = 0.0;
    ParallelFailure failure;  // a row's entries failing to allocate: rethrown after the loop
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : changed) reduction(max : largest)
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(m); ++k) {
        if (!S.computed[k] || failure.failed()) continue;
        failure.run([&] {
            const PatchId i = S.rows[k];
            const double Ai = scene.patches[i].area;
            std::uint64_t a = before.rowBegin(i);
            const std::uint64_t aEnd = before.rowEnd(i);
            std::vector<FormFactors::Entry>& out = rows[k];
            out.reserve(S.start[k + 1] - S.start[k]);
            for (std::uint64_t e = S.start[k]; e < S.start[k + 1]; ++e) {
                const std::uint32_t j = S.columns[e];
                while (a < aEnd && before.columns()[a] < j) ++a;  // S's pattern holds F's
                const double old = a < aEnd && before.columns()[a] == j ? before.values()[a] : 0.0;
                const double value = S.scales[j] ? x[i] * S.values[e] * x[j] / Ai : S.values[e];
                if (value != old) ++changed;
                largest = std::max(largest, std::abs(value - old));
                if (value > 0.0) out.push_back({j, value});
            }
        });
    }
    failure.rethrowIfFailed();
    report.changed = changed;
    report.largestChange = largest;
    return rows;
}

std::string describe(const ReciprocityReport& report) {
    char text[512];
    std::snprintf(text, sizeof text,
                  "reciprocity enforced with closure: A_i F_ij = A_j F_ji, %s; target reached within %.2e (%d Newton "
                  "steps, %d CG iterations%s); %zu entries changed, the largest by %.3g",
                  report.why.c_str(), report.residual, report.newtonSteps, report.cgIterations,
                  report.converged ? "" : ", NOT converged: rows miss their targets by the residual", report.changed,
                  report.largestChange);
    return text;
}

namespace {

/// S for every row of F, built in parallel; F^T lives only while it is built. Pairs whose entries
/// are both below `dropBelow` (0: none) are left out, their weight per row into `droppedWeight`.
SymmetricRows symmetricRowsOf(const FormFactors& F, const Scene& scene, double dropBelow = 0.0,
                              std::vector<double>* droppedWeight = nullptr) {
    const std::size_t n = F.size();
    const TransposedFormFactors Ft = transpose(F);
    SymmetricRows S;
    S.scales = F.computedFlags();
    // A pair is dropped whole (both rows), so that S stays symmetric; an entry whose column's row
    // was not computed is fixed and kept, and so is a pair with an emitter (keptFromDropping).
    // Each row gives up at most kDropBudget of its sum (dropCut).
    std::vector<double> cut(dropBelow > 0.0 ? n : 0, 0.0);
    std::vector<double> scratch;
    for (std::size_t i = 0; i < cut.size(); ++i)
        cut[i] = dropCut(F.values() + F.rowBegin(i), F.rowEnd(i) - F.rowBegin(i), dropBelow, scratch);
    auto dropped = [&](std::ptrdiff_t i, std::uint32_t j, double fij, double fji) {
        if (!(dropBelow > 0.0 && j != std::uint32_t(i) && F.rowComputed(j))) return false;
        const double Ai = scene.patches[std::size_t(i)].area, Aj = scene.patches[j].area;
        return droppedPair(Ai * fij, Ai * cut[std::size_t(i)], Aj * fji, Aj * cut[j]) && !keptFromDropping(scene, PatchId(i), j);
    };
    if (droppedWeight) droppedWeight->assign(n, 0.0);
    // Two passes over the merged row and column of each computed row, in parallel: count, then fill.
    S.start.assign(n + 1, 0);
    const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(dynamic, 64)
    for (std::ptrdiff_t i = 0; i < count; ++i)
        if (F.rowComputed(i))
            mergeRowAndColumn(F, Ft, i, [&](std::uint32_t j, double fij, double fji) {
                if (!dropped(i, j, fij, fji)) ++S.start[i + 1];
            });
    for (std::size_t i = 0; i < n; ++i) S.start[i + 1] += S.start[i];
    S.columns.resize(S.start[n]);
    S.values.resize(S.start[n]);
#pragma omp parallel for schedule(dynamic, 64)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
        if (!F.rowComputed(i)) continue;
        const double Ai = scene.patches[i].area;
        std::uint64_t e = S.start[i];
        mergeRowAndColumn(F, Ft, i, [&](std::uint32_t j, double fij, double fji) {
            if (dropped(i, j, fij, fji)) {
                if (droppedWeight) (*droppedWeight)[std::size_t(i)] += fij;
                return;
            }
            S.columns[e] = j;
            S.values[e++] = SymmetricRows::pairMean(i, j, Ai, fij, scene.patches[j].area * fji, F.rowComputed(j));
        });
    }
    S.rows.resize(n);
    S.computed = F.computedFlags();
    S.estimated.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        S.rows[i] = PatchId(i);
        S.estimated[i] = F.rowComputed(i) ? F.rowSum(i) : 0.0;
    }
    return S;
}

/// F replaced by the closure of S (the targets from S's estimated sums); F's hash, provenance and
/// parameters kept, "reciprocity" set.
ReciprocityReport closeFrom(SymmetricRows S, FormFactors& F, const Scene& scene) {
    ReciprocityReport report;
    chooseTargets(scene, estimatedNearOne(S), report);
    const std::vector<double> x = closureScaling(scene, S, report.closedTargets, singleProcess(), report);
    std::vector<std::vector<FormFactors::Entry>> rows = closedRows(scene, S, x, F, report);
    S = SymmetricRows();  // its memory back before F' is packed
    const std::uint64_t hash = F.sceneHash;
    auto params = F.parameters;
    const FormFactorProvenance provenance = F.provenance;
    F = FormFactors::fromRows(std::move(rows), F.computedFlags());
    F.sceneHash = hash;
    F.provenance = provenance;
    F.parameters = std::move(params);
    F.parameters["reciprocity"] = report.closedTargets ? "enforced, rows closed to 1" : "enforced, estimated row sums kept";
    return report;
}

}  // namespace

ReciprocityReport enforceReciprocity(FormFactors& F, const Scene& scene) { return closeFrom(symmetricRowsOf(F, scene), F, scene); }

SparsifyReport dropBelow(FormFactors& F, const Scene& scene, double threshold) {
    SparsifyReport report;
    report.threshold = threshold;
    report.nonzerosBefore = F.nonZeros();
    report.bytesBefore = F.memoryBytes();
    std::vector<double> droppedWeight;
    SymmetricRows S = symmetricRowsOf(F, scene, threshold, &droppedWeight);
    for (const double w : droppedWeight) report.largestDroppedRow = std::max(report.largestDroppedRow, w);
    report.closure = closeFrom(std::move(S), F, scene);
    report.nonzerosAfter = F.nonZeros();
    report.bytesAfter = F.memoryBytes();
    markSparsified(F, report);
    return report;
}

bool keptFromDropping(const Scene& scene, PatchId i, PatchId j) {
    return (scene.patches[i].emission > 0.0).any() || (scene.patches[j].emission > 0.0).any();
}

double dropCut(const double* values, std::size_t count, double threshold, std::vector<double>& scratch) {
    scratch.clear();
    double sum = 0.0;
    for (std::size_t k = 0; k < count; ++k) {
        sum += values[k];
        if (values[k] < threshold) scratch.push_back(values[k]);
    }
    std::sort(scratch.begin(), scratch.end());
    double taken = 0.0;
    for (const double v : scratch) {
        taken += v;
        if (taken > kDropBudget * sum) return v;  // this entry and larger ones stay
    }
    return threshold;
}

namespace {
constexpr const char* kSparsifiedPrefix = "pairs below ";
}  // namespace

void markSparsified(FormFactors& F, const SparsifyReport& report) {
    // The threshold in its shortest exact form: sparsifiedThreshold reads it back.
    char threshold[32];
    *std::to_chars(threshold, threshold + sizeof threshold - 1, report.threshold).ptr = '\0';
    char text[128];
    std::snprintf(text, sizeof text, "%s%s dropped (%zu of %zu nonzeros), rows rebalanced", kSparsifiedPrefix, threshold,
                  report.nonzerosBefore - std::min(report.nonzerosBefore, report.nonzerosAfter), report.nonzerosBefore);
    F.parameters["sparsified"] = text;
}

std::optional<double> sparsifiedThreshold(const FormFactors& F) {
    const auto it = F.parameters.find("sparsified");
    if (it == F.parameters.end() || it->second.rfind(kSparsifiedPrefix, 0) != 0) return std::nullopt;
    const std::string& text = it->second;
    double threshold = 0.0;
    const char* begin = text.data() + std::strlen(kSparsifiedPrefix);
    const auto [end, error] = std::from_chars(begin, text.data() + text.size(), threshold);
    if (error != std::errc() || end == begin || !(threshold > 0.0)) return std::nullopt;
    return threshold;
}

std::string describe(const SparsifyReport& report) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "pairs with both entries below %g dropped: %zu -> %zu nonzeros (%.1f -> %.1f MiB), at most %.3g of a "
                  "row's weight; ",
                  report.threshold, report.nonzerosBefore, report.nonzerosAfter, double(report.bytesBefore) / 1048576.0,
                  double(report.bytesAfter) / 1048576.0, report.largestDroppedRow);
    return text + describe(report.closure);
}

}  // namespace hemirad
