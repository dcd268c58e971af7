// One hour of sun and sky: the decomposition against a dense solve written in the test, and the
// power balance (incident = absorbed + escaped) to 1e-9.
#include "support.hpp"

#include "engine/error.hpp"
#include "environment/irradiance.hpp"
#include "environment/reflected_sun.hpp"
#include "environment/sky_view.hpp"
#include "environment/sunlit.hpp"
#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"

#include <Eigen/Dense>
#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

TEST_CASE("Irradiance of a ground patch and a wall in sun and sky: direct, sky, reflected by a 2 x 2 solve, balanced to 1e-9") {
    SceneBuilder b;
    const std::uint32_t ground = b.material("ground", Rgb::Constant(0.3));
    const std::uint32_t wall = b.material("wall", Rgb(0.5, 0.6, 0.7), Rgb::Zero(), 0.2);
    b.rectangle(2, 0.0, 0, 1, 0, 1, true, ground);   // z = 0 facing up, x in [0, 1]
    b.rectangle(0, 0.0, 0, 1, 0, 2, true, wall);     // x = 0 facing +x, height 2
    const Scene& s = b.scene;
    const Vec3 sun(1, 0.3, 1.2);
    const double dni = 800, dhi = 120;
    IrradianceInputs in;
    in.directSun = directIrradiance(s, sun, dni, sunlitFractions(s, sun));
    in.skyView = skyViewFactors(s, MethodSettings::of(HemisphereOptions{})).direct;
    in.dhi = dhi;
    const FormFactors F = computeFormFactors(s, MethodSettings::of(HemisphereOptions{}), neededRows(s, true)).F;
    SolverOptions lu;
    lu.solver = "lu";
    const IrradianceResult r = solarIrradiance(s, F, in, 1.0, lu);
    // The wall faces the sun (x > 0): lit whole; the ground too (nothing between it and the sun).
    CHECK(r.directSun[0] == doctest::Approx(dni * sun.normalized().z()));
    CHECK(r.directSun[1] == doctest::Approx(dni * sun.normalized().x()));
    CHECK(r.directSky[0] == relative(dhi * (1 - c14(1, 2, 1)), 1e-4));
    // By hand: J = rho (E + F J), rho the mean Kd (0.3 and 0.6).
    const double rho[2] = {0.3, 0.6};
    Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
    Eigen::Vector2d e;
    for (int i = 0; i < 2; ++i) {
        e[i] = rho[i] * (r.directSun[i] + r.directSky[i]);
        for (int j = 0; j < 2; ++j) A(i, j) -= rho[i] * F.at(i, j);
    }
    const Eigen::Vector2d J = A.fullPivLu().solve(e);
    for (int i = 0; i < 2; ++i) {
        const double H = F.at(i, 0) * J[0] + F.at(i, 1) * J[1];
        CHECK(r.reflected[i] == relative(H, 1e-12));
        CHECK(r.absorbed[i] == relative((1 - rho[i] - s.patches[i].specular) * (r.directSun[i] + r.directSky[i] + H), 1e-12));
    }
    MESSAGE("incident " << r.incidentPower << " W, absorbed " << r.absorbedPower << ", escaped " << r.escapedPower << ", balance " << r.balance);
    CHECK(r.balance <= 1e-9);
}

TEST_CASE("Irradiance with a mirror: the sun it reflects lands on the wall as a first arrival, and the power still balances") {
    // The mirror [0, 1]^2 at z = 0 (s = 0.8, Kd 0.1) under a 45-degree sun, the wall x = -2 facing it:
    // the beam's footprint 1 of the wall's 15 (test_reflected_sun.cpp), s DNI cos 45 where it lands.
    SceneBuilder b;
    const std::uint32_t mirror = b.material("mirror", Rgb::Constant(0.1), Rgb::Zero(), 0.8);
    const std::uint32_t wall = b.material("wall", Rgb::Constant(0.5));
    b.rectangle(2, 0.0, 0, 1, 0, 1, true, mirror);
    b.rectangle(0, -2.0, -1, 2, 0, 5, true, wall);
    const Scene& s = b.scene;
    const Vec3 sun(1, 0, 1);
    const double dni = 800, dhi = 100;
    IrradianceInputs in;
    in.directSun = directIrradiance(s, sun, dni, sunlitFractions(s, sun));
    in.skyView = skyViewFactors(s, MethodSettings::of(HemisphereOptions{})).direct;
    in.dhi = dhi;
    in.reflectedSun = reflectedSun(s, sun, dni).irradiance;
    const FormFactors F = computeFormFactors(s, MethodSettings::of(HemisphereOptions{}), neededRows(s, true)).F;
    SolverOptions lu;
    lu.solver = "lu";
    const IrradianceResult r = solarIrradiance(s, F, in, 1.0, lu);
    const double landed = 0.8 * dni * std::sqrt(0.5) / 15.0;
    CHECK(r.reflectedSun[1] == relative(landed, 1e-12));
    CHECK(r.directSun[1] == relative(dni * std::sqrt(0.5), 1e-12));  // the wall faces the sun too
    CHECK(r.total[1] == relative(r.directSun[1] + r.directSky[1] + landed + r.reflected[1], 1e-12));
    // Only the sun and sky come from outside: the landed beam is part of the mirror's reflection.
    const double outside = 1.0 * (r.directSun[0] + r.directSky[0]) + 15.0 * (r.directSun[1] + r.directSky[1]);
    CHECK(r.incidentPower == relative(outside, 1e-12));
    MESSAGE("incident " << r.incidentPower << " W, absorbed " << r.absorbedPower << ", escaped " << r.escapedPower << ", balance " << r.balance);
    CHECK(r.balance <= 1e-9);
    // Without it, the mirror's whole specular reflection leaves: the same power comes in, less is absorbed.
    in.reflectedSun.clear();
    const IrradianceResult without = solarIrradiance(s, F, in, 1.0, lu);
    CHECK(without.balance <= 1e-9);
    CHECK(without.incidentPower == relative(r.incidentPower, 1e-12));
    CHECK(without.absorbedPower < r.absorbedPower);
    CHECK(without.escapedPower > r.escapedPower);
}

TEST_CASE("Irradiance inputs of the wrong size are refused") {
    SceneBuilder b;
    b.rectangle(2, 0.0, 0, 1, 0, 1, true);
    const FormFactors F = computeFormFactors(b.scene, MethodSettings::of(HemisphereOptions{}), neededRows(b.scene, true)).F;
    IrradianceInputs in;
    in.directSun = {1.0, 2.0};
    in.skyView = {1.0};
    CHECK_THROWS_WITH_AS(solarIrradiance(b.scene, F, in, 1.0, SolverOptions{}), doctest::Contains("one entry per patch"), Error);
}

TEST_CASE("hemirad irradiance --sky MODEL: the model's cells reported, the sky through mirrors a column, and usage errors") {
    const auto dir = tempDir("irradiance-sky");
    const std::string hemirad = std::string(HEMIRAD_BINARY) + " irradiance " + sourcePath("scenes/cornell_mirror.obj") +
                                " --up y --unit mm --sun-direction 0.2,1,0.5 --dni 700 --dhi 100";
    CommandResult r = runCommand(hemirad + " --sky cie-overcast --sky-subdivision 1 -o " + (dir / "e.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("sky: cie-overcast, 145 cells (Tregenza) x 1 direction(s)") != std::string::npos);
    CHECK(readText(dir / "e.csv").find(",reflected_sun (W/m^2),reflected_sky (W/m^2)\n") != std::string::npos);
    r = runCommand(hemirad + " --sky perez --sun-time 2026-06-21T10:00Z -o x.csv 2>&1");  // a time with a direction
    CHECK(r.status == 2);
    r = runCommand(hemirad + " --sky clear -o x.csv 2>&1");
    CHECK(r.status == 2);
    CHECK(r.output.find("'clear' is not a sky model") != std::string::npos);
    r = runCommand(hemirad + " --sky-samples 2 -o x.csv 2>&1");
    CHECK(r.status == 2);
    CHECK(r.output.find("give --sky MODEL") != std::string::npos);
    CHECK(runCommand(hemirad + " --sky perez --sky-subdivision 9 -o x.csv 2>&1").status == 2);
}
