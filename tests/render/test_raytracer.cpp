// Rendering: a flat patch of known radiosity gives the expected pixel radiance L = B / pi and sRGB
// value; what the camera does not see is black; a mirror shows s times what it reflects.
#include "support.hpp"

#include "engine/tone_map.hpp"
#include "rays/ray_scene.hpp"
#include "render/raytracer.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

RenderOptions frontCamera(int size) {
    RenderOptions o;
    o.width = o.height = size;
    o.samplesPerPixel = 1;
    o.camera.eye = Vec3(0, 0, 3);
    o.camera.target = Vec3(0, 0, 0);
    o.camera.up = Vec3(0, 1, 0);
    o.camera.fovY = 40.0;  // half-height at the patch: 3 tan 20 deg = 1.09 > 1, so image corners miss it
    return o;
}

}  // namespace

TEST_CASE("A flat patch of known B renders as L = B / pi, the background black, and tone maps to the sRGB value") {
    SceneBuilder b;
    b.rectangle(2, 0, -1, 1, -1, 1, true);  // z = 0, facing the camera at z = 3
    const Scene& s = b.scene;
    const std::vector<Rgb> B = {Rgb(kPi, 2 * kPi, 0.5 * kPi)};
    const std::vector<Rgb> corner(s.corners.size(), B[0]);  // Gouraud with equal corners = flat
    const RayScene rays(s);
    for (bool flat : {true, false}) {
        CAPTURE(flat);
        RenderOptions o = frontCamera(33);
        o.flat = flat;
        const RadianceImage image = renderRadiance(s, rays, B, corner, o);
        REQUIRE(image.pixels.size() == 33u * 33u);
        const Rgb centre = image.pixels[16 * 33 + 16];
        CHECK(centre[0] == doctest::Approx(1.0).epsilon(1e-9));
        CHECK(centre[1] == doctest::Approx(2.0).epsilon(1e-9));
        CHECK(centre[2] == doctest::Approx(0.5).epsilon(1e-9));
        CHECK((image.pixels[0].array() == 0.0).all());  // the corner ray passes the patch
        double scale = 0;
        const std::vector<std::uint8_t> rgb = toneMap(image, 0.5, scale);
        CHECK(scale == 0.5);
        const std::size_t k = 3 * (16 * 33 + 16);
        // 0.5, 1.0 and 0.25 through the sRGB curve.
        CHECK(int(rgb[k]) == 188);
        CHECK(int(rgb[k + 1]) == 255);
        CHECK(int(rgb[k + 2]) == 137);
    }
}

TEST_CASE("Seen from behind a patch is black, and a mirror shows s times the radiance it reflects") {
    SceneBuilder b;
    b.rectangle(2, 0, -1, 1, -1, 1, false);  // facing away from the camera (normal -z)
    const Scene back = b.scene;
    const RayScene backRays(back);
    const std::vector<Rgb> B = {Rgb::Constant(kPi)};
    const RadianceImage dark = renderRadiance(back, backRays, B, std::vector<Rgb>(back.corners.size(), B[0]), frontCamera(9));
    CHECK((dark.pixels[4 * 9 + 4].array() == 0.0).all());

    // A mirror at z = 0 facing +z and, behind the camera at z = 6, a large patch facing -z with
    // B = pi: the centre ray reflects straight back onto it, so L = 0 (mirror's own B) + 0.8 x 1.
    SceneBuilder m;
    const std::uint32_t glass = m.material("mirror", Rgb::Zero(), Rgb::Zero(), 0.8);
    m.rectangle(2, 0, -1, 1, -1, 1, true, glass);
    m.rectangle(2, 6, -10, 10, -10, 10, false);
    const RayScene mirrorRays(m.scene);
    const std::vector<Rgb> Bm = {Rgb::Zero(), Rgb::Constant(kPi)};
    std::vector<Rgb> corner(m.scene.corners.size(), Rgb::Zero());
    for (std::uint32_t k = 0; k < m.scene.patches[1].cornerCount; ++k) corner[m.scene.patches[1].firstCorner + k] = Bm[1];
    const RadianceImage image = renderRadiance(m.scene, mirrorRays, Bm, corner, frontCamera(9));
    CHECK(image.pixels[4 * 9 + 4][0] == doctest::Approx(0.8).epsilon(1e-9));
}
