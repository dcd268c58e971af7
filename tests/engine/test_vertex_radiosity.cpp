// Corner radiosity for Gouraud shading: area weighting and the crease angle.
#include "support.hpp"

#include "engine/vertex_radiosity.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

TEST_CASE("Coplanar neighbours share an area-weighted value at their common corners") {
    SceneBuilder b;
    b.scene.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(3, 0, 0), Vec3(3, 1, 0)};
    b.scene.addPatch({0, 1, 2, 3}, 0, 0);  // area 1
    b.scene.addPatch({1, 4, 5, 2}, 0, 0);  // area 2
    const std::vector<Rgb> B = {Rgb::Constant(1.0), Rgb::Constant(4.0)};
    const std::vector<Rgb> c = cornerRadiosity(b.scene, B);
    CHECK(c[0][0] == doctest::Approx(1.0));          // corner (0,0,0): patch 0 only
    CHECK(c[1][0] == doctest::Approx(3.0));          // (1*1 + 2*4) / 3
    CHECK(c[4][0] == doctest::Approx(3.0));          // the same position seen from patch 1
    CHECK(c[5][0] == doctest::Approx(4.0));
}

TEST_CASE("The crease angle keeps light from bleeding around a corner") {
    SceneBuilder b;
    b.rectangle(2, 0, 0, 1, 0, 1, true);   // floor z = 0
    b.rectangle(0, 0, 0, 1, 0, 1, true);   // wall x = 0, sharing the edge x = 0, z = 0
    const std::vector<Rgb> B = {Rgb::Constant(1.0), Rgb::Constant(5.0)};
    for (const Rgb& v : cornerRadiosity(b.scene, B, 45.0)) CHECK((v == 1.0 || v == 5.0).all());
    // With a crease of 90 degrees the two walls blend at the shared edge.
    bool blended = false;
    for (const Rgb& v : cornerRadiosity(b.scene, B, 90.0)) blended |= v[0] == doctest::Approx(3.0);
    CHECK(blended);
}

TEST_CASE("Emission and material edges are creases: a light does not smear into the ceiling around it") {
    // Issue 14, defect 3: the Cornell light averaged with the ceiling polygons around it and showed as
    // a glowing band several times its size; a small emitter got a halo.
    SceneBuilder b;
    b.scene.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(2, 1, 0),
                        Vec3(3, 0, 0), Vec3(3, 1, 0)};
    b.scene.addPatch({0, 1, 2, 3}, 0, 0);  // ceiling
    b.scene.addPatch({1, 4, 5, 2}, 0, 0);  // the light, in the ceiling's plane
    b.scene.addPatch({4, 6, 7, 5}, 0, 0);  // ceiling again, another reflectance
    b.scene.patches[1].emission = Rgb::Constant(100.0);
    b.scene.patches[2].rho = Rgb(0.2, 0.3, 0.4);
    const std::vector<Rgb> B = {Rgb::Constant(1.0), Rgb::Constant(100.0), Rgb::Constant(2.0)};
    const std::vector<Rgb> c = cornerRadiosity(b.scene, B);
    for (std::uint32_t k = 0; k < 4; ++k) {
        CAPTURE(k);
        CHECK((c[b.scene.patches[0].firstCorner + k] == 1.0).all());
        CHECK((c[b.scene.patches[1].firstCorner + k] == 100.0).all());
        CHECK((c[b.scene.patches[2].firstCorner + k] == 2.0).all());
    }
    // Equal materials still blend (the first case above), so subdivided walls stay smooth.
    b.scene.patches[2].rho = b.scene.patches[0].rho;
    b.scene.patches[1].emission = b.scene.patches[0].emission;
    const std::vector<Rgb> blended = cornerRadiosity(b.scene, B);
    CHECK(blended[b.scene.patches[0].firstCorner + 1][0] == doctest::Approx((1.0 + 100.0) / 2.0));
}

TEST_CASE("At a T-junction (neighbours meshed to different sizes) corner values stay within their neighbours' range") {
    // A coarse unit square next to one refined 2 x 2 (the GUI's meshing of a selected object): the
    // refined side's vertex at (1, 0.5) lies on the coarse square's edge but is none of its corners.
    SceneBuilder b;
    b.scene.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(1.5, 0, 0), Vec3(2, 0, 0),
                        Vec3(2, 0.5, 0), Vec3(1.5, 0.5, 0), Vec3(1, 0.5, 0), Vec3(2, 1, 0), Vec3(1.5, 1, 0)};
    b.scene.addPatch({0, 1, 2, 3}, 0, 0);  // coarse, area 1
    b.scene.addPatch({1, 4, 7, 8}, 0, 0);  // fine, area 0.25 each
    b.scene.addPatch({4, 5, 6, 7}, 0, 0);
    b.scene.addPatch({7, 6, 9, 10}, 0, 0);
    b.scene.addPatch({8, 7, 10, 2}, 0, 0);
    const std::vector<Rgb> constant(5, Rgb::Constant(3.0));
    for (const Rgb& v : cornerRadiosity(b.scene, constant)) CHECK((v == 3.0).all());  // no seam in a constant field
    const std::vector<Rgb> B = {Rgb::Constant(1.0), Rgb::Constant(2.0), Rgb::Constant(3.0), Rgb::Constant(4.0),
                                Rgb::Constant(5.0)};
    const std::vector<Rgb> c = cornerRadiosity(b.scene, B);
    for (const Rgb& v : c) {
        CHECK(v.allFinite());
        CHECK(v[0] >= 1.0);
        CHECK(v[0] <= 5.0);
    }
    // The shared corners average both sides; the T-vertex only the fine patches that have it.
    CHECK(c[1][0] == doctest::Approx((1.0 * 1.0 + 0.25 * 2.0) / 1.25));       // (1, 0): coarse + fine 1
    CHECK(c[b.scene.patches[1].firstCorner + 3][0] == doctest::Approx(3.5));  // (1, 0.5): fine 1 and 4
}
