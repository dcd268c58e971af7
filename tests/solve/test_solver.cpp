// Solvers: the unit-cube table of physics.md, furnace identities, agreement of all methods, failure modes.
#include "support.hpp"

#include "engine/error.hpp"
#include "solve/solver.hpp"
#include "solve/solver_registry.hpp"

#include <doctest/doctest.h>
#include <omp.h>

#include <algorithm>
#include <numeric>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// Exact F of the closed unit cube (Howell): opposite faces pair up as (0,1), (2,3), (4,5).
FormFactors exactCubeF() {
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    for (std::uint32_t i = 0; i < 6; ++i)
        for (std::uint32_t j = 0; j < 6; ++j) {
            if (i == j) continue;
            const bool opposite = (i ^ 1) == j;
            rows[i].push_back({j, opposite ? kCubeOpposite : kCubeAdjacent});
        }
    return FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(6, 1));
}

Scene cubeWith(double rho) {
    Scene s = unitCube();
    for (Patch& p : s.patches) {
        p.rho = Rgb::Constant(rho);
        p.emission = Rgb::Zero();
    }
    s.patches[0].emission = Rgb::Constant(1.0);
    return s;
}

/// Every registered solver, by name.
std::vector<std::string> allSolvers() {
    std::vector<std::string> names;
    for (const SolverDescriptor* d : solverRegistry()) names.push_back(d->name);
    return names;
}
const std::vector<std::string> kAll = allSolvers();

/// The bands solved by LU to 1e-14: the reference for the iterative solvers' answers.
BandSolution solvedByLu(const Scene& s, const FormFactors& F, const std::vector<Band>& bands) {
    SolverOptions lu;
    lu.solver = "lu";
    lu.tolerance = 1e-14;
    return solveBands(s, F, bands, lu);
}

Radiosity solveWith(const Scene& s, const FormFactors& F, const std::string& kind, double tolerance = 1e-10) {
    SolverOptions o;
    o.solver = kind;
    o.tolerance = tolerance;
    return solveRadiosity(s, F, o);
}

}  // namespace

TEST_CASE("Every solver reproduces the unit-cube table of physics.md") {
    struct Row {
        double rho, floor, ceiling, wall;
    };
    // physics.md §5, computed with the exact cube factors (float F limits agreement to ~1e-6 relative).
    const Row table[] = {{0.5, 1.0909090981, 0.1817458261, 0.1818362689},
                         {0.9, 2.3728813748, 1.5253105511, 1.5254520185},
                         {0.99, 17.3622704726, 16.5274251277, 16.5275760999}};
    const FormFactors F = exactCubeF();
    for (const Row& row : table)
        for (const std::string& kind : kAll) {
            CAPTURE(row.rho);
            CAPTURE(kind);
            const Radiosity r = solveWith(cubeWith(row.rho), F, kind);
            const double tol = 1e-6 / (1 - row.rho);
            CHECK(r.B[0][0] == relative(row.floor, tol));
            CHECK(r.B[1][0] == relative(row.ceiling, tol));
            for (int w = 2; w < 6; ++w) CHECK(r.B[w][0] == relative(row.wall, tol));
            REQUIRE(r.reports.size() == 1);  // grey: the three channels are one solve
            CHECK(r.reports[0].channels == "rgb");
            CHECK(r.reports[0].converged);
        }
}

TEST_CASE("Furnace: a closed box with uniform rho and E has B = E / (1 - rho) for every solver") {
    Scene s = unitCube();
    for (Patch& p : s.patches) {
        p.rho = Rgb(0.3, 0.6, 0.9);
        p.emission = Rgb(1, 2, 3);
    }
    const FormFactors F = exactCubeF();
    for (const std::string& kind : kAll) {
        CAPTURE(kind);
        const Radiosity r = solveWith(s, F, kind);
        for (const Rgb& b : r.B) {
            // Float F rows sum to 1 within 1e-7: B is exact to that relative error / (1 - rho).
            CHECK(b[0] == relative(1 / 0.7, 1e-6));
            CHECK(b[1] == relative(2 / 0.4, 1e-6));
            CHECK(b[2] == relative(3 / 0.1, 1e-5));
        }
        CHECK(r.reports.size() == 3);  // distinct channels are solved separately
    }
}

TEST_CASE("All solvers agree on one non-symmetric system, and the symmetric form gives the LU answer") {
    // Coloured, uneven reflectances and emission on the exact (reciprocal) cube F.
    Scene s = unitCube();
    const double rhos[6][3] = {{.7, .2, .1}, {.5, .5, .5}, {.1, .8, .3}, {.9, .4, .2}, {.3, .3, .9}, {.6, .7, .05}};
    for (int i = 0; i < 6; ++i) {
        s.patches[i].rho = Rgb(rhos[i][0], rhos[i][1], rhos[i][2]);
        s.patches[i].emission = Rgb::Zero();
    }
    s.patches[1].emission = Rgb(10, 8, 6);
    s.patches[4].emission = Rgb(0, 1, 2);
    const FormFactors F = exactCubeF();
    const Radiosity lu = solveWith(s, F, "lu", 1e-12);
    for (const std::string& kind : kAll) {
        CAPTURE(kind);
        const Radiosity r = solveWith(s, F, kind, 1e-11);
        for (int i = 0; i < 6; ++i)
            for (int c = 0; c < 3; ++c) CHECK(r.B[i][c] == relative(lu.B[i][c], 1e-8));
    }
}

TEST_CASE("Cholesky and CG on a non-reciprocal F are not converged: the gate is the residual on I - R F") {
    // The exact cube F with one row scaled: A_0 F_0j != A_j F_j0. The symmetrised K still converges,
    // but its B does not solve (I - R F) B = E.
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    for (std::uint32_t i = 0; i < 6; ++i)
        for (std::uint32_t j = 0; j < 6; ++j)
            if (i != j) rows[i].push_back({j, float(((i ^ 1) == j ? kCubeOpposite : kCubeAdjacent) * (i == 0 ? 0.8 : 1.0))});
    const FormFactors F = FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(6, 1));
    const Scene s = cubeWith(0.9);
    for (const char* kind : {"cholesky", "cg"}) {
        CAPTURE(kind);
        SolverOptions o;
        o.solver = kind;
        o.tolerance = 1e-8;
        CHECK_THROWS_WITH_AS(solveRadiosity(s, F, o), doctest::Contains("the residual on I - R F is"), Error);
        o.allowUnconverged = true;
        const Radiosity r = solveRadiosity(s, F, o);
        REQUIRE(r.reports.size() == 1);
        CHECK_FALSE(r.reports[0].converged);
        CHECK(r.reports[0].residual < 1e-7);           // K itself converged
        CHECK(r.reports[0].residualOriginal > 1e-3);   // I - R F did not
    }
    // The unsymmetric solvers solve the posed system.
    for (const char* kind : {"lu", "bicgstab", "gauss-seidel", "sor"}) {
        const Radiosity r = solveWith(s, F, kind, 1e-8);
        CHECK(r.reports[0].converged);
        CHECK(r.reports[0].residualOriginal < 1e-7);
    }
}

TEST_CASE("Black patches (rho = 0) keep B = E and their rows need not be computed") {
    Scene s = cubeWith(0.5);
    s.patches[0].rho = Rgb::Zero();
    s.patches[0].emission = Rgb::Constant(2.0);
    FormFactors F = exactCubeF();
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    for (std::size_t i = 1; i < 6; ++i)
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) rows[i].push_back({F.columns()[k], F.values()[k]});
    const FormFactors skipped = FormFactors::fromRows(std::move(rows), {0, 1, 1, 1, 1, 1});
    for (const std::string& kind : kAll) {
        CAPTURE(kind);
        const Radiosity full = solveWith(s, F, kind);
        const Radiosity partial = solveWith(s, skipped, kind);
        CHECK(partial.B[0][0] == doctest::Approx(2.0));
        for (int i = 0; i < 6; ++i) CHECK(partial.B[i][1] == relative(full.B[i][1], 1e-8));
    }
    s.patches[0].rho = Rgb(0.2, 0, 0);
    CHECK_THROWS_WITH_AS(solveWith(s, skipped, "gauss-seidel"),
                         doctest::Contains("row 0 of F was not computed"), Error);
}

TEST_CASE("rho = 1 in a closed scene is reported as singular, not solved") {
    const Scene s = cubeWith(1.0);
    for (const std::string& kind : kAll) {
        CAPTURE(kind);
        CHECK_THROWS_WITH_AS(solveWith(s, exactCubeF(), kind), doctest::Contains("is singular"), Error);
    }
}

TEST_CASE("An unconverged solve is an error unless allowed, and says so") {
    const Scene s = cubeWith(0.99);
    SolverOptions o;
    o.solver = "jacobi";
    o.maxIterations = 5;
    CHECK_THROWS_WITH_AS(solveRadiosity(s, exactCubeF(), o), doctest::Contains("jacobi did not converge"), Error);
    o.allowUnconverged = true;
    const Radiosity r = solveRadiosity(s, exactCubeF(), o);
    REQUIRE(r.reports.size() == 1);
    CHECK_FALSE(r.reports[0].converged);
    CHECK(r.reports[0].iterations == 5);
    CHECK(r.reports[0].residual > 1e-3);
}

TEST_CASE("Direct solvers refuse when the factorisation may exceed memory") {
    SolverOptions o;
    o.solver = "lu";
    o.memoryLimit = 100;  // bytes
    CHECK_THROWS_WITH_AS(solveRadiosity(cubeWith(0.5), exactCubeF(), o), doctest::Contains("use --solver cg"), Error);
}

TEST_CASE("A warm start from the solution converges at once") {
    const Scene s = cubeWith(0.9);
    const Radiosity exact = solveWith(s, exactCubeF(), "lu");
    SolverOptions o;
    o.solver = "gauss-seidel";
    o.tolerance = 1e-8;
    const Radiosity warm = solveRadiosity(s, exactCubeF(), o, &exact.B);
    CHECK(warm.reports[0].iterations <= 1);
    const Radiosity cold = solveRadiosity(s, exactCubeF(), o);
    CHECK(cold.reports[0].iterations > 20);
}

TEST_CASE("The solver registry names every family's solvers, and unknown names are errors that list them") {
    CHECK(kAll == std::vector<std::string>{"lu", "cholesky", "cg", "bicgstab", "jacobi", "gauss-seidel", "sor", "southwell"});
    for (const std::string& kind : kAll) {
        CHECK(findSolver(kind).name == kind);
        CHECK_FALSE(findSolver(kind).summary.empty());
        CHECK_NOTHROW(checkSolverName(kind));
    }
    CHECK(findSolver("cg").symmetricForm);
    CHECK_FALSE(findSolver("bicgstab").symmetricForm);
    CHECK_NOTHROW(checkSolverName("auto"));
    CHECK_THROWS_WITH_AS(checkSolverName("magic"),
                         doctest::Contains("unknown solver 'magic' (auto, lu, cholesky, cg, bicgstab, jacobi, gauss-seidel, sor, southwell)"),
                         Error);
    SolverOptions o;
    o.solver = "magic";
    CHECK_THROWS_WITH_AS(solveRadiosity(cubeWith(0.5), exactCubeF(), o), doctest::Contains("unknown solver 'magic'"), Error);
}

TEST_CASE("Jacobi, Gauss-Seidel and SOR hand each sweep's radiosity to a progress callback") {
    const Scene s = cubeWith(0.9);
    const Radiosity exact = solveWith(s, exactCubeF(), "lu");
    for (const char* kind : {"jacobi", "gauss-seidel", "sor"}) {
        CAPTURE(kind);
        SolverOptions o;
        o.solver = kind;
        o.tolerance = 1e-9;
        std::vector<int> sweeps;
        std::vector<double> errors;
        o.progress = [&](int sweep, const std::vector<Rgb>& B) {
            sweeps.push_back(sweep);
            errors.push_back(std::abs(B[1][0] - exact.B[1][0]));
        };
        const Radiosity r = solveRadiosity(s, exactCubeF(), o);
        REQUIRE(sweeps.size() >= 10);
        for (std::size_t k = 1; k < sweeps.size(); ++k) CHECK(sweeps[k] == sweeps[k - 1] + 1);
        CHECK(errors.back() < 0.1 * errors.front());  // the view converges toward the answer
        CHECK(r.B[1][0] == relative(exact.B[1][0], 1e-6));
    }
}

TEST_CASE("auto picks LU for small systems, and above 2000 patches SOR on up to 2 threads and Jacobi (parallel sweeps) on more") {
    const Scene scene;
    const int saved = omp_get_max_threads();
    omp_set_num_threads(2);
    CHECK(chooseSolver(2000, scene) == "lu");
    CHECK(chooseSolver(2001, scene) == "sor");
    omp_set_num_threads(3);
    CHECK(chooseSolver(2000, scene) == "lu");
    CHECK(chooseSolver(2001, scene) == "jacobi");
    omp_set_num_threads(1);
    CHECK(chooseSolver(50000, scene) == "sor");
    omp_set_num_threads(saved);
}

TEST_CASE("Many bands solved together (a year's hours) give each band's LU answer with every solver") {
    // Seven distinct bands, more than RGB's three: the stationary solvers sweep them in one pass over
    // F. Forty: Gauss-Seidel splits them among the threads. Fifty-three: tiles of uneven widths.
    Scene s = unitCube();
    const FormFactors F = exactCubeF();
    for (const std::size_t count : {std::size_t(7), std::size_t(40), std::size_t(53)}) {
        CAPTURE(count);
        std::vector<Band> bands(count);
        for (std::size_t b = 0; b < bands.size(); ++b) {
            bands[b].name = "hour " + std::to_string(b);
            for (std::size_t i = 0; i < 6; ++i) {
                bands[b].rho.push_back(0.1 + 0.1 * double((i + b) % 8));
                bands[b].source.push_back(i == b % 6 ? 1.0 + double(b) : 0.05 * double(i));
            }
        }
        SolverOptions lu;
        lu.solver = "lu";
        lu.tolerance = 1e-12;
        const BandSolution reference = solveBands(s, F, bands, lu);
        for (const std::string& kind : kAll) {
            CAPTURE(kind);
            SolverOptions o;
            o.solver = kind;
            o.tolerance = 1e-11;
            const BandSolution r = solveBands(s, F, bands, o);
            REQUIRE(r.X.size() == bands.size());
            for (std::size_t b = 0; b < bands.size(); ++b)
                for (std::size_t i = 0; i < 6; ++i) CHECK(r.X[b][i] == relative(reference.X[b][i], 1e-8));
            for (const SolveReport& report : r.reports) CHECK(report.converged);
            // Each band gets the same sweeps whatever the number of threads splitting the bands (the
            // tiles they come in follow the number of bands alone): the very same bits.
            if (kind != "jacobi" && kind != "gauss-seidel" && kind != "sor") continue;
            const int saved = omp_get_max_threads();
            for (const int threads : {1, 3}) {
                CAPTURE(threads);
                omp_set_num_threads(threads);
                const BandSolution other = solveBands(s, F, bands, o);
                for (std::size_t b = 0; b < bands.size(); ++b)
                    for (std::size_t i = 0; i < 6; ++i) CHECK(other.X[b][i] == r.X[b][i]);
            }
            omp_set_num_threads(saved);
        }
    }
}

TEST_CASE("Many bands by iterative refinement: float corrections, residuals in double, to a tolerance float alone cannot reach") {
    // From 32 bands on, Gauss-Seidel and SOR sweep corrections in float and check residuals in
    // double. Float's rounding (about 1e-7 of a sum) stops a correction near 1e-6 of its residual:
    // 1e-13 takes several corrections, and the answer must be LU's to the same digits as the
    // double sweeps give.
    Scene s = unitCube();
    const FormFactors F = exactCubeF();
    std::vector<Band> bands(45);
    for (std::size_t b = 0; b < bands.size(); ++b) {
        bands[b].name = "hour " + std::to_string(b);
        for (std::size_t i = 0; i < 6; ++i) {
            bands[b].rho.push_back(0.2 + 0.1 * double((i + b) % 7));
            bands[b].source.push_back(i == b % 6 ? 100.0 + double(b) : 0.3 * double(i) + 1e-3 * double(b));
        }
    }
    const BandSolution reference = solvedByLu(s, F, bands);
    for (const std::string kind : {"gauss-seidel", "sor"}) {
        CAPTURE(kind);
        SolverOptions o;
        o.solver = kind;
        o.tolerance = 1e-13;
        const BandSolution r = solveBands(s, F, bands, o);
        for (std::size_t b = 0; b < bands.size(); ++b)
            for (std::size_t i = 0; i < 6; ++i) CHECK(r.X[b][i] == relative(reference.X[b][i], 1e-12));
        REQUIRE(r.reports.size() == bands.size());
        const std::string& note = r.reports[0].note;
        CAPTURE(note);
        const std::size_t at = note.find("iterative refinement: ");
        REQUIRE(at != std::string::npos);
        const int corrections = std::stoi(note.substr(at + 22));
        CHECK(corrections >= 2);  // float alone could not have met 1e-13
        for (const SolveReport& report : r.reports) {
            CHECK(report.converged);
            CHECK(report.residual <= 1e-13);  // in double, on the final B
        }
        // A warm start close to the answer (not E): the first correction starts from its residual,
        // and fewer sweeps reach the same answer.
        std::vector<std::vector<double>> starts(bands.size());
        for (std::size_t b = 0; b < bands.size(); ++b) {
            for (std::size_t i = 0; i < 6; ++i) starts[b].push_back(reference.X[b][i] * (1.0 + 1e-5 * double(i + 1)));
            bands[b].initial = &starts[b];
        }
        const BandSolution warm = solveBands(s, F, bands, o);
        for (std::size_t b = 0; b < bands.size(); ++b) {
            bands[b].initial = nullptr;
            for (std::size_t i = 0; i < 6; ++i) CHECK(warm.X[b][i] == relative(reference.X[b][i], 1e-12));
        }
        CHECK(warm.reports[0].converged);
        CHECK(warm.reports[0].iterations < r.reports[0].iterations);
    }
}

TEST_CASE("Iterative refinement on 300 patches: 33, 90 and 157 bands (every tile width, rows in blocks) give LU's answer, the same bits on 1 and 3 threads") {
    // A synthetic F (not reciprocal, self factors on some rows, row sums 0.85) on 300 patches: more
    // than a block of rows, and band counts whose float tiles take 24 to 48 lanes.
    SceneBuilder builder;
    for (int k = 0; k < 300; ++k) builder.rectangle(k % 3, double(k), 0, 1, 0, 1, true);
    const Scene s = builder.scene;
    const std::size_t n = 300;
    std::uint64_t state = 12345;
    auto next = [&] { return (state = state * 6364136223846793005ULL + 1442695040888963407ULL) >> 33; };
    std::vector<std::vector<FormFactors::Entry>> rows(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        std::vector<std::uint32_t> columns;
        for (int e = 0; e < 40; ++e) columns.push_back(std::uint32_t(next() % n));
        if (i % 7 == 0) columns.push_back(i);  // a self factor, solved for exactly
        std::sort(columns.begin(), columns.end());
        columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
        std::vector<double> weights;
        for (std::size_t k = 0; k < columns.size(); ++k) weights.push_back(1.0 + double(next() % 1000) / 100.0);
        const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
        for (std::size_t k = 0; k < columns.size(); ++k) rows[i].push_back({columns[k], float(0.85 * weights[k] / total)});
    }
    const FormFactors F = FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(n, 1));
    for (const std::size_t count : {std::size_t(33), std::size_t(90), std::size_t(157)}) {
        CAPTURE(count);
        std::vector<Band> bands(count);
        for (std::size_t b = 0; b < count; ++b) {
            bands[b].name = "hour " + std::to_string(b);
            for (std::size_t i = 0; i < n; ++i) {
                bands[b].rho.push_back(0.2 + 0.7 * double((i * 7 + b * 3) % 11) / 10.0);
                bands[b].source.push_back((i + b) % 13 == 0 ? 50.0 + double(b) : 0.01 * double(i % 5));
            }
        }
        const BandSolution reference = solvedByLu(s, F, bands);
        for (const std::string kind : {"gauss-seidel", "sor"}) {
            CAPTURE(kind);
            SolverOptions o;
            o.solver = kind;
            o.tolerance = 1e-12;
            const BandSolution r = solveBands(s, F, bands, o);
            CHECK(r.reports[0].note.find("iterative refinement") != std::string::npos);
            for (const SolveReport& report : r.reports) CHECK(report.converged);
            double worst = 0.0;
            for (std::size_t b = 0; b < count; ++b)
                for (std::size_t i = 0; i < n; ++i)
                    worst = std::max(worst, std::abs(r.X[b][i] - reference.X[b][i]) / std::max(1.0, std::abs(reference.X[b][i])));
            CHECK(worst <= 1e-10);
            const int saved = omp_get_max_threads();
            for (const int threads : {1, 3}) {
                CAPTURE(threads);
                omp_set_num_threads(threads);
                const BandSolution other = solveBands(s, F, bands, o);
                bool same = true;
                for (std::size_t b = 0; b < count; ++b) same = same && other.X[b] == r.X[b];
                CHECK(same);
            }
            omp_set_num_threads(saved);
        }
    }
}

TEST_CASE("Iterative refinement where over-relaxation makes the steps grow: 40 bands round a ring go back to Gauss-Seidel and converge") {
    // The ring of the test below (each patch sees only the next: not reciprocal), 40 bands at once:
    // SOR's factor overshoots within a float correction, falls back to 1, and the next corrections
    // still reach LU's answer in double.
    const Scene s = cubeWith(0.9);
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    for (std::uint32_t i = 0; i < 6; ++i) rows[i].push_back({(i + 1) % 6, 1.0f});
    const FormFactors ring = FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(6, 1));
    std::vector<Band> bands(40);
    for (std::size_t b = 0; b < bands.size(); ++b) {
        bands[b].name = "hour " + std::to_string(b);
        for (std::size_t i = 0; i < 6; ++i) {
            bands[b].rho.push_back(0.9);
            bands[b].source.push_back(i == b % 6 ? 1.0 + double(b) : 0.0);
        }
    }
    const BandSolution reference = solvedByLu(s, ring, bands);
    SolverOptions o;
    o.solver = "sor";
    o.tolerance = 1e-11;
    const BandSolution r = solveBands(s, ring, bands, o);
    CAPTURE(r.reports[0].note);
    CHECK(r.reports[0].note.find("over-relaxation made the steps grow") != std::string::npos);
    CHECK(r.reports[0].note.find("iterative refinement") != std::string::npos);
    for (const SolveReport& report : r.reports) CHECK(report.converged);
    for (std::size_t b = 0; b < bands.size(); ++b)
        for (std::size_t i = 0; i < 6; ++i) CHECK(r.X[b][i] == relative(reference.X[b][i], 1e-9));
}

TEST_CASE("SOR adapts its factor: fewer sweeps than Gauss-Seidel to the same answer, and Gauss-Seidel again where over-relaxing grows the steps") {
    // The closed cube at rho = 0.9: F reciprocal, so any factor in (0, 2) converges.
    const Scene s = cubeWith(0.9);
    const Radiosity exact = solveWith(s, exactCubeF(), "lu");
    const Radiosity gs = solveWith(s, exactCubeF(), "gauss-seidel");
    const Radiosity sor = solveWith(s, exactCubeF(), "sor");
    REQUIRE(sor.reports.size() == 1);
    CHECK(sor.reports[0].converged);
    CHECK(sor.reports[0].note.find("relaxation factor 1.") != std::string::npos);
    CHECK(sor.reports[0].note.find("relaxation factor 1.000") == std::string::npos);
    CHECK(sor.reports[0].iterations * 4 < gs.reports[0].iterations * 3);
    for (int i = 0; i < 6; ++i) CHECK(sor.B[i][0] == relative(exact.B[i][0], 1e-8));

    // Light passed round a ring, each patch seeing only the next (not reciprocal): the Jacobi
    // matrix's eigenvalues are complex, Young's factor overshoots and the steps grow. SOR goes back
    // to Gauss-Seidel, says so, and converges; held at that factor it would diverge.
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    for (std::uint32_t i = 0; i < 6; ++i) rows[i].push_back({(i + 1) % 6, 1.0f});
    const FormFactors ring = FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(6, 1));
    const Radiosity ringExact = solveWith(s, ring, "lu");
    const Radiosity ringSor = solveWith(s, ring, "sor");
    REQUIRE(ringSor.reports.size() == 1);
    CHECK(ringSor.reports[0].converged);
    CHECK(ringSor.reports[0].note.find("over-relaxation made the steps grow") != std::string::npos);
    for (int i = 0; i < 6; ++i) CHECK(ringSor.B[i][0] == relative(ringExact.B[i][0], 1e-8));
}
