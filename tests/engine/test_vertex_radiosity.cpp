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
