// Sky view factors against closed forms: a ground patch beside a wall (Howell C-14), the same wall
// seen from behind, a mirror wall by images, and the floor and wall of a long street canyon (the
// infinite-canyon formulas, averaged over the patch), with the default flags.
#include "support.hpp"

#include "engine/error.hpp"
#include "environment/sky_view.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

using namespace hemirad;
using namespace hemirad::test;

namespace {

SkyView defaults(const Scene& s) { return skyViewFactors(s, MethodSettings::of(HemisphereOptions{})); }

/// A w x l ground patch (z = 0, facing up, x in [0, w]) and an h x l wall on its edge x = 0 (the
/// plane x = 0, z in [0, h]) facing +x (toward the ground) or -x (its back to it), reflectance s.
Scene groundAndWall(double w, double h, double l, bool facing, double s) {
    SceneBuilder b;
    const std::uint32_t wall = b.material("wall", Rgb::Constant(0.5), Rgb::Zero(), s);
    b.rectangle(2, 0.0, 0, w, 0, l, true);
    b.rectangle(0, 0.0, 0, l, 0, h, facing, wall);  // u = y, v = z
    return b.scene;
}

}  // namespace

TEST_CASE("Sky view: a ground patch beside a wall sees 1 - C14 of sky, whichever way the wall faces") {
    for (const bool facing : {true, false}) {
        CAPTURE(facing);
        const Scene s = groundAndWall(1.0, 2.0, 1.0, facing, 0.0);
        const SkyView sky = defaults(s);
        const double expected = 1.0 - c14(1.0, 2.0, 1.0);  // physics.md: C-14 w=1, h=2, l=1 is 0.232853
        MESSAGE("facing " << facing << ": ground " << sky.direct[0] << ", closed form " << expected);
        CHECK(std::abs(sky.direct[0] - expected) <= 1e-4);
        CHECK(sky.mirrored.empty());
        // The wall sees the ground below its horizon (facing) or nothing of it: half its hemisphere is sky
        // less the ground's part, C14 the other way round.
        const double wallExpected = facing ? 1.0 - c14(2.0, 1.0, 1.0) : 1.0;
        CHECK(std::abs(sky.direct[1] - wallExpected) <= 1e-4);
    }
}

TEST_CASE("Sky view through a mirror wall: s times what the ground sees of the wall, by images") {
    const double s = 0.8;
    const Scene scene = groundAndWall(1.0, 2.0, 1.0, true, s);
    const SkyView sky = defaults(scene);
    const double f = c14(1.0, 2.0, 1.0);
    REQUIRE(sky.mirrored.size() == 2);
    MESSAGE("mirror wall: direct " << sky.direct[0] << " (" << 1 - f << "), through the mirror " << sky.mirrored[0] << " ("
                                   << s * f << ")");
    CHECK(std::abs(sky.direct[0] - (1.0 - f)) <= 1e-4);
    CHECK(std::abs(sky.mirrored[0] - s * f) <= 1e-4);
    CHECK(std::abs(sky.total()[0] - (1.0 - (1.0 - s) * f)) <= 1e-4);
}

TEST_CASE("Sky view in a long street canyon: the floor's and the wall's middle patches as the infinite canyon") {
    // Width W = 10, height H = 10, length 200 W; the middle patches are W long. Averaged over a
    // patch the infinite-canyon formulas integrate in closed form:
    //   floor: (sqrt(W^2 + H^2) - H) / W;   wall: 1/2 - (sqrt(H^2 + W^2) - W) / (2 H).
    const double W = 10, H = 10, L = 200 * W;
    SceneBuilder b;
    b.rectangle(2, 0.0, 0, W, -W / 2, W / 2, true);        // floor, the middle
    b.rectangle(0, 0.0, -W / 2, W / 2, 0, H, true);         // the wall x = 0 facing +x, the middle
    b.rectangle(2, 0.0, 0, W, W / 2, L / 2, true);          // the rest of the floor
    b.rectangle(2, 0.0, 0, W, -L / 2, -W / 2, true);
    b.rectangle(0, 0.0, W / 2, L / 2, 0, H, true);          // the rest of the wall x = 0
    b.rectangle(0, 0.0, -L / 2, -W / 2, 0, H, true);
    b.rectangle(0, W, -L / 2, L / 2, 0, H, false);          // the opposite wall, facing -x
    const SkyView sky = defaults(b.scene);
    const double floor = (std::sqrt(W * W + H * H) - H) / W;
    const double wall = 0.5 - (std::sqrt(H * H + W * W) - W) / (2 * H);
    MESSAGE("canyon: floor " << sky.direct[0] << " (infinite canyon " << floor << "), wall " << sky.direct[1] << " ("
                             << wall << ")");
    CHECK(std::abs(sky.direct[0] - floor) <= 1e-4);
    CHECK(std::abs(sky.direct[1] - wall) <= 1e-4);
}

TEST_CASE("The two-sided scene gives each patch a reversed twin just behind it") {
    const Scene s = groundAndWall(1.0, 2.0, 1.0, true, 0.8);
    const Scene two = twoSidedScene(s, 1e-3);
    REQUIRE(two.size() == 4);
    CHECK(two.patches[2].normal.dot(s.patches[0].normal) == doctest::Approx(-1.0));
    CHECK((two.patches[2].centroid - (s.patches[0].centroid - 1e-3 * s.patches[0].normal)).norm() < 1e-12);
    CHECK(two.patches[1].specular == 0.0);  // mirrors off for the direct factors
    CHECK(two.patches[2].area == doctest::Approx(s.patches[0].area));
}

TEST_CASE("Sky view at the centre of a courtyard: the opening's polygon by Lambert's formula") {
    // A 48-sided courtyard of circumradius 10 and height 10, walls facing in; a small patch (radius
    // 0.05) at the centre of the floor. The sky is the opening, a 48-gon at height 10: from a point,
    // F = (1 / 2 pi) sum over its edges of theta_e (n . unit(r_e x r_e+1)) (Lambert), within the
    // patch's spread (second order in 0.05 / 10) of the patch's average.
    const int sides = 48;
    const double R = 10, H = 10;
    SceneBuilder b;
    b.disk(Vec3(0, 0, 0), 0.05, 16, true);
    std::vector<Vec3> top;
    for (int k = 0; k < sides; ++k) {
        const double a0 = 2 * kPi * k / sides, a1 = 2 * kPi * (k + 1) / sides;
        const Vec3 p0(R * std::cos(a0), R * std::sin(a0), 0), p1(R * std::cos(a1), R * std::sin(a1), 0);
        b.polygon({p0, p0 + Vec3(0, 0, H), p1 + Vec3(0, 0, H), p1});  // facing the centre
        top.push_back(p0 + Vec3(0, 0, H));
    }
    REQUIRE(b.scene.patches[1].normal.dot(-b.scene.patches[1].centroid) > 0);
    double lambert = 0;
    for (int k = 0; k < sides; ++k) {
        const Vec3 r0 = top[k], r1 = top[(k + 1) % sides];
        const double theta = std::acos(std::clamp(r0.normalized().dot(r1.normalized()), -1.0, 1.0));
        lambert += theta * r0.cross(r1).normalized().z();
    }
    lambert = std::abs(lambert) / (2 * kPi);
    const SkyView sky = defaults(b.scene);
    MESSAGE("courtyard centre: " << sky.direct[0] << ", Lambert " << lambert << " (a disk: " << R * R / (R * R + H * H) << ")");
    CHECK(std::abs(sky.direct[0] - lambert) <= 1e-4);
}

TEST_CASE("Sky view factors stored and read back: every digit kept, and a file of other geometry refused with file and line") {
    const auto dir = tempDir("sky-view-csv");
    Scene s = groundAndWall(1.0, 2.0, 1.0, true, 0.0);
    s.objects.push_back("wall, west \"a\"");  // a name that needs quoting
    s.patches[1].object = std::uint32_t(s.objects.size() - 1);
    SkyView sky;
    sky.direct = {0.7671470966, 0.6234};
    sky.mirrored = {0.0, 0.0};
    const std::string path = (dir / "svf.csv").string();
    writeSkyViewCsv(path, s, sky);
    const SkyView back = readSkyViewCsv(path, s);
    CHECK(back.direct == sky.direct);
    CHECK(back.mirrored.empty());  // no mirrors in the scene, none through them
    CHECK(back.method == "read from " + path);

    auto refused = [&](const Scene& scene, const std::string& file, const std::string& expected) {
        try {
            readSkyViewCsv(file, scene);
            FAIL("accepted " << file);
        } catch (const Error& e) {
            MESSAGE(std::string(e.what()));
            CHECK(std::string(e.what()).find(expected) != std::string::npos);
        }
    };
    // The wall moved by 1e-3 (its area unchanged): its centroid tells.
    Scene moved = s;
    for (std::uint32_t k = 0; k < moved.patches[1].cornerCount; ++k) moved.vertices[moved.corners[moved.patches[1].firstCorner + k]].x() += 1e-3;
    moved.updateMeasures();
    refused(moved, path, path + ":3: patch 1's centroid");
    // The wall turned round (its corners reversed): same place and area, the other sky.
    Scene flipped = s;
    const Patch& wall = flipped.patches[1];
    std::reverse(flipped.corners.begin() + wall.firstCorner, flipped.corners.begin() + wall.firstCorner + wall.cornerCount);
    flipped.updateMeasures();
    refused(flipped, path, path + ":3: patch 1 faces");
    // Another object, another patch count, a damaged value, another header.
    Scene renamed = s;
    renamed.objects.back() = "east";
    refused(renamed, path, path + ":3: patch 1 belongs to object 'wall, west \"a\"' here and to 'east'");
    Scene fewer = groundAndWall(1.0, 2.0, 1.0, true, 0.0);
    fewer.patches.pop_back();
    refused(fewer, path, ":3: more rows than the scene's 1 patches");
    std::string text;
    {
        std::ifstream in(path);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::size_t second = text.find('\n') + 1;
    const std::string damaged = text.substr(0, second) + "0,default,1,0.5,x,0,0.5,0.5,0,0,0,1\n";
    refused(s, writeFile(dir / "damaged.csv", damaged), "damaged.csv:2: 'x' is not a number");
    refused(s, writeFile(dir / "short.csv", text.substr(0, text.rfind('\n', text.size() - 2) + 1)), "1 rows for the scene's 2 patches");
    refused(s, writeFile(dir / "other.csv", "patch,object,area,sky_view_factor\n0,default,1,0.5\n"), "other.csv:1: not a sky view factor file");
    refused(s, (dir / "missing.csv").string(), "missing.csv: cannot open");
    std::filesystem::remove_all(dir);
}
