// hemirad-gui's orbit camera without a window: framing from the scene camera's or the open side,
// framing a selection, the standard views.
#include "support.hpp"

#include "ui/orbit_camera.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;
using hemirad::ui::OrbitCamera;

namespace {

/// True when every corner of the scene's bounds lies inside the camera's view cone.
bool fitsInView(const OrbitCamera& camera, const Scene& scene) {
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const Vec3 eye = camera.eye(), forward = (camera.target - eye).normalized();
    const double halfAngle = 0.5 * camera.fovY * kPi / 180.0;
    for (int k = 0; k < 8; ++k) {
        const Vec3 corner((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
        if (std::acos(std::clamp(forward.dot((corner - eye).normalized()), -1.0, 1.0)) > halfAngle) return false;
    }
    return true;
}

}  // namespace

TEST_CASE("Frame scene looks from the scene camera's side, or into an open box through its open side") {
    // Issue 14, defect 8: Frame scene always looked from +z, at the back of the open Cornell box.
    Scene cornell = bundledScene("cornell_box.obj");  // open at z = 0; its camera looks from z < 0
    REQUIRE(cornell.camera.has_value());
    OrbitCamera camera;
    camera.frame(cornell);
    const Vec3 seen = (camera.eye() - camera.target).normalized();
    CHECK(seen.dot((cornell.camera->eye - cornell.camera->target).normalized()) == doctest::Approx(1.0));
    CHECK(fitsInView(camera, cornell));

    cornell.camera.reset();  // no camera: the open side is found from the geometry
    camera.frame(cornell);
    CHECK(camera.eye().z() < 0.0);
    CHECK(camera.eye().y() > camera.target.y());
    CHECK(std::abs(camera.eye().x() - camera.target.x()) < 1e-6 * camera.distance);
    CHECK(fitsInView(camera, cornell));

    // A closed cube has no open side: the default view from the front-right, above.
    const Scene cube = unitCube();
    camera.frame(cube);
    CHECK(camera.eye().z() > camera.target.z());
    CHECK(camera.eye().y() > camera.target.y());
    CHECK(fitsInView(camera, cube));
}

TEST_CASE("Frame selection centres the selected patches, and the standard views look along the axes") {
    const Scene cornell = bundledScene("cornell_box.obj");
    OrbitCamera camera;
    camera.frame(cornell);
    const double sceneDistance = camera.distance;
    const Vec3 direction = (camera.eye() - camera.target).normalized();
    PatchId light = 0;
    while (!(cornell.patches[light].emission > 0.0).any()) ++light;
    camera.frameSelection(cornell, {light});
    CHECK((camera.target - cornell.patches[light].centroid).norm() < 1e-9 * sceneDistance);
    CHECK(camera.distance < 0.5 * sceneDistance);  // the light is small
    CHECK((camera.eye() - camera.target).normalized().dot(direction) == doctest::Approx(1.0));

    camera.lookAlong(cornell, 1, true);  // top
    CHECK(camera.eye().y() > camera.target.y() + 0.99 * camera.distance);
    CHECK(fitsInView(camera, cornell));
    camera.lookAlong(cornell, 0, false);  // from -x
    CHECK(camera.eye().x() < camera.target.x() - 0.99 * camera.distance);
    CHECK(fitsInView(camera, cornell));
}
