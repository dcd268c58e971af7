// The sun reflected by a mirror against its exact reflected footprint, worked out by hand: a
// horizontal mirror under a 45-degree sun sends its beam up at 45 degrees onto a wall; a plate over
// half the mirror halves the beam, a post in the beam's way halves it again, and a receiver facing
// away or behind the mirror gets nothing.
#include "support.hpp"

#include "engine/error.hpp"
#include "environment/reflected_sun.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// The mirror [0, 1]^2 at z = 0 facing up (s = 0.8), and the wall x = -2, y in [-1, 2], z in [0, 5]
/// facing +x: patches 0 and 1.
SceneBuilder mirrorAndWall() {
    SceneBuilder b;
    const std::uint32_t mirror = b.material("mirror", Rgb::Constant(0.1), Rgb::Zero(), 0.8);
    b.rectangle(2, 0.0, 0, 1, 0, 1, true, mirror);
    b.rectangle(0, -2.0, -1, 2, 0, 5, true);
    return b;
}

}  // namespace

TEST_CASE("Reflected sun: a mirror's beam on a wall is its exact footprint, halved by a plate over the mirror and by a post") {
    const Vec3 toSun = Vec3(1, 0, 1);  // 45 degrees from +x: the beam leaves the mirror toward -x, up at 45 degrees
    const double dni = 800, peak = 0.8 * dni * std::sqrt(0.5);  // s DNI cos: the wall's normal +x against (1, 0, -1) / sqrt 2
    {
        // The mirror's points (x, y, 0) reach the wall x = -2 at z = x + 2: the footprint [0, 1] x [2, 3] in y, z.
        const SceneBuilder b = mirrorAndWall();
        const ReflectedSun sun = reflectedSun(b.scene, toSun, dni);
        REQUIRE(sun.spots.size() == 1);
        CHECK(sun.spots[0].mirror == 0);
        CHECK(sun.spots[0].receiver == 1);
        CHECK(sun.spots[0].litArea == relative(1.0, 1e-12));
        CHECK(sun.spots[0].peak == relative(peak, 1e-12));
        CHECK(sun.irradiance[1] == relative(peak * 1.0 / 15.0, 1e-12));
        CHECK(sun.irradiance[0] == 0.0);
        CHECK(sun.mirrorsLit == 1);
    }
    {
        // A plate at z = 1 over x in [1, 1.5] shades the mirror's half x < 0.5 (along the sun's rays),
        // and a post x = -1 (facing +x) over y in [0, 0.5] stands in the beam: the wall keeps the
        // footprint of x in [0.5, 1], y in [0.5, 1] (0.5 x 0.5), and the post's front gets the
        // beam's y < 0.5 half of the lit part where it crosses x = -1 (z = x + 1): 0.5 x 0.5.
        SceneBuilder b = mirrorAndWall();
        b.rectangle(2, 1.0, 1.0, 1.5, 0, 1, true);    // patch 2: the plate
        b.rectangle(0, -1.0, 0, 0.5, 0, 5, true);     // patch 3: the post, 2.5 in area
        const ReflectedSun sun = reflectedSun(b.scene, toSun, dni);
        double wall = 0.0, post = 0.0;
        for (const ReflectedSun::Spot& s : sun.spots) {
            CHECK(s.mirror == 0);
            if (s.receiver == 1) wall = s.litArea;
            if (s.receiver == 3) post = s.litArea;
        }
        CHECK(wall == relative(0.25, 1e-12));
        CHECK(post == relative(0.25, 1e-12));
        CHECK(sun.irradiance[1] == relative(peak * 0.25 / 15.0, 1e-12));
        CHECK(sun.irradiance[3] == relative(peak * 0.25 / 2.5, 1e-12));
        CHECK(sun.irradiance[2] == 0.0);  // the plate faces up, away from where the beam comes from
    }
}

TEST_CASE("Reflected sun: nothing for a receiver facing away, behind the mirror's plane, a mirror facing away, or no mirror") {
    SceneBuilder b = mirrorAndWall();
    b.rectangle(0, -3.0, -1, 2, 0, 5, false);   // patch 2: a wall facing away from the beam (-x)
    b.rectangle(0, -2.5, -1, 2, -6, -1, true);  // patch 3: below the mirror's plane, facing the beam's side
    const ReflectedSun sun = reflectedSun(b.scene, Vec3(1, 0, 1), 800);
    CHECK(sun.irradiance[2] == 0.0);
    CHECK(sun.irradiance[3] == 0.0);
    CHECK(sun.irradiance[1] > 0.0);
    CHECK(reflectedSun(b.scene, Vec3(1, 0, -1), 800).spots.empty());  // the sun behind the mirror
    SceneBuilder ground;
    ground.rectangle(2, 0.0, 0, 1, 0, 1, true);
    const ReflectedSun none = reflectedSun(ground.scene, Vec3(0, 0, 1), 800);
    CHECK(none.spots.empty());
    CHECK(none.mirrorsLit == 0);
    CHECK_THROWS_AS(reflectedSun(b.scene, Vec3::Zero(), 800), Error);
    CHECK_THROWS_AS(reflectedSun(b.scene, Vec3(0, 0, 1), -1), Error);
}

TEST_CASE("hemirad sun with a mirror: a reflected_sun column and --glare's spots, the footprint's figures") {
    const auto dir = tempDir("reflected-sun-cli");
    writeFile(dir / "m.mtl", "newmtl mirror\nKd 0.1 0.1 0.1\nKs 0.8 0.8 0.8\nillum 3\nnewmtl wall\nKd 0.5 0.5 0.5\n");
    // The mirror [0, 1]^2 at z = 0 facing up, the wall x = -2 (y in [-1, 2], z in [0, 5]) facing +x.
    writeFile(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -2 -1 0\nv -2 2 0\nv -2 2 5\nv -2 -1 5\n"
                             "o mirror\nusemtl mirror\nf 1 2 3 4\no wall\nusemtl wall\nf 5 6 7 8\n");
    const std::string base = std::string(HEMIRAD_BINARY) + " sun " + (dir / "m.obj").string() + " --sun-direction 1,0,1 -o " +
                             (dir / "sun.csv").string();
    CommandResult r = runCommand(base + " --dni 800 --glare " + (dir / "glare.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("reflected sun: 1 mirror(s) in the sun reach 1 (mirror, receiver) pair(s)") != std::string::npos);
    const std::string table = readText(dir / "sun.csv");
    CHECK(table.find(",direct_irradiance (W/m^2),reflected_sun (W/m^2)\n") != std::string::npos);
    const std::string glare = readText(dir / "glare.csv");
    REQUIRE(glare.rfind("mirror,mirror_object,receiver,receiver_object,irradiance (W/m^2),peak (W/m^2),lit_area\n0,mirror,1,wall,", 0) == 0);
    double mean = 0, peak = 0, area = 0;
    REQUIRE(std::sscanf(glare.c_str() + glare.find("0,mirror,1,wall,") + 16, "%lf,%lf,%lf", &mean, &peak, &area) == 3);
    CHECK(peak == relative(0.8 * 800 * std::sqrt(0.5), 1e-12));
    CHECK(area == relative(1.0, 1e-12));
    CHECK(mean == relative(peak / 15.0, 1e-12));
    CHECK(runCommand(base + " --glare " + (dir / "g.csv").string() + " 2>&1").status == 2);  // --glare needs --dni
}
