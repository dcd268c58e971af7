// The thermal TOML files: what they set, and every mistake named by file and line.
#include "thermal/thermal_scenes.hpp"

#include "engine/error.hpp"
#include "thermal/blackbody.hpp"
#include "thermal/thermal_files.hpp"
#include "thermal/thermal_solver.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;
using namespace hemirad::thermal;

namespace {

/// The unit cube with objects floor, ceiling, walls and materials paint (floor, ceiling), metal (walls).
Scene cubeScene() {
    Scene s = unitCube();
    s.path = "cube.obj";
    s.objects = {"floor", "ceiling", "walls", "unused"};
    Material metal;
    metal.name = "metal";
    metal.rho = Rgb::Constant(0.2);
    s.materials[0].name = "paint";
    s.materials.push_back(metal);
    s.patches[1].object = 1;
    for (PatchId i = 2; i < 6; ++i) {
        s.patches[i].object = 2;
        s.patches[i].material = 1;
        s.applyMaterial(i, 1);
    }
    return s;
}

/// Checks that the properties `text` (named p.toml), with bands, are refused with `message`.
void fails(const std::string& text, const std::string& message) {
    Scene t = cubeScene();
    std::vector<std::string> sources;
    BandProperties bands;
    CHECK_THROWS_WITH_AS(applyPropertiesText(text, "p.toml", t, sources, nullptr, &bands), doctest::Contains(message.c_str()), hemirad::Error);
}

}  // namespace

TEST_CASE("Properties: object over material over the default table over the MTL, and a specular value becomes the scene's") {
    Scene s = cubeScene();
    std::vector<std::string> sources;
    const auto surface = applyPropertiesText("[default]\nemissivity = 0.5\n"
                                             "[materials.metal]\nemissivity = 0.1\nspecular = 0.8\n"
                                             "[objects.ceiling]\nemissivity = 0.9\n",
                                             "props.toml", s, sources);
    CHECK(surface[0].emissivity == 0.5);   // floor: [default]
    CHECK(surface[1].emissivity == 0.9);   // ceiling: its object
    CHECK(surface[2].emissivity == 0.1);   // walls: their material
    CHECK(surface[2].specular == 0.8);
    CHECK(s.patches[2].specular == 0.8);   // F will be computed with it
    CHECK(s.patches[0].specular == 0.0);
    REQUIRE(sources.size() == 3);
    CHECK(sources[2].find("[materials.metal]") != std::string::npos);

    Scene fromMtl = cubeScene();
    const auto mtl = applyPropertiesText("", "", fromMtl, sources);
    CHECK(mtl[0].emissivity == doctest::Approx(0.5));  // 1 - Kd 0.5
    CHECK(mtl[2].emissivity == doctest::Approx(0.8));  // 1 - Kd 0.2
    CHECK(sources[0].find("from the MTL") != std::string::npos);
}

TEST_CASE("Properties errors name the file and line: eps + s > 1, unknown names and keys, syntax") {
    Scene s = cubeScene();
    std::vector<std::string> sources;
    CHECK_THROWS_WITH_AS(applyPropertiesText("\n[objects.walls]\nemissivity = 0.7\nspecular = 0.6\n", "p.toml", s, sources),
                         doctest::Contains("p.toml:2: [objects.walls]: emissivity 0.7 + specular 0.6 = 1.3 > 1"), Error);
    // Split over two tables: the sum is checked per patch, naming the object and material.
    CHECK_THROWS_WITH_AS(applyPropertiesText("[materials.metal]\nspecular = 0.6\n[objects.walls]\nemissivity = 0.7\n", "p.toml", s, sources),
                         doctest::Contains("object 'walls' (material 'metal'): emissivity 0.7 + specular 0.6"), Error);
    CHECK_THROWS_WITH_AS(applyPropertiesText("[objects.roof]\nemissivity = 0.7\n", "p.toml", s, sources),
                         doctest::Contains("p.toml:1: [objects.roof] names no object of cube.obj"), Error);
    CHECK_THROWS_WITH_AS(applyPropertiesText("[default]\nemisivity = 0.7\n", "p.toml", s, sources),
                         doctest::Contains("p.toml:2: unknown key 'emisivity'"), Error);
    CHECK_THROWS_WITH_AS(applyPropertiesText("[default]\nemissivity = 1.5\n", "p.toml", s, sources),
                         doctest::Contains("p.toml:2: emissivity 1.5 in [default] is outside [0, 1]"), Error);
    CHECK_THROWS_WITH_AS(applyPropertiesText("[default]\nemissivity = = 0.7\n", "p.toml", s, sources),
                         doctest::Contains("p.toml:2:"), Error);
    CHECK_THROWS_WITH_AS(applyPropertiesText("[default]\nemissivity = \"high\"\n", "p.toml", s, sources),
                         doctest::Contains("p.toml:2: 'emissivity' must be a finite number"), Error);
}

TEST_CASE("Conditions: temperatures in K or C, fluxes, adiabatic, power makes an isothermal node, the environment") {
    const Scene s = cubeScene();
    const Conditions c = readConditionsText("[environment]\ntemperature_C = -20\n"
                                            "[objects.floor]\ntemperature_K = 300\n"
                                            "[objects.ceiling]\npower_W = 25\n"
                                            "[objects.walls]\nadiabatic = true\n",
                                            "bc.toml", s, 1.0);
    REQUIRE(c.environment);
    CHECK(*c.environment == doctest::Approx(253.15));
    CHECK(c.perPatch[0].kind == Condition::Kind::Temperature);
    CHECK(c.perPatch[0].value == 300.0);
    CHECK(c.perPatch[1].kind == Condition::Kind::Isothermal);
    REQUIRE(c.isothermal.size() == 1);
    CHECK(c.isothermal[0].name == "ceiling");
    CHECK(c.isothermal[0].power == 25.0);
    CHECK(c.perPatch[3].kind == Condition::Kind::Flux);
    CHECK(c.perPatch[3].value == 0.0);
    const Conditions d = readConditionsText("[default]\nflux_W_m2 = 10\n[objects.floor]\ntemperature_C = 25\n", "bc.toml", s, 1.0);
    CHECK(d.perPatch[0].value == doctest::Approx(298.15));
    CHECK(d.perPatch[4].kind == Condition::Kind::Flux);
    CHECK(d.perPatch[4].value == 10.0);
    CHECK(!d.environment);
}

TEST_CASE("Solar keys: absorptance and specular by the same layers, the MTL by default, the sun per object or by default") {
    Scene s = cubeScene();
    std::vector<std::string> sources;
    std::vector<SurfaceProperties> solar;
    applyPropertiesText("[materials.metal]\nemissivity = 0.1\nspecular = 0.8\nsolar_absorptance = 0.15\nsolar_specular = 0.7\n"
                        "[objects.ceiling]\nsolar_absorptance = 0.9\n",
                        "props.toml", s, sources, &solar);
    REQUIRE(solar.size() == 6);
    CHECK(solar[0].emissivity == doctest::Approx(0.5));  // floor: 1 - Kd 0.5 - s 0
    CHECK(solar[1].emissivity == 0.9);
    CHECK(solar[2].emissivity == 0.15);
    CHECK(solar[2].specular == 0.7);
    CHECK(s.patches[2].specular == 0.8);  // the IR specular is the scene's
    CHECK_THROWS_WITH_AS(applyPropertiesText("[objects.walls]\nsolar_absorptance = 0.5\nsolar_specular = 0.6\n", "p.toml", s,
                                             sources, &solar),
                         doctest::Contains("p.toml:1: [objects.walls]: solar_absorptance 0.5 + solar_specular 0.6 = 1.1 > 1"),
                         hemirad::Error);
    const Conditions c = readConditionsText("[default]\nadiabatic = true\nsolar_W_m2 = 100\n[objects.floor]\ntemperature_K = 300\n"
                                            "[objects.walls]\nadiabatic = true\nsolar_W_m2 = 1361\n",
                                            "bc.toml", s, 1.0);
    CHECK(c.solarIncident[0] == 100.0);   // the floor's table says no sun: the default's
    CHECK(c.solarIncident[1] == 100.0);
    CHECK(c.solarIncident[2] == 1361.0);
    CHECK_THROWS_WITH_AS(readConditionsText("[default]\nadiabatic = true\nsolar_W_m2 = -5\n", "bc.toml", s, 1.0),
                         doctest::Contains("bc.toml:3: [default]: solar_W_m2 must be >= 0"), hemirad::Error);
}

TEST_CASE("Condition errors name the file and line: no such object, below 0 K, two conditions, none, objects left out") {
    const Scene s = cubeScene();
    auto read = [&](const std::string& text) { return readConditionsText(text, "bc.toml", s, 1.0); };
    CHECK_THROWS_WITH_AS(read("[default]\nadiabatic = true\n[objects.roof]\ntemperature_K = 300\n"),
                         doctest::Contains("bc.toml:3: [objects.roof] names no object with patches in cube.obj"), Error);
    CHECK_THROWS_WITH_AS(read("[default]\nadiabatic = true\n[objects.unused]\ntemperature_K = 300\n"),
                         doctest::Contains("bc.toml:3: [objects.unused] names no object with patches"), Error);
    CHECK_THROWS_WITH_AS(read("[default]\ntemperature_C = -300\n"),
                         doctest::Contains("bc.toml:2: [default]: temperature_C = -300 is below absolute zero"), Error);
    CHECK_THROWS_WITH_AS(read("[environment]\ntemperature_K = -3\n[default]\nadiabatic = true\n"),
                         doctest::Contains("bc.toml:2: [environment]: temperature_K = -3 is below absolute zero"), Error);
    CHECK_THROWS_WITH_AS(read("[default]\ntemperature_K = 300\nflux_W_m2 = 5\n"),
                         doctest::Contains("[default] gives two conditions"), Error);
    CHECK_THROWS_WITH_AS(read("[default]\n[objects.floor]\ntemperature_K = 300\n"),
                         doctest::Contains("bc.toml:1: [default] gives no condition"), Error);
    CHECK_THROWS_WITH_AS(read("[objects.floor]\ntemperature_K = 300\n"),
                         doctest::Contains("no boundary condition for object(s) 'ceiling', 'walls'"), Error);
    CHECK_THROWS_WITH_AS(read("[default]\ntemprature_K = 300\n"), doctest::Contains("bc.toml:2: unknown key 'temprature_K'"), Error);
    CHECK_THROWS_WITH_AS(read("[default]\nadiabatic = false\n"), doctest::Contains("bc.toml:2: [default]: adiabatic must be true"), Error);
}

TEST_CASE("A closed enclosure of fluxes only has no temperatures: said, not solved") {
    const Scene s = cubeScene();
    const double opp = c11(1, 1, 1), adj = c14(1, 1, 1);
    std::vector<std::vector<double>> rows(6, std::vector<double>(6, adj));
    for (int i = 0; i < 6; ++i) rows[i][i] = 0.0, rows[i][i ^ 1] = opp;
    const FormFactors F = denseF(rows);
    ThermalModel m;
    m.surface.assign(6, SurfaceProperties{0.5, 0.0});
    const Conditions c = readConditionsText("[default]\nflux_W_m2 = 10\n", "bc.toml", s, 1.0);
    m.condition = c.perPatch;
    CHECK_THROWS_WITH_AS(solveThermal(s, F, m, SolverOptions{}),
                         doctest::Contains("every surface has a heat-flux or power condition in a closed enclosure"), Error);
    // With a temperature somewhere it is determined.
    m.condition[0] = Condition{Condition::Kind::Temperature, 300.0, 0};
    CHECK(solveThermal(s, F, m, SolverOptions{}).balance <= 1e-9);
    // A flux that asks a surface to absorb more than it receives has no temperature.
    m.condition[3] = Condition{Condition::Kind::Flux, -1e6, 0};
    CHECK_THROWS_WITH_AS(solveThermal(s, F, m, SolverOptions{}), doctest::Contains("would have to absorb more than it receives"), Error);
}

TEST_CASE("Bands in the properties file: limits, a list per entry or one value in every band, and their mistakes") {
    Scene s = cubeScene();
    std::vector<std::string> sources;
    BandProperties bands;
    const auto surface = applyPropertiesText("[bands]\nlimits_um = [4.0]\n[default]\nemissivity = 0.5\n"
                                             "[materials.metal]\nemissivity = [0.05, 0.3]\n",
                                             "props.toml", s, sources, nullptr, &bands);
    REQUIRE(bands.emissivity.size() == 2);
    CHECK(bands.limitsUm == std::vector<double>{4.0});
    CHECK(bands.emissivity[0][0] == 0.5);
    CHECK(bands.emissivity[1][0] == 0.5);
    CHECK(bands.emissivity[0][2] == 0.05);
    CHECK(bands.emissivity[1][2] == 0.3);
    CHECK(surface[0].emissivity == doctest::Approx(0.5));
    // At 300 K almost all emission lies above 4 um: the gray value is close to the second band's.
    CHECK(surface[2].emissivity > 0.29);
    CHECK(surface[2].emissivity < 0.3);
    fails("[default]\nemissivity = [0.1, 0.2]\n", "p.toml:1: [default]: emissivity has 2 values but no [bands] table gives their limits");
    fails("[bands]\nlimits_um = [4.0, 8.0]\n[default]\nemissivity = [0.1, 0.2]\n", "p.toml:3: [default]: emissivity has 2 values for 3 bands");
    fails("[bands]\nlimits_um = [8.0, 4.0]\n", "p.toml:2: [bands]: limits_um must be positive and increasing");
    fails("[bands]\nlimits = [4.0]\n", "p.toml:2: unknown key 'limits' in [bands]");
    fails("[bands]\nlimits_um = [4.0]\n[materials.metal]\nemissivity = [0.1, 1.2]\n", "p.toml:4: emissivity 1.2 in [materials.metal] is outside [0, 1]");
}

TEST_CASE("Specular reflectance per band: a list per entry, the scene's the bands' weighted at the reference temperature, and their mistakes") {
    Scene s = cubeScene();
    std::vector<std::string> sources;
    BandProperties bands;
    // The walls are mirrors at short wavelengths (a polished metal) and dull beyond 4 um.
    applyPropertiesText("[bands]\nlimits_um = [4.0]\nreference_temperature_K = 1000\n[default]\nemissivity = 0.5\n"
                        "[materials.metal]\nemissivity = [0.05, 0.3]\nspecular = [0.9, 0.2]\n",
                        "props.toml", s, sources, nullptr, &bands);
    REQUIRE(bands.specular.size() == 2);
    CHECK(bands.specular[0][2] == 0.9);
    CHECK(bands.specular[1][2] == 0.2);
    CHECK(bands.specular[0][0] == 0.0);  // the floor keeps its one value (the MTL's 0) in both bands
    CHECK(bands.specular[1][0] == 0.0);
    const double f = bandFraction(0.0, 4.0, 1000.0);
    CHECK(s.patches[2].specular == doctest::Approx(0.9 * f + 0.2 * (1.0 - f)).epsilon(1e-14));
    CHECK(s.patches[0].specular == 0.0);
    ThermalModel m;
    takeBandProperties(m, std::move(bands));
    CHECK(m.bandSpecular[0][2] == 0.9);
    CHECK(bandNeedsOwnFormFactors(s, m, 0));
    CHECK(bandNeedsOwnFormFactors(s, m, 1));
    // Equal values are the scene's value exactly (no F of its own for an ulp); without a given
    // emissivity each band's is 1 - mean(Kd) - its own s (the metal's Kd is 0.2).
    Scene t = cubeScene();
    BandProperties same;
    applyPropertiesText("[bands]\nlimits_um = [4.0]\n[materials.metal]\nspecular = [0.3, 0.3]\n[materials.paint]\n"
                        "specular = [0.4, 0.1]\n", "props.toml", t, sources, nullptr, &same);
    CHECK(t.patches[2].specular == 0.3);
    ThermalModel sm;
    takeBandProperties(sm, std::move(same));
    for (std::size_t k = 0; k < 2; ++k) CHECK(sm.bandSpecular[k][2] == t.patches[2].specular);  // the walls' metal
    const double paintKd = cubeScene().materials[0].rho.mean();
    CHECK(sm.bandEmissivity[0][0] == doctest::Approx(1.0 - paintKd - 0.4));
    CHECK(sm.bandEmissivity[1][0] == doctest::Approx(1.0 - paintKd - 0.1));
    CHECK(sm.bandEmissivity[0][2] == doctest::Approx(1.0 - 0.2 - 0.3));
    fails("[default]\nspecular = [0.1, 0.2]\n", "p.toml:1: [default]: specular has 2 values but no [bands] table gives their limits");
    fails("[bands]\nlimits_um = [4.0]\n[default]\nspecular = [0.1, 0.2, 0.3]\n", "p.toml:3: [default]: specular has 3 values for 2 bands");
    fails("[bands]\nlimits_um = [4.0]\n[materials.metal]\nspecular = [0.1, -0.2]\n", "p.toml:4: specular -0.2 in [materials.metal] is outside [0, 1]");
    fails("[bands]\nlimits_um = [4.0]\n[materials.metal]\nemissivity = [0.05, 0.3]\nspecular = [0.9, 0.8]\n",
          "p.toml:3: object 'walls' (material 'metal'): in band 2 emissivity 0.3 + specular 0.8 = 1.1 > 1");
}
