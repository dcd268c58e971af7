// Sunlit fractions against exact shadow polygons computed in the test (the convex hull of a box's
// corners projected along the sun's rays), and the convex-difference and hull geometry underneath.
#include "support.hpp"

#include "engine/error.hpp"
#include "environment/solar_position.hpp"
#include "environment/sunlit.hpp"
#include "preprocess/hemisphere/convex_pieces.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// The convex hull (Andrew's monotone chain) of 2D points.
std::vector<Vec2> hull(std::vector<Vec2> p) {
    std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
    std::vector<Vec2> h(2 * p.size());
    std::size_t k = 0;
    auto turn = [](const Vec2& o, const Vec2& a, const Vec2& b) { return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x(); };
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && turn(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && turn(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    h.resize(k - 1);
    return h;
}

/// A 20 x 20 ground (z = 0, facing up) and a closed box [x0, x0 + 2] x [y0, y0 + 3] x [0, 4] on it (no
/// bottom): walls facing out, a top facing up.
Scene groundAndBox(double x0, double y0) {
    SceneBuilder b;
    b.rectangle(2, 0.0, -10, 10, -10, 10, true);
    const double x1 = x0 + 2, y1 = y0 + 3, h = 4;
    b.rectangle(2, h, x0, x1, y0, y1, true);
    b.rectangle(0, x0, y0, y1, 0, h, false);
    b.rectangle(0, x1, y0, y1, 0, h, true);
    b.rectangle(1, y0, 0, h, x0, x1, false);
    b.rectangle(1, y1, 0, h, x0, x1, true);
    return b.scene;
}

}  // namespace

TEST_CASE("Sunlit fraction of a ground patch beside a box: 1 - the box's exact shadow polygon, any sun") {
    const double x0 = -1, y0 = -2;
    const Scene s = groundAndBox(x0, y0);
    for (const Vec3& sun : {Vec3(1, 0.5, 1), Vec3(-0.3, 1, 2), Vec3(0.2, -0.1, 3)}) {
        CAPTURE(sun.transpose());
        const std::vector<double> lit = sunlitFractions(s, sun);
        // The shadow on z = 0: the hull of the box's corners moved along -sun to the ground.
        std::vector<Vec2> shadow;
        for (const double x : {x0, x0 + 2})
            for (const double y : {y0, y0 + 3})
                for (const double z : {0.0, 4.0}) {
                    const Vec3 c(x, y, z);
                    const Vec3 g = c - sun * (z / sun.z());
                    shadow.emplace_back(g.x(), g.y());
                }
        const double expected = 1.0 - polygonArea2d(hull(shadow)) / 400.0;
        MESSAGE("sun " << sun.transpose() << ": ground lit " << lit[0] << ", exact " << expected);
        CHECK(std::abs(lit[0] - expected) <= 1e-12);
        CHECK(lit[1] == doctest::Approx(1.0));  // the top: nothing above it
        // Walls facing the sun are lit whole, the others not at all.
        for (PatchId w = 2; w < 6; ++w) CHECK(lit[w] == (s.patches[w].normal.dot(sun) > 0 ? 1.0 : 0.0));
    }
}

TEST_CASE("Sunlit fraction: a shadow partly off the patch, overlapping shadows counted once, the sun below the horizon") {
    // A 1 x 1 and a 2 x 1 plate above a 2 x 2 receiver at heights 1 and 2, the sun straight up:
    // shadows [0.5, 1.5] x [0, 1] and [1, 3] x [0.5, 1.5]; on [0, 2]^2 they cover 1 and 1 (the second's
    // half beyond x = 2 misses), overlapping by 0.25: 1.75 of 4 is shaded.
    SceneBuilder b;
    b.rectangle(2, 0.0, 0, 2, 0, 2, true);
    b.rectangle(2, 1.0, 0.5, 1.5, 0, 1, false);
    b.rectangle(2, 2.0, 1, 3, 0.5, 1.5, false);
    const std::vector<double> lit = sunlitFractions(b.scene, Vec3(0, 0, 1));
    CHECK(lit[0] == relative(1.0 - 1.75 / 4.0, 1e-12));
    CHECK(lit[1] == 0.0);  // facing down, away from the sun
    const std::vector<double> night = sunlitFractions(b.scene, Vec3(0.3, 0, -1));
    CHECK(night[0] == 0.0);
    const std::vector<double> E = directIrradiance(b.scene, Vec3(0, 0, 2), 800.0, lit);
    CHECK(E[0] == doctest::Approx(800.0 * (1.0 - 1.75 / 4.0)));
    CHECK_THROWS_AS(sunlitFractions(b.scene, Vec3(0, 0, 0)), Error);
}

TEST_CASE("Sunlit fraction of a receiver whose corner leaves its plane by the file's rounding, behind a wall, at a grazing sun: dark") {
    // A unit square on z = 0 (counter-clockwise from above) with its last corner 1e-4 down (a
    // file's rounding), a wall at x = 2 from z = -1 to 1 in two overlapping halves (the second 0.1
    // further) across every y the beam can take, and a sun 1.7 degrees above the horizon towards
    // +x: every line from the receiver to the sun meets the wall (the rays rise at most 0.06
    // before it). The receiver's outline dropped square onto its plane while the prism's sides run
    // along the beam through its corners: a sliver along its rim lay outside both shadows (1/cos =
    // 34 times the corner's depth wide): 8.3e-4 and 1.1e-3 of it read lit for the first two suns.
    SceneBuilder b;
    b.polygon({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, -1e-4)});
    b.rectangle(0, 2.0, -5, 0.6, -1, 1, false);
    b.rectangle(0, 2.1, 0.4, 6, -1, 1, false);
    for (const double along : {0.0, 0.3, -0.4}) {
        const Vec3 sun = Vec3(1, along, 0.03).normalized();
        CAPTURE(sun.transpose());
        const std::vector<double> lit = sunlitFractions(b.scene, sun);
        CHECK(lit[0] <= 1e-12);
    }
}

TEST_CASE("Convex difference: a square less a square across its corner leaves an L of the right area") {
    const std::vector<std::vector<Vec2>> square = {{Vec2(0, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)}};
    const auto rest = subtractConvex(square, {Vec2(1, 1), Vec2(3, 1), Vec2(3, 3), Vec2(1, 3)});
    double area = 0;
    for (const auto& piece : rest) area += polygonArea2d(piece);
    CHECK(area == doctest::Approx(3.0));
    // A shadow sharing only an edge with the piece takes nothing (corners on the line stay).
    const auto touching = subtractConvex(square, {Vec2(0, 0), Vec2(2, 0), Vec2(2, -3), Vec2(0, -3)});
    REQUIRE(touching.size() == 1);
    CHECK(polygonArea2d(touching[0]) == doctest::Approx(4.0));
    // Clockwise shadows count the same; a shadow that misses changes nothing.
    const auto same = subtractConvex(square, {Vec2(1, 3), Vec2(3, 3), Vec2(3, 1), Vec2(1, 1)});
    area = 0;
    for (const auto& piece : same) area += polygonArea2d(piece);
    CHECK(area == doctest::Approx(3.0));
    const auto none = subtractConvex(square, {Vec2(5, 5), Vec2(6, 5), Vec2(6, 6)});
    CHECK(polygonArea2d(none.at(0)) == doctest::Approx(4.0));
}

TEST_CASE("Convex difference: a shadow that repeats a corner (an edge of no length) cuts what it covers, not all") {
    // Clipping a blocker to a receiver's prism can repeat a corner, exactly or within rounding. An
    // edge of no length has no line to split by: taken as one, it left the whole piece clear.
    const std::vector<std::vector<Vec2>> square = {{Vec2(0, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)}};
    for (const double apart : {0.0, 1e-15, 3e-13}) {
        CAPTURE(apart);
        const auto rest = subtractConvex(square, {Vec2(1, 1), Vec2(3, 1), Vec2(3 + apart, 1 + apart), Vec2(3, 3), Vec2(1, 3)});
        double area = 0;
        for (const auto& piece : rest) area += polygonArea2d(piece);
        CHECK(std::abs(area - 3.0) <= 1e-12);
    }
}

TEST_CASE("Convex hull: corners a rounding apart and columns of points (a solid's corners projected once per face) keep every point inside, and its cut to an outline with an edge of rounding length keeps all") {
    // Two sets of projected corners as cornell13k's shadows met them: a block's faces (merged tiles,
    // their corners lifted back from the plane a rounding apart) and a cylinder's two faces with a
    // column of four points at one u. Floating-point turns kept points 1e-13 apart as an edge and
    // bent the chain the wrong way, or took the column's lowest corner for a straight line and
    // dropped it: hulls that left most of the shadow out.
    const std::vector<std::vector<std::array<double, 2>>> sets = {
        {{-660.85181471895589, -2352.3854490582294}, {-498.24028756430602, -1748.5160681424966},
         {-498.24028756430602, -1748.5160681424966}, {-335.38421688742596, -1143.7429435923864},
         {-335.38421688742591, -1143.7429435923864}, {-288.81024582307407, -970.78658974355358},
         {-288.81024582307401, -970.78658974355358}, {-253.86598994339909, -841.02030855059013},
         {-253.86598994339823, -841.02030855058899}, {-226.67946872934229, -740.06210255752671},
         {-226.67946872934161, -740.0621025575258}, {-204.92590775740291, -659.27808958564106},
         {20.071342870492355, 87.218311727284956}, {21.924963901034921, 88.41366513011485},
         {21.924963901035028, 88.413665130114865}, {24.031316409211342, 89.772154823110043},
         {24.031316409211595, 89.772154823110057}, {26.446080470168347, 91.329605440624434},
         {26.446080470168525, 91.329605440624434}, {29.242809008693797, 93.133175594528069},
         {29.242809008694117, 93.133175594528069}, {36.410453097493892, 97.755916063566076},
         {36.410453097493892, 97.755916063566076}, {41.108105900103496, 100.78540951644679}},
        {{602.22466634577427, -0.3979434557775221}, {472.4750422507841, -0.0083163112511783766},
         {-135.36590000000001, -0.0083163112511783766}, {-135.36590000000004, -0.3979434557775221},
         {-135.36590000000001, -19.242285488277787}, {767.77173226309753, -19.242285488277787},
         {602.22466634577381, -0.39794345577780632}, {-135.36590000000001, -0.39794345577780632}}};
    for (const auto& set : sets) {
        std::vector<std::array<double, 2>> points = set, hull;
        convexHull2D(points, hull);
        REQUIRE(hull.size() >= 3);
        double scale = 0.0;
        for (const auto& p : set) scale = std::max({scale, std::abs(p[0]), std::abs(p[1])});
        // Counter-clockwise, every point inside or on it (within 1e-9 of the scale), every corner
        // one of the points.
        for (std::size_t k = 0; k < hull.size(); ++k) {
            const auto& a = hull[k];
            const auto& b = hull[(k + 1) % hull.size()];
            const double length = std::hypot(b[0] - a[0], b[1] - a[1]);
            for (const auto& p : set) {
                const double left = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / length;
                CHECK(left >= -1e-9 * scale);
            }
            double nearest = INFINITY;
            for (const auto& p : set) nearest = std::min(nearest, std::hypot(p[0] - a[0], p[1] - a[1]));
            CHECK(nearest <= 1e-11 * scale);
        }
    }
    // A coordinate that is not finite: no hull, said (the caller casts the faces one by one).
    std::vector<std::array<double, 2>> bad = {{0, 0}, {1, 0}, {NAN, 1}}, hull;
    CHECK_FALSE(convexHull2D(bad, hull));
    CHECK(hull.empty());
    // Clipped to a receiver whose outline has two corners a rounding apart (cut at a plane): the
    // edge between them, its direction rounding, cuts nothing (it cut the square along x + y = 2).
    const std::vector<double> square = {-1, -1, 3, -1, 3, 3, -1, 3};
    const std::vector<double> window = {0, 0, 2, 0, 2 - 1e-13, 1e-13, 2, 2, 0, 2};
    std::vector<double> out, scratch, rest;
    const std::size_t corners = clipToConvex(square.data(), 4, window.data(), 5, out, scratch, rest);
    REQUIRE(corners >= 3);
    CHECK(std::abs(doubleArea(out.data(), corners) - 8.0) <= 1e-9);
}

TEST_CASE("Sunlit fractions with one set-up for many suns: walls in triangles (merged to their rectangles) shade as the box") {
    // The box's faces each split into two triangles along a diagonal, as exporters write them: the
    // shadow set-up merges each pair into its rectangle, and the ground's lit part stays exact.
    const double x0 = -1, y0 = -2;
    const Scene boxes = groundAndBox(x0, y0);
    SceneBuilder b;
    for (PatchId i = 0; i < boxes.size(); ++i) {
        const std::vector<Vec3> c = boxes.polygon(i);
        if (i == 0) {
            b.polygon(c);
            continue;
        }
        b.polygon({c[0], c[1], c[2]});
        b.polygon({c[0], c[2], c[3]});
    }
    const Scene& split = b.scene;
    const BeamShadows shadows(split);
    for (const Vec3& sun : {Vec3(1, 0.5, 1), Vec3(-0.3, 1, 2), Vec3(0.2, -0.1, 3), Vec3(-1, -0.2, 0.1)}) {
        CAPTURE(sun.transpose());
        const std::vector<double> lit = shadows.sunlitFractions(sun);
        const std::vector<double> whole = sunlitFractions(boxes, sun);
        CHECK(std::abs(lit[0] - whole[0]) <= 1e-12);
        for (PatchId i = 1; i < boxes.size(); ++i) {
            CHECK(lit[2 * i - 1] == doctest::Approx(whole[i]).epsilon(1e-12));
            CHECK(lit[2 * i] == doctest::Approx(whole[i]).epsilon(1e-12));
        }
        CHECK(lit == sunlitFractions(split, sun));  // a set-up kept for many suns gives each sun's own
    }
}

TEST_CASE("Sunlit fraction at the scene's edge: a plate over a corner triangle shades it though the corners leave the scene at once") {
    // The tree's search box for a receiver's prism reaches as far as its points travel inside the
    // scene's box. Here every corner of the ground triangle leaves that box at once (by x or by y),
    // yet the points between them rise to the plate 0.3 above: a box from the corners alone was flat
    // and passed over the tree's upper leaf (the plate and three plates high up; the lower leaf is
    // the ground).
    SceneBuilder b;
    b.polygon({Vec3(9, 10, 0), Vec3(10, 9, 0), Vec3(10, 10, 0)});  // the receiver, facing up
    for (const Vec3& c : {Vec3(9.0, 9.0, 0), Vec3(9.4, 9.0, 0), Vec3(9.0, 9.4, 0)})  // more ground, apart
        b.polygon({c, c + Vec3(0.3, 0, 0), c + Vec3(0, 0.3, 0)});
    b.rectangle(2, 0.3, 9.85, 9.95, 9.85, 9.95, false);  // the plate, facing down
    for (const Vec3& c : {Vec3(9.1, 9.1, 5), Vec3(9.4, 9.1, 5), Vec3(9.1, 9.4, 5)})  // high up: shadows far off
        b.rectangle(2, c.z(), c.x(), c.x() + 0.1, c.y(), c.y() + 0.1, false);
    const std::vector<double> lit = sunlitFractions(b.scene, Vec3(1, 1, 1));
    // The plate's shadow, [9.55, 9.65]^2 on the ground, lies inside the triangle (area 1/2).
    CHECK(lit[0] == doctest::Approx(1.0 - 0.01 / 0.5).epsilon(1e-12));
}

TEST_CASE("Solar position (Michalsky 1988) against NREL's SPA example and the equinox noon, within 0.05 degrees") {
    // Reda & Andreas (2004), NREL's SPA report, its example: 2003-10-17 12:30:30 at UTC-7, latitude
    // 39.742476, longitude -105.1786: zenith 50.11162 (elevation 39.88838), azimuth 194.34024 degrees.
    const SolarPosition p = solarPosition("2003-10-17T12:30:30-07:00", 39.742476, -105.1786);
    MESSAGE("SPA example: elevation " << p.elevation << " (39.88838), azimuth " << p.azimuth << " (194.34024)");
    CHECK(std::abs(p.elevation - 39.88838) < 0.05);
    CHECK(std::abs(p.azimuth - 194.34024) < 0.05);
    // Near the March equinox at solar noon on the equator the sun is nearly overhead.
    const SolarPosition q = solarPosition("2020-03-20T12:07:00Z", 0.0, 0.0);
    CHECK(q.elevation > 89.0);
    // The direction in a z-up scene with north +y: azimuth 180 (south) at elevation 45 is (0, -1, 1)/sqrt 2.
    const Vec3 d = sunDirection({45.0, 180.0}, Vec3(0, 0, 1), Vec3(0, 1, 0));
    CHECK((d - Vec3(0, -1, 1).normalized()).norm() < 1e-12);
    const Vec3 e = sunDirection({0.0, 90.0}, Vec3(0, 1, 0), Vec3(0, 0, -1));  // y up, north -z: east is +x
    CHECK((e - Vec3(1, 0, 0)).norm() < 1e-12);
    CHECK_THROWS_WITH_AS(solarPosition("2003-10-17 12:30", 0, 0), doctest::Contains("is not YYYY-MM-DDTHH:MM"), Error);
    CHECK_THROWS_WITH_AS(solarPosition("2100-01-01T00:00", 0, 0), doctest::Contains("outside 1950-2050"), Error);
    CHECK_THROWS_WITH_AS(solarPosition("2003-10-17T12:30+25:00", 0, 0), doctest::Contains("malformed offset"), Error);
    CHECK_THROWS_WITH_AS(solarPosition("2003-10-17T12:30", 95, 0), doctest::Contains("latitude 95"), Error);
}
