// Convex solids among the blockers: which components are solids, and that leaving out their faces
// turned away from a point changes no visible factor (against every tile as its own blocker).
#include "support.hpp"

#include "preprocess/hemisphere/convex_solids.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"
#include "preprocess/hemisphere/shadow_polygons.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// The face o + a u + b v (a, b in [0, 1]) as tiles x tiles quads facing u x v (or its opposite).
std::vector<PatchId> face(SceneBuilder& b, const Vec3& o, const Vec3& u, const Vec3& v, int tiles, bool reversed = false) {
    std::vector<PatchId> ids;
    for (int i = 0; i < tiles; ++i)
        for (int j = 0; j < tiles; ++j) {
            const auto at = [&](int p, int q) { return Vec3(o + (double(p) / tiles) * u + (double(q) / tiles) * v); };
            std::vector<Vec3> quad = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
            if (reversed) std::swap(quad[1], quad[3]);
            ids.push_back(b.polygon(quad));
        }
    return ids;
}

/// The box [lo, hi] facing out (or in), its faces as tiles x tiles quads; `bottom` false leaves
/// the face z = lo.z out; `topTiles` (when > 0) tiles the top differently (T-junctions along its rim).
std::vector<PatchId> box(SceneBuilder& b, const Vec3& lo, const Vec3& hi, int tiles, bool bottom = true, bool inward = false,
                         int topTiles = 0) {
    const Vec3 d = hi - lo;
    const Vec3 X(d.x(), 0, 0), Y(0, d.y(), 0), Z(0, 0, d.z());
    std::vector<PatchId> ids;
    const auto add = [&](const std::vector<PatchId>& more) { ids.insert(ids.end(), more.begin(), more.end()); };
    add(face(b, Vec3(hi.x(), lo.y(), lo.z()), Y, Z, tiles, inward));
    add(face(b, lo, Z, Y, tiles, inward));
    add(face(b, Vec3(lo.x(), hi.y(), lo.z()), Z, X, tiles, inward));
    add(face(b, lo, X, Z, tiles, inward));
    add(face(b, Vec3(lo.x(), lo.y(), hi.z()), X, Y, topTiles > 0 ? topTiles : tiles, inward));
    if (bottom) add(face(b, lo, Y, X, tiles, inward));
    return ids;
}

struct Built {
    Scene scene;
    PatchGeometry geometry;
    ConvexSolids solids;
    explicit Built(const Scene& s) : scene(s) {
        geometry.build(scene);
        geometry.buildNeighbours(scene);
        solids.build(geometry, std::vector<std::uint8_t>(scene.size(), 1));
    }
    /// The solid all of `ids` belong to (kNone when they are in none or in several).
    std::uint32_t solidOf(const std::vector<PatchId>& ids) const {
        const std::uint32_t first = solids.solidOf(ids.front());
        for (const PatchId j : ids)
            if (solids.solidOf(j) != first) return ConvexSolids::kNone;
        return first;
    }
};

/// Solids of every kind above a tiled floor (6 x 6, facing up), below a tiled ceiling (facing
/// down): a closed box, lidless boxes on the floor and floating (open below), a box with
/// T-junctions along its top, one on the floor with its rim staggered, and a dented bipyramid
/// (no solid). Five solids.
Scene solidsBetweenFloorAndCeiling(std::vector<PatchId>& floor, std::vector<PatchId>& ceiling) {
    SceneBuilder b;
    floor = face(b, Vec3(-1, -1, 0), Vec3(6, 0, 0), Vec3(0, 6, 0), 6);
    ceiling = face(b, Vec3(-1, -1, 4), Vec3(0, 6, 0), Vec3(6, 0, 0), 6);
    box(b, Vec3(0, 0, 1), Vec3(1, 1, 2), 2);                    // closed, floating
    box(b, Vec3(2, 0, 0), Vec3(3, 1, 1.5), 3, false);           // lidless, on the floor
    box(b, Vec3(0.5, 2.5, 2.5), Vec3(1.8, 3.5, 3.5), 2, false); // lidless, floating: open below
    box(b, Vec3(2.5, 2.5, 1), Vec3(3.5, 3.5, 2), 1, true, false, 2);  // T-junctions on its top
    box(b, Vec3(-0.8, 3.8, 0), Vec3(0.2, 4.6, 2.2), 3, false, false, 2);  // on the floor, the rim staggered
    for (int k = 0; k < 4; ++k) {                                // the dented bipyramid
        const std::array<Vec3, 4> ring = {Vec3(4.5, 2, 2), Vec3(4, 2.5, 2), Vec3(3.5, 2, 2), Vec3(4, 1.5, 2)};
        b.polygon({Vec3(4, 2, 1), ring[(k + 1) % 4], ring[k]});
        b.polygon({Vec3(4, 2, 1.6), ring[k], ring[(k + 1) % 4]});
    }
    return b.scene;
}

/// The floor-and-ceiling scene's blockers three ways: with the solids, merged without them, and
/// every tile its own (the reference).
struct ThreeWays {
    std::vector<PatchId> floor, ceiling;
    Scene scene;
    PatchGeometry geometry;
    ShadowPolygons withSolids, merged, tiles;
    ThreeWays() : scene(solidsBetweenFloorAndCeiling(floor, ceiling)) { build(); }
    explicit ThreeWays(const Scene& s) : scene(s) { build(); }
    void build() {
        geometry.build(scene);
        geometry.buildNeighbours(scene);
        const std::vector<std::uint8_t> blocks(scene.size(), 1);
        withSolids.build(geometry, blocks, true);
        merged.build(geometry, blocks, true, false);
        tiles.build(geometry, blocks, false);
    }
};

/// The visible factor from x (normal n, on patch e) to patch r three ways: with the solids, merged
/// without them and every tile its own (the reference), each within 1e-9 of the factor (the cuts
/// merge corners within 1e-9 of a shadow's size: 5e-10 of the factor seen where one shadow was
/// kept whole and the other path cut two). Counts what it compared.
struct VisibleThreeWays {
    const ThreeWays& w;
    ShadowPolygons::Scratch s1, s2, s3;
    std::size_t shadowsWith = 0, shadowsMerged = 0, shadowsTiles = 0, compared = 0, partial = 0, hiddenWhole = 0;
    void operator()(const Vec3& x, const Vec3& n, PatchId e, PatchId r) {
        const PatchShape& t = w.geometry.shapes[r];
        const Vec3* polygon = w.geometry.polygon(r);
        const double whole = pointToPolygonFactor(x, n, polygon, t.count);
        if (!(whole > 0.0)) return;
        const double a = w.withSolids.visibleFactor(x, n, polygon, t.count, e, r, whole, s1);
        const double c = w.tiles.visibleFactor(x, n, polygon, t.count, e, r, whole, s2);
        const double m = w.merged.visibleFactor(x, n, polygon, t.count, e, r, whole, s3);
        shadowsWith += s1.shadows;
        shadowsMerged += s3.shadows;
        shadowsTiles += s2.shadows;
        ++compared;
        partial += c > 0.0 && c < whole;
        hiddenWhole += c == 0.0;
        CHECK(std::abs(a - c) <= 1e-9 * whole);
        CHECK(std::abs(a - m) <= 1e-9 * whole);
    }
};

}  // namespace

TEST_CASE("Convex solids: a closed box, a lidless box on its floor and boxes with T-junctions along their tops are solids, an inward box, a box open on two sides and flat faces are not") {
    SceneBuilder b;
    const std::vector<PatchId> closed = box(b, Vec3(0, 0, 1), Vec3(1, 1, 2), 2);
    const std::vector<PatchId> lidless = box(b, Vec3(2, 0, 0), Vec3(3, 1, 1), 3, false);
    const std::vector<PatchId> floor = face(b, Vec3(-1, -1, 0), Vec3(6, 0, 0), Vec3(0, 6, 0), 2);
    const std::vector<PatchId> inward = box(b, Vec3(0, 3, 0), Vec3(1, 4, 1), 1, true, true);
    // Open at the bottom and on the side x = 4.5 (the box [3.5, 4.5] x [3, 4] x [0, 1] less two
    // faces): its open edges lie in two planes.
    SceneBuilder open = b;
    std::vector<PatchId> twoSides;
    for (const auto& [o, u, v] : {std::array<Vec3, 3>{Vec3(3.5, 3, 0), Vec3(0, 0, 1), Vec3(0, 1, 0)},
                                  std::array<Vec3, 3>{Vec3(3.5, 4, 0), Vec3(0, 0, 1), Vec3(1, 0, 0)},
                                  std::array<Vec3, 3>{Vec3(3.5, 3, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)},
                                  std::array<Vec3, 3>{Vec3(3.5, 3, 1), Vec3(1, 0, 0), Vec3(0, 1, 0)}})
        twoSides.push_back(face(open, o, u, v, 1).front());
    // The top tiled 2 x 2 against sides in one tile (a side's top edge meets two tiles: T-junctions),
    // and 2 x 2 against sides in 3 x 3 (the rim split at halves on one side, thirds on the other).
    const std::vector<PatchId> tjunction = box(b, Vec3(2, 3, 0.5), Vec3(3, 4, 1.5), 1, true, false, 2);
    const std::vector<PatchId> staggered = box(b, Vec3(-3, 0, 0.5), Vec3(-2, 1, 1.5), 3, true, false, 2);
    const Built built(b.scene);
    CHECK(built.solids.size() == 4);
    CHECK(built.solidOf(closed) != ConvexSolids::kNone);
    CHECK(built.solidOf(lidless) != ConvexSolids::kNone);
    CHECK(built.solidOf(closed) != built.solidOf(lidless));
    for (const PatchId j : floor) CHECK(built.solids.solidOf(j) == ConvexSolids::kNone);
    for (const PatchId j : inward) CHECK(built.solids.solidOf(j) == ConvexSolids::kNone);
    CHECK(built.solidOf(tjunction) != ConvexSolids::kNone);
    CHECK(built.solidOf(staggered) != ConvexSolids::kNone);
    CHECK(built.solidOf(staggered) != built.solidOf(tjunction));
    // Which points a solid's far faces may be left out for: outside it, not below its open side.
    std::vector<std::uint32_t> hint;
    const std::uint32_t l = built.solidOf(lidless);
    CHECK(built.solids.entersByFrontFace(l, Vec3(2.5, 0.5, 3), hint));      // above it
    CHECK(built.solids.entersByFrontFace(l, Vec3(1.5, 0.5, 0), hint));      // on the floor beside it
    CHECK_FALSE(built.solids.entersByFrontFace(l, Vec3(2.5, 0.5, 0), hint));  // on the floor under it
    CHECK_FALSE(built.solids.entersByFrontFace(l, Vec3(2.5, 0.5, -1), hint)); // below the open side
    CHECK_FALSE(built.solids.entersByFrontFace(l, Vec3(1.5, 0.5, -1), hint)); // below its plane, beside it

    const Built twoOpen(open.scene);
    for (const PatchId j : twoSides) CHECK(twoOpen.solids.solidOf(j) == ConvexSolids::kNone);
}

TEST_CASE("Convex solids: a district's building (walls in strips of two triangles, a roof of two, T-junctions along the roof and the ground) is a solid open on the ground, two buildings wall to wall are not") {
    // Walls of the footprint [x0, x1] x [y0, y1] up to h, each in `strips` vertical strips of two
    // triangles facing out, and a roof of two; side `cut` (0: y = y0, 2: y = y1) only from z =
    // `from` up (above a neighbour's roof; none of it where from >= h).
    const auto building = [](SceneBuilder& b, double x0, double y0, double x1, double y1, double h, int strips,
                             int cut = -1, double from = 0.0) {
        std::vector<PatchId> ids;
        const std::array<Vec3, 4> corners = {Vec3(x0, y0, 0), Vec3(x1, y0, 0), Vec3(x1, y1, 0), Vec3(x0, y1, 0)};
        for (int side = 0; side < 4; ++side) {
            const Vec3 p = corners[side], q = corners[(side + 1) % 4];
            const double low = side == cut ? from : 0.0;
            if (low >= h) continue;
            for (int k = 0; k < strips; ++k) {
                const Vec3 u = p + (q - p) * (double(k) / strips), v = p + (q - p) * (double(k + 1) / strips);
                const Vec3 du(u.x(), u.y(), low), dv(v.x(), v.y(), low), tu(u.x(), u.y(), h), tv(v.x(), v.y(), h);
                ids.push_back(b.polygon({du, dv, tv}));
                ids.push_back(b.polygon({du, tv, tu}));
            }
        }
        ids.push_back(b.polygon({Vec3(x0, y0, h), Vec3(x1, y0, h), Vec3(x1, y1, h)}));
        ids.push_back(b.polygon({Vec3(x0, y0, h), Vec3(x1, y1, h), Vec3(x0, y1, h)}));
        return ids;
    };
    SceneBuilder b;
    const std::vector<PatchId> alone = building(b, 0, 0, 10, 6, 12, 3);
    // The ground around it: four quads whose inner edges are the footprint's sides whole (the
    // walls' bottoms are split in three: T-junctions), facing up.
    b.polygon({Vec3(-5, -5, 0), Vec3(15, -5, 0), Vec3(10, 0, 0), Vec3(0, 0, 0)});
    b.polygon({Vec3(15, -5, 0), Vec3(15, 11, 0), Vec3(10, 6, 0), Vec3(10, 0, 0)});
    b.polygon({Vec3(15, 11, 0), Vec3(-5, 11, 0), Vec3(0, 6, 0), Vec3(10, 6, 0)});
    b.polygon({Vec3(-5, 11, 0), Vec3(-5, -5, 0), Vec3(0, 0, 0), Vec3(0, 6, 0)});
    // Wall to wall at y = 26: a tall building's wall there stands above the low one's roof (from
    // z = 8), the low one has none there (as district.py writes them).
    const std::vector<PatchId> tall = building(b, 0, 20, 10, 26, 20, 2, 2, 8);
    const std::vector<PatchId> low = building(b, 0, 26, 10, 32, 8, 2, 0, 8);
    const Built built(b.scene);
    CHECK(built.solids.size() == 1);
    CHECK(built.solidOf(alone) != ConvexSolids::kNone);
    std::vector<std::uint32_t> hint;
    CHECK(built.solids.entersByFrontFace(built.solidOf(alone), Vec3(20, 3, 0), hint));       // on the ground
    CHECK_FALSE(built.solids.entersByFrontFace(built.solidOf(alone), Vec3(5, 3, 0), hint));  // under it
    for (const PatchId j : tall) CHECK(built.solids.solidOf(j) == ConvexSolids::kNone);
    for (const PatchId j : low) CHECK(built.solids.solidOf(j) == ConvexSolids::kNone);
}

TEST_CASE("Convex solids: a dented bipyramid, closed and consistently oriented but not convex, is no solid") {
    // Equator square at z = 0, lower apex at z = -1, upper apex pushed down to z = -0.5: the upper
    // faces dent inwards and meet at concave edges, open edges of theirs that lie in no one plane.
    SceneBuilder b;
    const std::array<Vec3, 4> ring = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)};
    const Vec3 low(0, 0, -1), dent(0, 0, -0.5);
    std::vector<PatchId> faces;
    for (int k = 0; k < 4; ++k) {
        faces.push_back(b.polygon({low, ring[(k + 1) % 4], ring[k]}));
        faces.push_back(b.polygon({dent, ring[k], ring[(k + 1) % 4]}));
    }
    const Built dented(b.scene);
    CHECK(dented.solids.size() == 0);
    // The same with the upper apex at z = +0.5: a convex closed octahedron.
    SceneBuilder c;
    for (int k = 0; k < 4; ++k) {
        c.polygon({low, ring[(k + 1) % 4], ring[k]});
        c.polygon({Vec3(0, 0, 0.5), ring[k], ring[(k + 1) % 4]});
    }
    const Built octahedron(c.scene);
    CHECK(octahedron.solids.size() == 1);
    CHECK(octahedron.solids.solidOf(0) != ConvexSolids::kNone);
}

TEST_CASE("Convex solids: leaving out the faces a point sees from behind changes no visible factor, inside a lidless box, below one or beside it") {
    // Points on the floor (under the lidless box standing on it too) and on the ceiling's
    // underside look at every tile of the other. Reference: the same blockers, every tile its
    // own, none left out (merge off).
    const ThreeWays w;
    const std::vector<PatchId>&floor = w.floor, &ceiling = w.ceiling;
    const PatchGeometry& geometry = w.geometry;
    CHECK(w.withSolids.solids() == 5);
    CHECK(w.merged.solids() == 0);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    VisibleThreeWays compare{w};
    for (int k = 0; k < 40; ++k) {
        const PatchId e = floor[std::size_t(unit(random) * floor.size())];
        const Vec3& p0 = geometry.polygon(e)[0];
        const Vec3 x = p0 + Vec3(unit(random), unit(random), 0.0);
        for (const PatchId r : ceiling) compare(x, Vec3(0, 0, 1), e, r);
        const Vec3 y = x + Vec3(0, 0, 4);
        for (const PatchId r : floor) compare(y, Vec3(0, 0, -1), ceiling[0], r);
    }
    // Inside the lidless box on the floor (its floor tile under it): the whole ceiling hidden.
    for (const PatchId r : ceiling) compare(Vec3(2.4, 0.6, 0), Vec3(0, 0, 1), floor[0], r);
    // Below the floating lidless box, looking into it: the tiles above it hidden alike.
    for (const PatchId r : ceiling) compare(Vec3(1.1, 3.0, 0), Vec3(0, 0, 1), floor[0], r);
    // Seen: 2,952 factors, 1,389 in part, 555 hidden whole; 3,714 shadows with the solids, 5,367
    // with every face of theirs, 10,588 with every tile.
    CHECK(compare.compared > 2500);
    CHECK(compare.partial > 1000);
    CHECK(compare.hiddenWhole > 400);
    CHECK(double(compare.shadowsWith) < 0.8 * double(compare.shadowsMerged));
}

TEST_CASE("Convex solids cast one shadow each, the hull of their faces': a 12-sided prism in tiles and a faceted sphere, seen from above, below and beside them, as every tile its own") {
    // A 12-sided prism turned 10 degrees about z (each side 3 x 3 tiles, merged to one polygon:
    // their corners lifted back from the plane differ from the neighbouring sides' by rounding),
    // its top a fan of triangles, standing on a tiled floor; a faceted sphere (16 x 10, triangles)
    // floating beside it; a tiled wall and ceiling. Each solid's faces in a cone cast one shadow,
    // the hull of their projected corners, the same visible parts as face by face. (The hull of
    // corners a rounding apart, which a floating-point chain got wrong on cornell13k, has its own
    // test: test_sunlit.cpp's "Convex hull".)
    SceneBuilder b;
    const std::vector<PatchId> floor = face(b, Vec3(-3, -3, 0), Vec3(6, 0, 0), Vec3(0, 6, 0), 6);
    const std::vector<PatchId> ceiling = face(b, Vec3(-3, -3, 5), Vec3(0, 6, 0), Vec3(6, 0, 0), 6);
    const std::vector<PatchId> wall = face(b, Vec3(3, -3, 0), Vec3(0, 0, 5), Vec3(0, 6, 0), 6);
    const Vec3 base(0.3, -0.9, 0.0), dz(0, 0, 1.7);
    std::vector<Vec3> rim;
    for (int k = 0; k < 12; ++k) {
        const double angle = 0.17453292519943295 + 2 * 3.141592653589793 * k / 12;
        rim.push_back(base + 0.7 * Vec3(std::cos(angle), std::sin(angle), 0.0));
    }
    for (int k = 0; k < 12; ++k) {
        const Vec3& c = rim[std::size_t(k)];
        const Vec3& next = rim[std::size_t((k + 1) % 12)];
        face(b, c, next - c, dz, 3);  // facing out
        b.polygon({base + dz, c + dz, next + dz});
    }
    const Vec3 centre(-1.2, 0.8, 2.6);
    const double radius = 0.7;
    const auto onSphere = [&](int stack, int slice) {
        const double theta = 3.141592653589793 * stack / 10, phi = 2 * 3.141592653589793 * slice / 16;
        return Vec3(centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    };
    const auto outward = [&](std::vector<Vec3> t) {
        if ((t[1] - t[0]).cross(t[2] - t[0]).dot(t[0] - centre) < 0.0) std::swap(t[1], t[2]);
        b.polygon(t);
    };
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 16; ++j) {
            const Vec3 a = onSphere(i, j), c = onSphere(i + 1, j + 1);
            if (i > 0) outward({a, onSphere(i, j + 1), c});
            if (i < 9) outward({a, c, onSphere(i + 1, j)});
        }
    const ThreeWays w(b.scene);
    const PatchGeometry& geometry = w.geometry;
    REQUIRE(w.withSolids.solids() == 2);
    std::mt19937 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    VisibleThreeWays compare{w};
    for (int k = 0; k < 30; ++k) {
        const PatchId e = floor[std::size_t(unit(random) * floor.size())];
        const Vec3 x = geometry.polygon(e)[0] + Vec3(unit(random), unit(random), 0.0);
        for (const PatchId r : ceiling) compare(x, Vec3(0, 0, 1), e, r);
        for (const PatchId r : wall) compare(x, Vec3(0, 0, 1), e, r);
        const Vec3 y = x + Vec3(0, 0, 5);
        for (const PatchId r : floor) compare(y, Vec3(0, 0, -1), ceiling[0], r);
        for (const PatchId r : wall) compare(y, Vec3(0, 0, -1), ceiling[0], r);
    }
    // Seen: 4,320 factors, 737 in part; 1,209 shadows with the solids, 10,163 with their faces.
    CHECK(compare.compared > 4000);
    CHECK(compare.partial > 600);
    CHECK(double(compare.shadowsWith) < 0.3 * double(compare.shadowsMerged));
    // The sun's parallel beams past the same solids: every patch facing 100 suns over the sphere,
    // grazing ones too (their faces then cut to the whole prism, not only the receiver's plane).
    ShadowPolygons::Scratch s1, s2;
    std::normal_distribution<double> gauss;
    std::size_t lit = 0, partlyLit = 0, beamWith = 0, beamTiles = 0;
    for (int k = 0; k < 100; ++k) {
        const Vec3 toSun = Vec3(gauss(random), gauss(random), gauss(random)).normalized();
        for (PatchId r = 0; r < w.scene.size(); ++r) {
            const PatchShape& t = geometry.shapes[r];
            if (!(t.normal.dot(toSun) > 0.0)) continue;
            const double a = w.withSolids.litFraction(geometry.polygon(r), t.count, t.normal, r, toSun, 6e-9, s1);
            const double c = w.tiles.litFraction(geometry.polygon(r), t.count, t.normal, r, toSun, 6e-9, s2);
            beamWith += s1.shadows;
            beamTiles += s2.shadows;
            ++lit;
            partlyLit += c > 0.0 && c < 1.0;
            CHECK(std::abs(a - c) <= 1e-9);
        }
    }
    // Seen: 25,668 fractions, 4,869 in part; 15,118 shadows with the solids, 62,576 with every tile.
    CHECK(lit > 20000);
    CHECK(partlyLit > 3000);
    CHECK(double(beamWith) < 0.4 * double(beamTiles));
}

TEST_CASE("Convex solids: leaving out the faces turned away from the sun changes no sunlit fraction, whatever the sun, through an open side too") {
    // Every patch of the floor-and-ceiling scene lit by 200 suns spread over the sphere (from below
    // too: into the floating lidless box's open side, onto the ceiling's underside). Reference:
    // every tile its own blocker, none left out.
    const ThreeWays w;
    const PatchGeometry& geometry = w.geometry;
    const ShadowPolygons &withSolids = w.withSolids, &tiles = w.tiles, &merged = w.merged;
    REQUIRE(withSolids.solids() == 5);
    ShadowPolygons::Scratch s1, s2, s3;
    std::mt19937 random(11);
    std::normal_distribution<double> gauss;
    const double tolerance = 1e-9 * 6.0;
    std::size_t compared = 0, partial = 0, dark = 0, shadowsWith = 0, shadowsMerged = 0, shadowsTiles = 0;
    for (int k = 0; k < 200; ++k) {
        const Vec3 toSun = Vec3(gauss(random), gauss(random), gauss(random)).normalized();
        for (PatchId r = 0; r < w.scene.size(); ++r) {
            const PatchShape& t = geometry.shapes[r];
            if (!(t.normal.dot(toSun) > 0.0)) continue;
            const double a = withSolids.litFraction(geometry.polygon(r), t.count, t.normal, r, toSun, tolerance, s1);
            const double c = tiles.litFraction(geometry.polygon(r), t.count, t.normal, r, toSun, tolerance, s2);
            const double m = merged.litFraction(geometry.polygon(r), t.count, t.normal, r, toSun, tolerance, s3);
            shadowsWith += s1.shadows;
            shadowsMerged += s3.shadows;
            shadowsTiles += s2.shadows;
            ++compared;
            partial += c > 0.0 && c < 1.0;
            dark += c == 0.0;
            CHECK(std::abs(a - c) <= 1e-9);
            CHECK(std::abs(a - m) <= 1e-9);
        }
    }
    CHECK(compared > 10000);
    CHECK(partial > 1000);
    CHECK(dark > 1000);
    // Seen: 21,836 fractions, 5,703 partly lit, 6,370 dark; shadows 20,710 with the solids,
    // 25,175 with every face of theirs, 60,998 with every tile.
    CHECK(double(shadowsWith) < 0.9 * double(shadowsMerged));
}
