// hemirad-gui's inspector pictures without a window: what a patch sees over its Nusselt disk or on
// its hemicube atlas, kept as radiance and tone-mapped with the exposure of the frame that draws it.
#include "support.hpp"

#include "engine/tone_map.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "rays/ray_scene.hpp"
#include "ui/inspector_picture.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;
using hemirad::ui::InspectorPicture;
using hemirad::ui::makeInspectorPicture;

TEST_CASE("Inspector pictures keep radiance and follow the exposure they are drawn with") {
    // Issue 14, defect 4: the picture was tone-mapped once, with the exposure of the frame that made
    // it, and cached: white after an emission edit, too dark after an undo and in --run --select
    // screenshots (made before the solve's exposure was known).
    const Scene scene = bundledScene("cornell_box.obj");
    const RayScene rays(scene);
    std::vector<Rgb> B(scene.size());
    for (PatchId i = 0; i < scene.size(); ++i) B[i] = scene.patches[i].emission + Rgb::Constant(0.5);
    PatchId floor = 0;
    while (!(scene.patches[floor].normal.y() > 0.99)) ++floor;  // a patch looking up, at the light
    const InspectorPicture disk = makeInspectorPicture(scene, rays, B, floor, Projection::NusseltDisk);
    REQUIRE(disk.width == 192);
    REQUIRE(disk.kind.size() == std::size_t(192 * 192));
    std::size_t hits = 0, outside = 0, brightest = 0;
    for (std::size_t k = 0; k < disk.kind.size(); ++k) {
        hits += disk.kind[k] == InspectorPicture::Pixel::Hit;
        outside += disk.kind[k] == InspectorPicture::Pixel::Outside;
        if (disk.radiance[k][0] > disk.radiance[brightest][0]) brightest = k;
    }
    CHECK(hits > 20000);  // the closed side of the box fills most of the disk
    CHECK(outside == doctest::Approx(192.0 * 192.0 * (1.0 - kPi / 4.0)).epsilon(0.02));
    double lightB = 0.0;
    for (PatchId i = 0; i < scene.size(); ++i) lightB = std::max(lightB, B[i][0]);
    CHECK(disk.radiance[brightest][0] == doctest::Approx(lightB / kPi));  // the light, seen from the floor

    // Drawn with two exposures: each pixel as the view maps that radiance at that exposure.
    for (double exposure : {0.05, 0.8}) {
        CAPTURE(exposure);
        const std::vector<std::uint8_t> rgba = disk.rgba(exposure);
        const auto expected = toSrgb8(disk.radiance[brightest], exposure);
        for (int c = 0; c < 3; ++c) CHECK(rgba[4 * brightest + c] == expected[c]);
    }
    CHECK(disk.rgba(0.05) != disk.rgba(0.8));

    // The hemicube atlas: the back end's layout, with its unused corner white.
    const InspectorPicture atlas = makeInspectorPicture(scene, rays, B, floor, Projection::HemicubeAtlas);
    const HemicubeLayout layout(64);
    CHECK(atlas.width == int(layout.width()));
    CHECK(atlas.height == int(layout.height()));
    std::size_t unused = 0;
    for (const auto k : atlas.kind) unused += k == InspectorPicture::Pixel::Unused;
    CHECK(unused == atlas.kind.size() - 3 * 64 * 64);  // top 64 x 64, four sides 64 x 32
    CHECK(atlas.caption.find("hemicube atlas of patch " + std::to_string(floor)) == 0);
}
