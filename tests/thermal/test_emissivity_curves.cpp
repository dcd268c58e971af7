// Emissivity against temperature (issue 36): known temperatures take the curve's value there (the
// two-surface closed form), a flux surface's and an isothermal node's temperatures against
// bisections written here over the closed form and over dense 3 x 3 solves, and the properties
// file's curves with their errors (file:line).
#include "thermal/thermal_scenes.hpp"

#include "engine/error.hpp"
#include "thermal/thermal_files.hpp"
#include "thermal/thermal_solver.hpp"

#include <Eigen/Dense>
#include <doctest/doctest.h>

#include <cmath>
#include <functional>

using namespace hemirad;
using namespace hemirad::test;
using namespace hemirad::thermal;

namespace {

/// Piecewise linear through (T_k, e_k), constant beyond the ends: written here, not the model's.
double curveAt(const std::vector<std::pair<double, double>>& points, double T) {
    if (T <= points.front().first) return points.front().second;
    for (std::size_t k = 1; k < points.size(); ++k)
        if (T <= points[k].first) {
            const auto [t0, e0] = points[k - 1];
            const auto [t1, e1] = points[k];
            return e0 + (T - t0) / (t1 - t0) * (e1 - e0);
        }
    return points.back().second;
}

EmissivityCurve curveOf(const std::vector<std::pair<double, double>>& points) {
    EmissivityCurve c;
    for (const auto& [T, e] : points) {
        c.temperatureK.push_back(T);
        c.emissivity.push_back(e);
    }
    return c;
}

/// The root of the increasing g on [lo, hi] by bisection.
double bisect(const std::function<double(double)>& g, double lo, double hi) {
    for (int step = 0; step < 200; ++step) {
        const double mid = 0.5 * (lo + hi);
        (g(mid) < 0 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

/// A unit square inside a 2 x 1 one: F12 = 1, F21 = F22 = 1/2 (dyadic, exact), areas 1 and 2.
Scene twoSurfaces(SceneBuilder& b) {
    b.scene.objects = {"inner", "outer"};
    b.rectangle(2, 0.0, 0, 1, 0, 1, true);
    b.rectangle(2, 1.0, 0, 2, 0, 1, false);
    b.scene.patches[1].object = 1;
    return b.scene;
}

ThermalModel grayModel(std::size_t n) {
    ThermalModel m;
    m.surface.assign(n, SurfaceProperties{0.5, 0.0});
    m.condition.assign(n, Condition{});
    m.curveOf.assign(n, -1);
    return m;
}

const std::vector<std::pair<double, double>> kOxidisedSteel = {{300, 0.3}, {600, 0.55}, {1000, 0.8}, {1400, 0.85}};

/// The two surfaces' model: the inner held at T1 (eps 0.9), the outer, whose emissivity follows
/// `curve`, given a net flux -Q1 / 2 (its area is 2: it takes Q1 away).
ThermalModel innerHeldOuterCurved(const std::vector<std::pair<double, double>>& curve, double T1, double Q1) {
    ThermalModel m = grayModel(2);
    m.surface[0].emissivity = 0.9;
    m.emissivityCurves = {curveOf(curve)};
    m.curveOf = {-1, 0};
    m.condition = {Condition{Condition::Kind::Temperature, T1, 0}, Condition{Condition::Kind::Flux, -Q1 / 2, 0}};
    return m;
}

}  // namespace

TEST_CASE("Emissivity against temperature: known temperatures take the curve's value there (two-surface closed form)") {
    SceneBuilder b;
    const Scene s = twoSurfaces(b);
    const FormFactors F = denseF({{0.0, 1.0}, {0.5, 0.5}});
    ThermalModel m = grayModel(2);
    m.emissivityCurves = {curveOf(kOxidisedSteel)};
    m.curveOf = {0, -1};
    m.surface[1].emissivity = 0.6;
    const double T1 = 800, T2 = 300;
    m.condition = {Condition{Condition::Kind::Temperature, T1, 0}, Condition{Condition::Kind::Temperature, T2, 0}};
    const ThermalSolution sol = solveThermal(s, F, m, SolverOptions{});
    const double e1 = curveAt(kOxidisedSteel, T1);
    const double expected = (blackbody(T1) - blackbody(T2)) / (1 / e1 + 0.5 * (1 / 0.6 - 1));
    MESSAGE("eps(800 K) = " << e1 << ": Q1 = " << sol.Q[0] << " W, closed form " << expected << "; " << sol.report.note);
    CHECK(sol.Q[0] == relative(expected, 1e-10));
    CHECK(sol.Q[1] == relative(-expected, 1e-10));
    CHECK(sol.balance <= 1e-9);
}

TEST_CASE("Emissivity against temperature: a flux surface's temperature balances with its emissivity at that temperature") {
    // Inner at 1000 K (eps 0.9), the outer given a net flux -q (it takes Q1 = 2 q away): the closed
    // form Q1 = (Eb1 - Eb2) / (1 / eps1 + (A1 / A2) (1 / eps2(T2) - 1)) solved for T2 by bisection.
    SceneBuilder b;
    const Scene s = twoSurfaces(b);
    const FormFactors F = denseF({{0.0, 1.0}, {0.5, 0.5}});
    const double T1 = 1000, Q1 = 20000;
    const ThermalModel m = innerHeldOuterCurved(kOxidisedSteel, T1, Q1);
    const ThermalSolution sol = solveThermal(s, F, m, SolverOptions{});
    const double T2 = bisect(
        [&](double T) { return Q1 * (1 / 0.9 + 0.5 * (1 / curveAt(kOxidisedSteel, T) - 1)) - (blackbody(T1) - blackbody(T)); },
        0.0, T1);
    // With the curve's value at the reference temperature (300 K) held constant instead:
    const double held = bisect(
        [&](double T) { return Q1 * (1 / 0.9 + 0.5 * (1 / curveAt(kOxidisedSteel, 300) - 1)) - (blackbody(T1) - blackbody(T)); },
        0.0, T1);
    MESSAGE("outer: " << sol.T[1] << " K (by hand " << T2 << " K; with eps held at 300 K's: " << held << " K); " << sol.report.note);
    CHECK(sol.T[1] == relative(T2, 1e-10));
    CHECK(std::abs(T2 - held) > 10.0);  // the curve matters here
    CHECK(sol.Q[0] == relative(Q1, 1e-9));
    CHECK(sol.balance <= 1e-9);
}

TEST_CASE("Emissivity against temperature: a curve that is 0 at the reference temperature still starts and solves") {
    // The outer surface emits only above 500 K (0 at the 300 K start): its temperature must come
    // out finite and satisfy the two-surface closed form with its emissivity there.
    SceneBuilder b;
    const Scene s = twoSurfaces(b);
    const FormFactors F = denseF({{0.0, 1.0}, {0.5, 0.5}});
    const std::vector<std::pair<double, double>> late = {{500, 0.0}, {1000, 0.8}};
    const double T1 = 1000, Q1 = 2000;
    ThermalModel m = innerHeldOuterCurved(late, T1, Q1);
    m.surface[1].emissivity = 0.0;
    const ThermalSolution sol = solveThermal(s, F, m, SolverOptions{});
    const double T2 = sol.T[1], e2 = curveAt(late, T2);
    MESSAGE("outer: " << T2 << " K, eps " << e2 << "; " << sol.report.note);
    REQUIRE(std::isfinite(T2));
    CHECK(e2 > 0.0);
    CHECK(Q1 == relative((blackbody(T1) - blackbody(T2)) / (1 / 0.9 + 0.5 * (1 / e2 - 1)), 1e-9));
    CHECK(sol.balance <= 1e-9);
    // An isothermal node whose curve is 0 at 300 K emits elsewhere: accepted.
    m.isothermal = {IsothermalNode{"outer", -Q1}};
    m.condition[1] = Condition{Condition::Kind::Isothermal, 0.0, 0};
    CHECK_NOTHROW(checkModel(s, m));
}

TEST_CASE("Emissivity against temperature: a heated isothermal plate against a bisection over dense solves") {
    // Three unit squares, F_ij = 1/2: a at 700 K (eps 0.8), b an isothermal node giving off 3 kW
    // whose emissivity follows the curve, c at 300 K (eps 0.4). (At 0 W its emissivity would not
    // matter: a reradiating surface's radiosity is its irradiance whatever it is.)
    SceneBuilder b;
    b.scene.objects = {"a", "b", "c"};
    for (int k = 0; k < 3; ++k) b.rectangle(2, double(k), 0, 1, 0, 1, true);
    for (PatchId i = 0; i < 3; ++i) b.scene.patches[i].object = i;
    const FormFactors F = denseF({{0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}});
    ThermalModel m = grayModel(3);
    m.surface[0].emissivity = 0.8;
    m.surface[2].emissivity = 0.4;
    m.emissivityCurves = {curveOf(kOxidisedSteel)};
    m.curveOf = {-1, 0, -1};
    m.isothermal = {IsothermalNode{"b", 3000.0}};
    m.condition = {Condition{Condition::Kind::Temperature, 700, 0}, Condition{Condition::Kind::Isothermal, 0.0, 0},
                   Condition{Condition::Kind::Temperature, 300, 0}};
    const ThermalSolution sol = solveThermal(b.scene, F, m, SolverOptions{});
    // By hand: J = eps E + (1 - eps) F J for a trial T_b, its net q_b = eps_b (E_b - (F J)_b).
    auto netOfB = [&](double Tb) {
        const double T[3] = {700, Tb, 300}, eps[3] = {0.8, curveAt(kOxidisedSteel, Tb), 0.4};
        Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
        Eigen::Vector3d e;
        for (int i = 0; i < 3; ++i) {
            e[i] = eps[i] * blackbody(T[i]);
            for (int j = 0; j < 3; ++j) A(i, j) -= (1 - eps[i]) * F.at(i, j);
        }
        const Eigen::Vector3d J = A.fullPivLu().solve(e);
        return eps[1] * (blackbody(Tb) - 0.5 * (J[0] + J[2]));
    };
    const double Tb = bisect([&](double T) { return netOfB(T) - 3000.0; }, 300, 3000);
    MESSAGE("plate: " << sol.isothermalT[0] << " K (by hand " << Tb << " K); " << sol.report.note);
    CHECK(sol.isothermalT[0] == relative(Tb, 1e-10));
    CHECK(sol.Q[1] == relative(3000.0, 1e-9));
    CHECK(sol.balance <= 1e-9);
}

TEST_CASE("Emissivity against temperature from the properties file: [[T_K, eps], ...], and its errors with file and line") {
    SceneBuilder b;
    Scene s = twoSurfaces(b);
    std::vector<std::string> sources;
    BandProperties bands;
    const auto surface = applyPropertiesText("[objects.outer]\nemissivity = [[300, 0.3], [1000, 0.8]]\n[default]\nemissivity = 0.7\n",
                                             "p.toml", s, sources, nullptr, &bands);
    REQUIRE(bands.curveOf.size() == 2);
    CHECK(bands.curveOf[0] == -1);
    CHECK(bands.curveOf[1] == 0);
    REQUIRE(bands.emissivityCurves.size() == 1);
    CHECK(bands.emissivityCurves[0].at(650) == doctest::Approx(0.55).epsilon(1e-14));
    CHECK(surface[0].emissivity == 0.7);
    CHECK(surface[1].emissivity == 0.3);  // at the reference temperature, 300 K
    CHECK(sources[1].find("emissivity against temperature from [objects.outer]") != std::string::npos);
    ThermalModel model;
    takeBandProperties(model, std::move(bands));
    CHECK(hasEmissivityCurves(model));

    const auto refused = [&](const std::string& text, const std::string& message) {
        CAPTURE(text);
        CHECK_THROWS_WITH_AS(applyPropertiesText(text, "p.toml", s, sources, nullptr, &bands), doctest::Contains(message.c_str()), Error);
    };
    refused("[default]\nemissivity = [[300, 0.3],\n  [300, 0.8]]\n", "p.toml:3: emissivity in [default]: temperature 300 K must be >= 0 and above");
    refused("[default]\nemissivity = [[300, 0.3], [400, 1.2]]\n", "emissivity 1.2 at 400 K in [default] is outside [0, 1]");
    refused("[default]\nemissivity = [[300, 0.3, 2]]\n", "a curve against temperature is a list of [T_K, eps] pairs");
    refused("[default]\nemissivity = [[300, 0.3], [900, 0.9]]\nspecular = 0.2\n", "emissivity 0.9 + specular 0.2");
    refused("[bands]\nlimits_um = [5.0]\n[default]\nemissivity = [[300, 0.3], [900, 0.9]]\n",
            "an emissivity curve against temperature takes the gray model");
}
