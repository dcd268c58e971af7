// --enforce-reciprocity with closure: symmetric scaling of the pair means to the row targets.
#include "allocation_failure.hpp"
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/reciprocal_closure.hpp"
#include "engine/subdivide.hpp"
#include "solve/furnace.hpp"
#include "solve/solver.hpp"
#include "solve/solver_registry.hpp"

#include <doctest/doctest.h>
#include <omp.h>

#include <algorithm>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// The exact cube F (opposite faces 0-1, 2-3, 4-5) with each row's entries scaled by `scale[i]` and
/// entry (0, 2) by `skew`: rows off 1 by a few 1e-3, pairs no longer reciprocal, as estimates are.
FormFactors perturbedCubeF(const double (&scale)[6], double skew) {
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    for (std::uint32_t i = 0; i < 6; ++i)
        for (std::uint32_t j = 0; j < 6; ++j)
            if (i != j) {
                const double f = ((i ^ 1) == j ? kCubeOpposite : kCubeAdjacent) * scale[i] * (i == 0 && j == 2 ? skew : 1.0);
                rows[i].push_back({j, f});
            }
    return FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(6, 1));
}

double worstReciprocity(const FormFactors& F, const Scene& s) {
    double worst = 0.0, largest = 0.0;
    for (PatchId i = 0; i < F.size(); ++i)
        for (PatchId j = 0; j < F.size(); ++j) {
            const double a = s.patches[i].area * F.at(i, j), b = s.patches[j].area * F.at(j, i);
            worst = std::max(worst, std::abs(a - b));
            largest = std::max(largest, a);
        }
    return worst / largest;
}

}  // namespace

TEST_CASE("Enforced reciprocity closes a nearly closed box: reciprocal, rows sum to 1, every solver reaches the furnace answer") {
    Scene s = unitCube();
    for (Patch& p : s.patches) {
        p.rho = Rgb::Constant(0.99);
        p.emission = Rgb::Constant(1.0);
    }
    const double scale[6] = {0.995, 1.0, 1.004, 0.998, 1.0, 1.002};
    const FormFactors estimated = perturbedCubeF(scale, 1.006);
    FormFactors F = estimated;
    const ReciprocityReport report = enforceReciprocity(F, s);
    CHECK(report.closedTargets);
    CHECK(report.converged);
    CHECK(report.residual <= 1e-12);
    CHECK(report.changed > 0);
    CHECK(F.parameters.at("reciprocity") == "enforced, rows closed to 1");
    CHECK(worstReciprocity(F, s) < 2e-7);  // float storage of the two entries
    for (PatchId i = 0; i < 6; ++i) CHECK(F.rowSum(i) == relative(1.0, 2e-7));
    // B = E / (1 - rho) = 100 for every solver, the symmetric ones (Cholesky, CG) included.
    for (const SolverDescriptor* d : solverRegistry()) {
        CAPTURE(d->name);
        CHECK(furnaceError(s, F, d->name, 0.99) <= 1e-6);
    }
    // As estimated, the symmetric form is not F's system: Cholesky's answer fails the residual gate.
    SolverOptions cholesky;
    cholesky.solver = "cholesky";
    cholesky.tolerance = 1e-9;
    CHECK_THROWS_WITH_AS(solveRadiosity(s, estimated, cholesky), doctest::Contains("the residual on I - R F"), Error);
}

TEST_CASE("Enforced reciprocity keeps the estimated row sums of an open scene and of a scene with mirrors") {
    // The cube without its ceiling (patch 1): open, so each row keeps what the estimator found escaping.
    const double scale[6] = {1.0, 1.0, 0.98, 1.01, 0.99, 1.0};
    const FormFactors closedF = perturbedCubeF(scale, 1.006);
    std::vector<std::vector<FormFactors::Entry>> rows(5);
    for (PatchId i = 0; i < 6; ++i)
        if (i != 1)
            for (std::uint64_t e = closedF.rowBegin(i); e < closedF.rowEnd(i); ++e) {
                const std::uint32_t j = closedF.columns()[e];
                if (j != 1) rows[i - (i > 1)].push_back({j - (j > 1), closedF.values()[e]});
            }
    FormFactors F = FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(5, 1));
    Scene open = unitCube();
    open.patches.erase(open.patches.begin() + 1);
    const FormFactors before = F;
    SUBCASE("open: a missing face") {
        const ReciprocityReport report = enforceReciprocity(F, open);
        CHECK_FALSE(report.closedTargets);
        CHECK(report.why.find("an open scene") != std::string::npos);
    }
    SUBCASE("mirrors") {
        open.patches[0].specular = 0.5;
        const ReciprocityReport report = enforceReciprocity(F, open);
        CHECK_FALSE(report.closedTargets);
        CHECK(report.why.find("mirrors") != std::string::npos);
    }
    CHECK(F.parameters.at("reciprocity") == "enforced, estimated row sums kept");
    CHECK(worstReciprocity(F, open) < 2e-7);
    for (PatchId i = 0; i < 5; ++i) CHECK(F.rowSum(i) == relative(before.rowSum(i), 2e-7));
}

TEST_CASE("Closure converges with a row that sees almost nothing: its miss is judged against 1e-9, not its own sum") {
    // The perturbed cube plus a plate outside it (open: its edges are no other patch's) whose row
    // and column are rounding noise, 1e-17, as a floor patch under a block in the Cornell box: the
    // neighbours' scaling moves its sum by 1e-5 of itself, which Newton's steps (measured in
    // absolute terms) never correct; judged against its own sum the closure was "NOT converged".
    Scene s = unitCube();
    SceneBuilder b;
    b.scene = s;
    const PatchId plate = b.rectangle(1, 3.0, 0, 1, 0, 1, true);
    s = b.scene;
    REQUIRE(plate == 6);
    const double scale[6] = {0.995, 1.0, 1.004, 0.998, 1.0, 1.002};
    const FormFactors cube = perturbedCubeF(scale, 1.006);
    std::vector<std::vector<FormFactors::Entry>> rows(7);
    for (PatchId i = 0; i < 6; ++i) {
        for (std::uint64_t e = cube.rowBegin(i); e < cube.rowEnd(i); ++e) rows[i].push_back({cube.columns()[e], cube.values()[e]});
        rows[i].push_back({plate, float(1e-17 * (1.0 + 0.1 * i))});
        rows[plate].push_back({i, float(1e-17 * (1.0 + 0.1 * i))});
    }
    FormFactors F = FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(7, 1));
    const ReciprocityReport report = enforceReciprocity(F, s);
    CHECK_FALSE(report.closedTargets);
    CHECK(report.converged);
    CHECK(report.residual <= 1e-12);
    CHECK(worstReciprocity(F, s) < 2e-7);
}

TEST_CASE("A scene counts as watertight only when every patch edge has exactly two patches") {
    CHECK(isWatertight(unitCube()));
    CHECK(isWatertight(subdivide(unitCube(), 0.25)));  // conforming grids meet at the cube's edges
    Scene open = unitCube();
    open.patches.pop_back();
    CHECK_FALSE(isWatertight(open));
    // A T-junction: one face split in two, its neighbours not.
    SceneBuilder b;
    b.rectangle(1, 0, 0, 1, 0, 1, true);
    CHECK_FALSE(isWatertight(b.scene));
    CHECK_FALSE(isWatertight(Scene{}));
}

TEST_CASE("Rows not computed keep their entries, and computed rows stay reciprocal among themselves") {
    const Scene s = unitCube();
    const double scale[6] = {0.995, 1.0, 1.004, 0.998, 1.0, 1.002};
    const FormFactors full = perturbedCubeF(scale, 1.0);
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    std::vector<std::uint8_t> computed(6, 1);
    computed[5] = 0;
    for (PatchId i = 0; i < 5; ++i)
        for (std::uint64_t e = full.rowBegin(i); e < full.rowEnd(i); ++e) rows[i].push_back({full.columns()[e], full.values()[e]});
    FormFactors F = FormFactors::fromRows(std::move(rows), computed);
    const FormFactors before = F;
    const ReciprocityReport report = enforceReciprocity(F, s);
    CHECK(report.closedTargets);
    CHECK(report.converged);
    CHECK_FALSE(F.rowComputed(5));
    CHECK(F.rowEnd(5) == F.rowBegin(5));
    for (PatchId i = 0; i < 5; ++i) {
        CHECK(F.at(i, 5) == before.at(i, 5));  // its partner row is unknown: kept
        CHECK(F.rowSum(i) == relative(1.0, 2e-7));
        for (PatchId j = 0; j < 5; ++j) CHECK(F.at(i, j) == relative(F.at(j, i), 2e-7));
    }
}

TEST_CASE("F diagnostics: row sums, reciprocity over pairs with one or two entries, self factors, rows not computed") {
    Scene s = unitCube();  // six unit faces; areas set below
    const double area[6] = {1.0, 2.0, 4.0, 1.0, 1.0, 1.0};
    for (PatchId i = 0; i < 6; ++i) s.patches[i].area = area[i];
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    rows[0] = {{1, 0.4f}, {2, 0.5f}};  // pair (0,1): 0.4 against 2 x 0.2 = 0.4; pair (0,2): one entry only
    rows[1] = {{0, 0.2f}, {1, 0.1f}};  // a self factor
    rows[2] = {{3, 0.25f}};            // pair (2,3) against row 3, which was not computed
    std::vector<std::uint8_t> computed = {1, 1, 1, 0, 1, 1};
    FormFactors F = FormFactors::fromRows(std::move(rows), computed);
    const FormFactorStats st = computeStats(F, s);
    CHECK(st.rows == 6);
    CHECK(st.computedRows == 5);
    CHECK(st.nonZeros == 5);
    CHECK(st.selfFactors == 1);
    CHECK(st.rowSumMin == doctest::Approx(0.0));
    CHECK(st.rowSumMax == doctest::Approx(0.9));
    CHECK(st.rowSumMean == doctest::Approx((0.9 + 0.3 + 0.25) / 5));
    // (0,2) is the only violation: A_0 F_02 = 0.5 against 0, so the worst is 1. Each pair counts from
    // both of its rows: (0,1) adds 2 x (0.4 + 0.4) exchanged, (0,2) adds 2 x 0.5 violation and exchange.
    CHECK(st.reciprocityMax == doctest::Approx(1.0));
    CHECK(st.reciprocityMean == relative(1.0 / (1.6f + 1.0), 1e-6));
}

TEST_CASE("F diagnostics agree with the definition on a random sparse F (rows of every length, some not computed)") {
    // 400 patches of random areas; row i holds each column with probability growing with i, so the
    // threads' blocks (split by nonzeros) cut the rows unevenly.
    Scene s;
    std::uint64_t state = 12345;
    auto next = [&] {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return double(state >> 11) / double(1ULL << 53);
    };
    const std::uint32_t n = 400;
    s.patches.resize(n);
    for (Patch& p : s.patches) p.area = 0.5 + next();
    std::vector<std::vector<FormFactors::Entry>> rows(n);
    std::vector<std::uint8_t> computed(n, 1);
    for (std::uint32_t i = 0; i < n; ++i) {
        computed[i] = next() < 0.9;
        if (!computed[i]) continue;
        for (std::uint32_t j = 0; j < n; ++j)
            if (next() < 0.02 + 0.5 * i / n) rows[i].push_back({j, float(next() / n)});
    }
    const FormFactors F = FormFactors::fromRows(std::move(rows), computed);
    double worst = 0.0, violation = 0.0, exchanged = 0.0;
    std::size_t self = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!computed[i]) continue;
        self += F.at(i, i) > 0.0;
        for (std::uint32_t j = 0; j < n; ++j) {
            if (j == i || !computed[j]) continue;
            const double a = s.patches[i].area * F.at(i, j), b = s.patches[j].area * F.at(j, i);
            if (a == 0.0 && b == 0.0) continue;
            worst = std::max(worst, std::abs(a - b) / std::max(a, b));
            violation += std::abs(a - b);
            exchanged += a + b;
        }
    }
    // Any number of threads, more than rows too: the blocks (split by nonzeros) cover every row once.
    const int threads = omp_get_max_threads();
    for (const int t : {1, 2, 3, 7, 512}) {
        CAPTURE(t);
        omp_set_num_threads(t);
        const FormFactorStats st = computeStats(F, s);
        CHECK(st.computedRows == std::size_t(std::count(computed.begin(), computed.end(), 1)));
        CHECK(st.selfFactors == self);
        CHECK(st.reciprocityMax == relative(worst, 1e-12));
        CHECK(st.reciprocityMean == relative(violation / exchanged, 1e-12));
        const FormFactorStats empty = computeStats(FormFactors::fromRows(std::vector<std::vector<FormFactors::Entry>>(n), computed), s);
        CHECK(empty.nonZeros == 0);
        CHECK(empty.computedRows == st.computedRows);
        CHECK(empty.rowSumMax == 0.0);
        CHECK(empty.reciprocityMean == 0.0);
    }
    omp_set_num_threads(threads);
}

TEST_CASE("An out-of-memory inside the parallel passes over F (diagnostics, reciprocity closure) is an exception, never std::terminate") {
    // A thread's buffers (the diagnostics' cursors, a closed row's entries) were allocated inside an
    // OpenMP region with no try around them: a failure ended in std::terminate, which aborts this
    // test. One thread, so that the region's only thread is the calling one, whose allocations fail
    // in turn (a dynamic schedule could hand every row to another).
    Scene s = unitCube();
    for (Patch& p : s.patches) p.rho = Rgb::Constant(0.5);
    const double scale[6] = {0.995, 1.0, 1.004, 0.998, 1.0, 1.002};
    const FormFactors estimated = perturbedCubeF(scale, 1.006);
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const FailureSweep stats = failEachAllocation([&] { computeStats(estimated, s); });
    const FailureSweep closure = failEachAllocation([&] {
        FormFactors F = estimated;
        enforceReciprocity(F, s);
    });
    omp_set_num_threads(threads);
    CHECK(stats.failures > 0);
    CHECK(stats.outOfMemory == stats.failures);
    CHECK(closure.failures > 10);
    CHECK(closure.outOfMemory == closure.failures);
    // Unarmed, both still give their answers.
    FormFactors F = estimated;
    CHECK(enforceReciprocity(F, s).converged);
    CHECK(computeStats(F, s).reciprocityMax <= 2e-7);
}
