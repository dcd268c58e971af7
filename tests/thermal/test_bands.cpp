// Non-gray IR: blackbody fractions against the tables, a banded two-surface enclosure against its
// closed form band by band, a banded reradiating surface against an independent dense solve, and
// the gray limit.
#include "thermal/thermal_scenes.hpp"

#include "engine/error.hpp"
#include "thermal/blackbody.hpp"
#include "thermal/thermal_solver.hpp"

#include <Eigen/Dense>
#include <doctest/doctest.h>

#include <limits>

using namespace hemirad;
using namespace hemirad::test;
using namespace hemirad::thermal;

namespace {

const double kInfinity = std::numeric_limits<double>::infinity();

/// Three unit squares, F_ij = 1/2 (an abstract closed duct), objects a, b, c.
Scene duct() {
    SceneBuilder b;
    b.scene.objects = {"a", "b", "c"};
    for (int k = 0; k < 3; ++k) b.rectangle(2, double(k), 0, 1, 0, 1, true);
    for (PatchId i = 0; i < 3; ++i) b.scene.patches[i].object = i;
    return b.scene;
}

ThermalModel banded(std::size_t n, std::vector<double> limits, std::vector<std::vector<double>> epsPerPatch) {
    ThermalModel m;
    m.bandLimitsUm = std::move(limits);
    m.bandEmissivity.assign(m.bandLimitsUm.size() + 1, std::vector<double>(n));
    m.surface.assign(n, SurfaceProperties{});
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < m.bandEmissivity.size(); ++k) m.bandEmissivity[k][i] = epsPerPatch[i][k];
        double e = 0;
        for (std::size_t k = 0; k < m.bandEmissivity.size(); ++k) {
            const double lo = k ? m.bandLimitsUm[k - 1] : 0.0, hi = k < m.bandLimitsUm.size() ? m.bandLimitsUm[k] : kInfinity;
            e += epsPerPatch[i][k] * bandFraction(lo, hi, 300.0);
        }
        m.surface[i].emissivity = e;
    }
    m.condition.assign(n, Condition{});
    return m;
}

}  // namespace

TEST_CASE("Blackbody fractions F(0 -> lambda T) match Planck's law integrated numerically and join smoothly where the series switch") {
    // F = (15 / pi^4) int_z^inf x^3 / (e^x - 1) dx, z = C2 / (lambda T): composite Simpson in the test.
    auto planck = [](double lambdaT) {
        const double z = kSecondRadiationConstant / lambdaT, top = z + 80.0;
        const int steps = 200000;
        const double h = (top - z) / steps;
        auto f = [](double x) { return x * x * x / std::expm1(x); };
        double sum = f(z) + f(top);
        for (int k = 1; k < steps; ++k) sum += (k % 2 ? 4.0 : 2.0) * f(z + k * h);
        return 15.0 / std::pow(kPi, 4) * sum * h / 3.0;
    };
    for (const double lambdaT : {500.0, 1000.0, 2898.0, 5000.0, 10000.0, 25000.0, 50000.0}) {
        CAPTURE(lambdaT);
        CHECK(std::abs(blackbodyFraction(lambdaT) - planck(lambdaT)) < 1e-11);
    }
    CHECK(blackbodyFraction(2898.0) == relative(0.2501, 1e-4));  // Wien's peak: a quarter below
    const double z05 = kSecondRadiationConstant / 0.5;  // the switch between the two series
    CHECK(std::abs(blackbodyFraction(z05 * (1 - 1e-12)) - blackbodyFraction(z05 * (1 + 1e-12))) < 1e-13);
    CHECK(blackbodyFraction(0.0) == 0.0);
    CHECK(blackbodyFraction(kInfinity) == 1.0);
    CHECK(bandFraction(0.0, kInfinity, 300.0) == relative(1.0, 1e-15));
}

TEST_CASE("Bands: a two-surface enclosure exchanges band by band as the closed form with the bands' blackbody fractions") {
    // Areas 1 and 2, F12 = 1, F21 = F22 = 1/2 (a convex surface inside another, dyadic and exact).
    SceneBuilder b;
    b.scene.objects = {"inner", "outer"};
    b.rectangle(2, 0.0, 0, 1, 0, 1, true);
    b.rectangle(2, 1.0, 0, 2, 0, 1, false);
    b.scene.patches[1].object = 1;
    const FormFactors F = denseF({{0.0, 1.0}, {0.5, 0.5}});
    const std::vector<double> limits = {3.0, 8.0};
    const std::vector<std::vector<double>> eps = {{0.2, 0.5, 0.9}, {0.8, 0.3, 0.6}};
    ThermalModel m = banded(2, limits, eps);
    const double T1 = 800, T2 = 300;
    m.condition = {Condition{Condition::Kind::Temperature, T1, 0}, Condition{Condition::Kind::Temperature, T2, 0}};
    const ThermalSolution sol = solveThermal(b.scene, F, m, SolverOptions{});
    double expected = 0;
    for (std::size_t k = 0; k < 3; ++k) {
        const double lo = k ? limits[k - 1] : 0.0, hi = k < 2 ? limits[k] : kInfinity;
        const double Eb1 = bandFraction(lo, hi, T1) * blackbody(T1), Eb2 = bandFraction(lo, hi, T2) * blackbody(T2);
        expected += (Eb1 - Eb2) / (1 / eps[0][k] + 0.5 * (1 / eps[1][k] - 1));
    }
    MESSAGE("banded enclosure: Q1 = " << sol.Q[0] << " W, closed form " << expected);
    CHECK(sol.Q[0] == relative(expected, 1e-10));
    CHECK(sol.Q[1] == relative(-expected, 1e-10));
    CHECK(sol.balance <= 1e-9);
}

TEST_CASE("Bands: a reradiating surface's temperature matches an independent bisection over dense band solves") {
    const Scene s = duct();
    const FormFactors F = denseF({{0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}});
    const std::vector<double> limits = {4.0};
    const std::vector<std::vector<double>> eps = {{0.9, 0.9}, {0.1, 0.7}, {0.6, 0.2}};
    ThermalModel m = banded(3, limits, eps);
    m.condition = {Condition{Condition::Kind::Temperature, 700, 0}, Condition{Condition::Kind::Flux, 0.0, 0},
                   Condition{Condition::Kind::Temperature, 300, 0}};
    const ThermalSolution sol = solveThermal(s, F, m, SolverOptions{});
    // By hand: for a trial T_b, per band J = eps E + (1 - eps) F J (3 x 3), q_b = sum_k eps_k (E_k - (F J_k)_b).
    auto netOfB = [&](double Tb, double* Q0) {
        const double T[3] = {700, Tb, 300};
        double q = 0, q0 = 0;
        for (std::size_t k = 0; k < 2; ++k) {
            const double lo = k ? 4.0 : 0.0, hi = k ? kInfinity : 4.0;
            Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
            Eigen::Vector3d e;
            for (int i = 0; i < 3; ++i) {
                e[i] = eps[i][k] * bandFraction(lo, hi, T[i]) * blackbody(T[i]);
                for (int j = 0; j < 3; ++j) A(i, j) -= (1 - eps[i][k]) * F.at(i, j);
            }
            const Eigen::Vector3d J = A.fullPivLu().solve(e);
            for (int i : {0, 1}) {
                double H = 0;
                for (int j = 0; j < 3; ++j) H += F.at(i, j) * J[j];
                const double net = eps[i][k] * (bandFraction(lo, hi, T[i]) * blackbody(T[i]) - H);
                (i == 0 ? q0 : q) += net;
            }
        }
        if (Q0) *Q0 = q0;
        return q;
    };
    double lo = 300, hi = 700;
    for (int step = 0; step < 200; ++step) {
        const double mid = 0.5 * (lo + hi);
        (netOfB(mid, nullptr) < 0 ? lo : hi) = mid;
    }
    double Q0 = 0;
    netOfB(0.5 * (lo + hi), &Q0);
    MESSAGE("banded reradiating surface: " << sol.T[1] << " K (reference " << 0.5 * (lo + hi) << " K), "
                                           << sol.report.note << "; Q_a = " << sol.Q[0] << " W (reference " << Q0 << ")");
    CHECK(sol.T[1] == relative(0.5 * (lo + hi), 1e-10));
    CHECK(sol.Q[0] == relative(Q0, 1e-9));
    CHECK(std::abs(sol.Q[1]) == 0.0);
    CHECK(sol.balance <= 1e-9);
}

TEST_CASE("Bands with their own specular reflectances: a mirror in one band, each band on its own F, against bisection over dense band solves") {
    // The duct's third wall reflects s specularly back where it came from (a retroreflector, which
    // diffuse reflection is not): the extended factors are F_00 = F_11 = s/2 and the rest 1/2
    // (exact, closed, reciprocal). A polished wall: s = 0.9
    // below 4 um, 0 above, facing a wall at 1500 K (three quarters of its emission below 4 um); the
    // scene (and F) hold the reflectances weighted at 300 K.
    Scene s = duct();
    const std::vector<double> limits = {4.0};
    const std::vector<std::vector<double>> eps = {{0.9, 0.9}, {0.1, 0.7}, {0.05, 0.9}};
    const double mirror[2] = {0.9, 0.0};
    auto ductF = [](double r) {
        return denseF({{r / 2, 0.5, 0.5}, {0.5, r / 2, 0.5}, {0.5, 0.5, 0.0}});
    };
    ThermalModel m = banded(3, limits, eps);
    m.bandSpecular.assign(2, std::vector<double>(3, 0.0));
    const double f0 = bandFraction(0.0, 4.0, 300.0);
    const double weighted = mirror[0] * f0 + mirror[1] * (1.0 - f0);
    for (std::size_t k = 0; k < 2; ++k) m.bandSpecular[k][2] = mirror[k];
    s.patches[2].specular = m.surface[2].specular = weighted;
    m.condition = {Condition{Condition::Kind::Temperature, 1500, 0}, Condition{Condition::Kind::Flux, 0.0, 0},
                   Condition{Condition::Kind::Temperature, 300, 0}};
    const FormFactors F = ductF(weighted), F0 = ductF(mirror[0]), F1 = ductF(mirror[1]);
    CHECK_THROWS_WITH_AS(solveThermal(s, F, m, SolverOptions{}), doctest::Contains("IR band 1's specular reflectances differ"), Error);
    const ThermalSolution sol = solveThermal(s, F, m, SolverOptions{}, {&F0, &F1});
    // By hand: per band J = eps E + rho_d F_k J with rho_d = 1 - eps_k - s_k, H = F_k J.
    auto netOfB = [&](double Tb, double* Q0, bool ownF) {
        const double T[3] = {1500, Tb, 300};
        double q = 0, q0 = 0;
        for (std::size_t k = 0; k < 2; ++k) {
            const double lo = k ? 4.0 : 0.0, hi = k ? kInfinity : 4.0;
            const FormFactors& Fk = ownF ? (k ? F1 : F0) : F;
            Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
            Eigen::Vector3d e;
            for (int i = 0; i < 3; ++i) {
                const double sk = i == 2 ? (ownF ? mirror[k] : weighted) : 0.0;
                e[i] = eps[i][k] * bandFraction(lo, hi, T[i]) * blackbody(T[i]);
                for (int j = 0; j < 3; ++j) A(i, j) -= (1 - eps[i][k] - sk) * Fk.at(i, j);
            }
            const Eigen::Vector3d J = A.fullPivLu().solve(e);
            for (int i : {0, 1}) {
                double H = 0;
                for (int j = 0; j < 3; ++j) H += Fk.at(i, j) * J[j];
                (i == 0 ? q0 : q) += eps[i][k] * (bandFraction(lo, hi, T[i]) * blackbody(T[i]) - H);
            }
        }
        if (Q0) *Q0 = q0;
        return q;
    };
    auto reradiating = [&](bool ownF) {
        double lo = 300, hi = 1500;
        for (int step = 0; step < 200; ++step) {
            const double mid = 0.5 * (lo + hi);
            (netOfB(mid, nullptr, ownF) < 0 ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    };
    const double Tb = reradiating(true), grayMirror = reradiating(false);
    double Q0 = 0;
    netOfB(Tb, &Q0, true);
    MESSAGE("per-band mirror: T_b = " << sol.T[1] << " K (reference " << Tb << " K; " << grayMirror
                                      << " K with one weighted mirror in both bands); Q_a = " << sol.Q[0] << " W (reference " << Q0 << ")");
    CHECK(std::abs(Tb - grayMirror) > 1.0);  // the case tells the two apart
    CHECK(sol.T[1] == relative(Tb, 1e-10));
    CHECK(sol.Q[0] == relative(Q0, 1e-9));
    CHECK(sol.balance <= 1e-9);
    // A band given F itself (nullptr) where its reflectances are the scene's: no own F needed.
    ThermalModel same = m;
    same.bandSpecular[1][2] = weighted;
    CHECK_NOTHROW(solveThermal(s, F, same, SolverOptions{}, {&F0, nullptr}));
    // Out of range per band.
    ThermalModel bad = m;
    bad.bandSpecular[1][2] = 0.6;  // eps 0.9 + 0.6 > 1
    CHECK_THROWS_WITH_AS(solveThermal(s, F, bad, SolverOptions{}, {&F0, &F1}),
                         doctest::Contains("band 2 emissivity 0.9 + specular 0.6 must be in [0, 1]"), Error);
}

TEST_CASE("Bands with equal emissivities are the gray model") {
    const Scene s = duct();
    const FormFactors F = denseF({{0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}});
    ThermalModel m = banded(3, {2.0, 6.0, 20.0}, {{0.7, 0.7, 0.7, 0.7}, {0.4, 0.4, 0.4, 0.4}, {0.9, 0.9, 0.9, 0.9}});
    m.condition = {Condition{Condition::Kind::Temperature, 500, 0}, Condition{Condition::Kind::Isothermal, 0.0, 0},
                   Condition{Condition::Kind::Flux, 100.0, 0}};
    m.isothermal = {{"b", -50.0}};
    m.environment = 3.0;
    const ThermalSolution bands = solveThermal(s, F, m, SolverOptions{});
    ThermalModel gray = m;
    gray.bandEmissivity.clear();
    gray.bandLimitsUm.clear();
    const ThermalSolution one = solveThermal(s, F, gray, SolverOptions{});
    for (PatchId i = 0; i < 3; ++i) {
        CHECK(bands.T[i] == relative(one.T[i], 1e-11));
        CHECK(bands.Q[i] == relative(one.Q[i], 1e-9));
    }
    CHECK(bands.isothermalT[0] == relative(one.isothermalT[0], 1e-11));
}
