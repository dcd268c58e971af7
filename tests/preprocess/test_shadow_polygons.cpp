// Shadow polygons against closed forms: from a point, the visible part of a rectangle past
// rectangular blockers parallel to it is the rectangle minus the blockers' scaled images, whose
// factors are sums of Howell's B-3 corner terms.
#include "support.hpp"

#include "preprocess/hemisphere/obstruction.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"
#include "preprocess/hemisphere/shadow_polygons.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

struct Setup {
    Scene scene;
    PatchGeometry geometry;
    ShadowPolygons shadows;
    void finish() {
        geometry.build(scene);
        geometry.buildNeighbours(scene);
        shadows.build(geometry, std::vector<std::uint8_t>(scene.size(), 1));
    }
};

}  // namespace

TEST_CASE("Shadow polygons: two overlapping blockers between a point and a rectangle leave the rectangle minus their union") {
    // Receiver [-0.5, 0.5]^2 at z = 1 facing down; from x = (0.2, -0.1, 0) a square [-0.05, 0.05]^2
    // at z = 0.9 and [0, 0.1] x [-0.05, 0.05] at z = 0.8 cast the images x + (y - x) / z of their corners.
    Setup s;
    SceneBuilder b;
    const PatchId emitter = b.rectangle(2, 0, 0.15, 0.25, -0.15, -0.05, true);
    const PatchId receiver = b.rectangle(2, 1, -0.5, 0.5, -0.5, 0.5, false);
    b.rectangle(2, 0.9, -0.05, 0.05, -0.05, 0.05, false);
    b.rectangle(2, 0.8, 0.0, 0.1, -0.05, 0.05, true);  // a back face towards x blocks too
    s.scene = b.scene;
    s.finish();
    const double px = 0.2, py = -0.1;
    auto image = [&](double y, double p, double z) { return p + (y - p) / z; };
    // The two shadows and their overlap, as rectangles [x0, x1] x [y0, y1] on the receiver.
    const double a[4] = {image(-0.05, px, 0.9), image(0.05, px, 0.9), image(-0.05, py, 0.9), image(0.05, py, 0.9)};
    const double c[4] = {image(0.0, px, 0.8), image(0.1, px, 0.8), image(-0.05, py, 0.8), image(0.05, py, 0.8)};
    const double o[4] = {std::max(a[0], c[0]), std::min(a[1], c[1]), std::max(a[2], c[2]), std::min(a[3], c[3])};
    REQUIRE(o[0] < o[1]);
    REQUIRE(o[2] < o[3]);
    const double whole = toRectangle(px, py, -0.5, 0.5, -0.5, 0.5, 1.0);
    const double expected = whole - toRectangle(px, py, a[0], a[1], a[2], a[3], 1.0) -
                            toRectangle(px, py, c[0], c[1], c[2], c[3], 1.0) + toRectangle(px, py, o[0], o[1], o[2], o[3], 1.0);
    const Vec3 x(px, py, 0), n(0, 0, 1);
    ShadowPolygons::Scratch scratch;
    const double lambert = pointToPolygonFactor(x, n, s.geometry.polygon(receiver), 4);
    CHECK(lambert == doctest::Approx(whole).epsilon(1e-12));
    const double visible = s.shadows.visibleFactor(x, n, s.geometry.polygon(receiver), 4, emitter, receiver, lambert, scratch);
    CHECK(scratch.shadows == 2);
    CHECK(visible == doctest::Approx(expected).epsilon(1e-12));
    CHECK(expected < 0.99 * whole);  // the blockers matter (2.4 %)
}

TEST_CASE("Shadow polygons: what lies behind the receiver, behind the point or on the receiver's plane casts no shadow, a cover hides all") {
    SceneBuilder b;
    const PatchId emitter = b.rectangle(2, 0, -0.1, 0.1, -0.1, 0.1, true);
    const PatchId receiver = b.rectangle(2, 1, -0.5, 0.5, -0.5, 0.5, false);
    b.rectangle(2, 1.5, -1, 1, -1, 1, false);     // behind the receiver
    b.rectangle(2, -0.5, -1, 1, -1, 1, true);     // behind the point
    b.rectangle(2, 1, 0.5, 1.5, -0.5, 0.5, false);  // the receiver's neighbour in its plane
    b.rectangle(0, 0.5, -0.5, 0.5, 0.0, 1.0, false);  // a wall along the receiver's edge, outside its cone
    Setup s;
    s.scene = b.scene;
    s.finish();
    const Vec3 x(0.05, 0.02, 0), n(0, 0, 1);
    ShadowPolygons::Scratch scratch;
    const double whole = pointToPolygonFactor(x, n, s.geometry.polygon(receiver), 4);
    CHECK(s.shadows.visibleFactor(x, n, s.geometry.polygon(receiver), 4, emitter, receiver, whole, scratch) == whole);
    CHECK(scratch.shadows == 0);
    // A plate covering the whole cone hides everything.
    SceneBuilder covered = b;
    covered.rectangle(2, 0.5, -2, 2, -2, 2, false);
    s.scene = covered.scene;
    s.finish();
    CHECK(s.shadows.visibleFactor(x, n, s.geometry.polygon(receiver), 4, emitter, receiver, whole, scratch) == 0.0);
}

TEST_CASE("Shadow polygons: a receiver of 64 corners keeps every side of its cone, so a blocker beside it casts nothing") {
    // A 64-gon of radius 1 at z = 1 seen from the origin: at z = 0.5 its cone reaches radius 0.5 at a
    // corner. A fixed array of 64 planes left out the sides through its last two edges, and the cone
    // then reached 0.5049 there: a small plate between 0.5012 and 0.504 towards the last corner cast
    // a shadow outside the receiver, subtracted from its factor (issue 35 #4).
    for (const int corners : {62, 64}) {
        CAPTURE(corners);
        SceneBuilder b;
        const PatchId emitter = b.rectangle(2, 0, -0.01, 0.01, -0.01, 0.01, true);
        const PatchId receiver = b.disk(Vec3(0, 0, 1), 1.0, corners, false);
        const double angle = 2 * kPi / corners;  // corner corners - 1 (the disk winds clockwise)
        const Vec3 u(std::cos(angle), std::sin(angle), 0), v(-std::sin(angle), std::cos(angle), 0), z(0, 0, 0.5);
        b.polygon({z + 0.5012 * u - 0.0015 * v, z + 0.504 * u - 0.0015 * v, z + 0.504 * u + 0.0015 * v,
                   z + 0.5012 * u + 0.0015 * v});
        Setup s;
        s.scene = b.scene;
        s.finish();
        const Vec3 x(0, 0, 0), n(0, 0, 1);
        ShadowPolygons::Scratch scratch;
        const Vec3* polygon = s.geometry.polygon(receiver);
        const double whole = pointToPolygonFactor(x, n, polygon, std::size_t(corners));
        CHECK(s.shadows.visibleFactor(x, n, polygon, std::size_t(corners), emitter, receiver, whole, scratch) == whole);
        CHECK(scratch.shadows == 0);
    }
}

TEST_CASE("Shadow polygons: a partition from the emitter's edge to the receiver's middle hides exactly the far half") {
    // Emitter [0, 1]^2 at z = 0, receiver [0, 2] x [0, 1] at z = 1, a wall x = 1 between them: from
    // every point of the emitter the receiver's part x > 1 is hidden, whatever the point.
    SceneBuilder b;
    const PatchId emitter = b.rectangle(2, 0, 0, 1, 0, 1, true);
    const PatchId receiver = b.rectangle(2, 1, 0, 2, 0, 1, false);
    b.rectangle(0, 1, 0, 1, 0, 1, false);
    Setup s;
    s.scene = b.scene;
    s.finish();
    ShadowPolygons::Scratch scratch;
    for (const double px : {0.01, 0.5, 0.999})
        for (const double py : {0.02, 0.7}) {
            CAPTURE(px);
            CAPTURE(py);
            const Vec3 x(px, py, 0), n(0, 0, 1);
            const double whole = pointToPolygonFactor(x, n, s.geometry.polygon(receiver), 4);
            const double visible =
                s.shadows.visibleFactor(x, n, s.geometry.polygon(receiver), 4, emitter, receiver, whole, scratch);
            CHECK(visible == doctest::Approx(toRectangle(px, py, 0, 1, 0, 1, 1)).epsilon(1e-9));
        }
}

TEST_CASE("Shadow polygons: coplanar tiles whose union is convex block as one polygon, an L of tiles stays tiles, same shadows") {
    // The first test's blockers, the square at z = 0.9 as 2 x 2 tiles; then as an L of three tiles
    // (the fourth quarter open), whose shadow is the square's minus that quarter's.
    const double px = 0.2, py = -0.1;
    const Vec3 x(px, py, 0), n(0, 0, 1);
    auto make = [&](bool fourth, Setup& s, PatchId& emitter, PatchId& receiver) {
        SceneBuilder b;
        emitter = b.rectangle(2, 0, 0.15, 0.25, -0.15, -0.05, true);
        receiver = b.rectangle(2, 1, -0.5, 0.5, -0.5, 0.5, false);
        b.rectangle(2, 0.9, -0.05, 0.0, -0.05, 0.0, false);
        b.rectangle(2, 0.9, 0.0, 0.05, -0.05, 0.0, false);
        b.rectangle(2, 0.9, -0.05, 0.0, 0.0, 0.05, false);
        if (fourth) b.rectangle(2, 0.9, 0.0, 0.05, 0.0, 0.05, false);
        b.rectangle(2, 0.8, 0.0, 0.1, -0.05, 0.05, true);
        s.scene = b.scene;
        s.finish();
    };
    auto image = [&](double y, double p, double z) { return p + (y - p) / z; };
    const double whole = toRectangle(px, py, -0.5, 0.5, -0.5, 0.5, 1.0);
    const double c[4] = {image(0.0, px, 0.8), image(0.1, px, 0.8), image(-0.05, py, 0.8), image(0.05, py, 0.8)};
    // Hidden part of the receiver: union of the tiles' shadow T and the other blocker's C, by
    // inclusion-exclusion over rectangles.
    auto hidden = [&](const double t[4]) {
        const double o[4] = {std::max(t[0], c[0]), std::min(t[1], c[1]), std::max(t[2], c[2]), std::min(t[3], c[3])};
        const double overlap = o[0] < o[1] && o[2] < o[3] ? toRectangle(px, py, o[0], o[1], o[2], o[3], 1.0) : 0.0;
        return toRectangle(px, py, t[0], t[1], t[2], t[3], 1.0) + toRectangle(px, py, c[0], c[1], c[2], c[3], 1.0) - overlap;
    };
    const double square[4] = {image(-0.05, px, 0.9), image(0.05, px, 0.9), image(-0.05, py, 0.9), image(0.05, py, 0.9)};
    const double quarter[4] = {image(0.0, px, 0.9), image(0.05, px, 0.9), image(0.0, py, 0.9), image(0.05, py, 0.9)};
    ShadowPolygons::Scratch scratch;
    {
        Setup s;
        PatchId e, r;
        make(true, s, e, r);
        CHECK(s.shadows.size() == 4);  // the four tiles merged; the other blocker, the emitter, the receiver
        const double visible = s.shadows.visibleFactor(x, n, s.geometry.polygon(r), 4, e, r, whole, scratch);
        CHECK(scratch.shadows == 2);
        CHECK(visible == doctest::Approx(whole - hidden(square)).epsilon(1e-12));
    }
    {
        Setup s;
        PatchId e, r;
        make(false, s, e, r);
        CHECK(s.shadows.size() == 6);  // the L is not convex: three tiles; the other blocker, the emitter, the receiver
        const double visible = s.shadows.visibleFactor(x, n, s.geometry.polygon(r), 4, e, r, whole, scratch);
        // The L hides the square's shadow but the quarter's part outside C's.
        const double o[4] = {std::max(quarter[0], c[0]), std::min(quarter[1], c[1]), std::max(quarter[2], c[2]),
                             std::min(quarter[3], c[3])};
        const double quarterOutsideC = toRectangle(px, py, quarter[0], quarter[1], quarter[2], quarter[3], 1.0) -
                                       (o[0] < o[1] && o[2] < o[3] ? toRectangle(px, py, o[0], o[1], o[2], o[3], 1.0) : 0.0);
        CHECK(visible == doctest::Approx(whole - hidden(square) + quarterOutsideC).epsilon(1e-12));
    }
}
