// The GUI's values with units: areas in the scene's unit and in m^2, power in W where it is known;
// counts of patches and objects.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "ui/units.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::ui;
using namespace hemirad::test;

TEST_CASE("GUI units: areas in the scene's unit with m^2 alongside, power in W only when the unit is known") {
    CHECK(formatNumber(3090.0) == "3090");
    CHECK(formatNumber(1.534e5) == "1.534e+05");
    CHECK(formatArea(3090.0, "mm") == "3090 mm^2 (0.00309 m^2)");
    CHECK(formatArea(2.0, "m") == "2 m^2");
    CHECK(formatArea(1.0, "ft") == "1 ft^2 (0.0929 m^2)");
    CHECK(formatArea(3090.0, "") == "3090 (scene units^2)");
    CHECK(lengthUnitLabel("") == "scene units");
    CHECK(lengthUnitLabel("cm") == "cm");
    // 1e6 mm^2 x 1 W/m^2 = 1 W.
    CHECK(formatPower(Rgb(1e6, 2e6, 5e5), "mm") == "1 2 0.5 W");
    CHECK(formatPower(Rgb(1, 2, 3), "") == "1 2 3 W/m^2 x scene units^2");
    CHECK_THROWS_AS(formatArea(1.0, "furlong"), Error);
}

TEST_CASE("GUI counts: objects are those holding patches, and one of a thing is singular (issue 38 #9)") {
    // The loader's "default" object (faces before any `o` line) is empty in the Cornell box: 8 groups.
    CHECK(sceneCounts(bundledScene("cornell_box.obj")) == "20 patches, 8 objects");
    CHECK(sceneCounts(bundledScene("cornell_mirror.obj")).find(", mirrors") != std::string::npos);
    const auto dir = tempDir("units-counts");
    writeFile(dir / "one.mtl", "newmtl white\nKd 0.5 0.5 0.5\n");
    Warnings quiet = quietWarnings();
    const Scene one = loadObj(writeFile(dir / "one.obj", "mtllib one.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl white\nf 1 2 3\n"), quiet);
    CHECK(sceneCounts(one) == "1 patch, 1 object");
    const Scene named = loadObj(writeFile(dir / "named.obj", "mtllib one.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\no plate\nusemtl white\nf 1 2 3\n"), quiet);
    CHECK(sceneCounts(named) == "1 patch, 1 object");
    // The meshing line: the Cornell box meshed whole (every object's edge set, "default" included),
    // then one object of it.
    const Scene box = bundledScene("cornell_box.obj");
    REQUIRE(box.objects.size() == 9);
    CHECK(meshedCounts(box, std::vector<double>(9, 60.0)) == "8 of 8 objects meshed");
    std::vector<double> edges(9, 0.0);
    edges[box.patches.back().object] = 25.0;
    CHECK(meshedCounts(box, edges) == "1 of 8 objects meshed");
    CHECK(meshedCounts(one, {10.0}) == "1 of 1 object meshed");
    CHECK(formatCount(0, "patch", "patches") == "0 patches");
    CHECK(formatCount(2, "object", "objects") == "2 objects");
}
