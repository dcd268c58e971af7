// Subdivision: regular grids, area conservation, parent cells, shared vertices, kept materials.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "engine/subdivide.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <set>

using namespace hemirad;
using namespace hemirad::test;

TEST_CASE("A quad becomes a regular nu x nv grid that keeps area, normal and its cells") {
    SceneBuilder b;
    const std::uint32_t red = b.material("red", Rgb(.6, .1, .1), Rgb(1, 0, 0));
    b.rectangle(2, 0, 0, 3, 0, 1, true, red);  // 3 x 1 rectangle
    const Scene s = subdivide(b.scene, 0.5);
    REQUIRE(s.size() == 6 * 2);
    REQUIRE(s.parents.size() == 1);
    const Parent& parent = s.parents[0];
    CHECK(parent.kind == GridKind::Quad);
    CHECK(parent.nu == 6);
    CHECK(parent.nv == 2);
    CHECK(parent.patchCount == 12);
    double area = 0;
    for (PatchId i = 0; i < s.size(); ++i) {
        const Patch& p = s.patches[i];
        area += p.area;
        CHECK(p.area == doctest::Approx(0.25));
        CHECK(p.normal.isApprox(Vec3(0, 0, 1)));
        CHECK(p.parent == 0);
        CHECK(i == parent.firstPatch + p.cellJ * parent.nu + p.cellI);
        CHECK((p.rho == Rgb(.6, .1, .1)).all());
        CHECK((p.emission == Rgb(1, 0, 0)).all());
    }
    CHECK(area == doctest::Approx(3.0));
    CHECK(s.vertices.size() == 7 * 3);  // grid vertices shared, not duplicated
}

TEST_CASE("A triangle becomes n^2 triangles indexed by triangleCell") {
    SceneBuilder b;
    b.polygon({Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(0, 3, 0)});
    const Scene s = subdivide(b.scene, 1.5);  // longest edge 4.24 -> n = 3
    REQUIRE(s.parents.size() == 1);
    const Parent& parent = s.parents[0];
    CHECK(parent.kind == GridKind::Triangle);
    REQUIRE(parent.nu == 3);
    REQUIRE(s.size() == 9);
    std::set<std::uint32_t> cells;
    double area = 0;
    for (PatchId i = 0; i < s.size(); ++i) {
        const Patch& p = s.patches[i];
        area += p.area;
        CHECK(p.area == doctest::Approx(0.5));
        CHECK(p.normal.isApprox(Vec3(0, 0, 1)));
        CHECK(p.cellI < 2 * (parent.nu - p.cellJ) - 1);
        cells.insert(triangleCell(parent.nu, p.cellI, p.cellJ));
    }
    CHECK(area == doctest::Approx(4.5));
    CHECK(cells.size() == 9);
    CHECK(*cells.rbegin() == 8);
}

TEST_CASE("Neighbouring quads with equal edge counts share the vertices of their common edge") {
    SceneBuilder b;
    // Two unit squares sharing the edge x = 1, written with opposite traversal of that edge.
    b.scene.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)};
    b.scene.addPatch({0, 1, 2, 3}, 0, 0);
    b.scene.addPatch({1, 4, 5, 2}, 0, 0);
    const Scene s = subdivide(b.scene, 0.3);  // 4 x 4 each
    CHECK(s.size() == 32);
    CHECK(s.vertices.size() == 9 * 5);  // 5 rows of 9 points: the shared column is not duplicated
}

TEST_CASE("Polygons with more than four corners are fanned into triangle grids, small patches stay whole") {
    SceneBuilder b;
    b.disk(Vec3(0, 0, 0), 1.0, 6, true);
    b.rectangle(2, 5, 0, 0.1, 0, 0.1, true);
    const Scene s = subdivide(b.scene, 0.5);
    double area = 0;
    for (const Patch& p : s.patches)
        if (p.centroid.z() == 0) area += p.area;
    CHECK(area == doctest::Approx(b.scene.patches[0].area));
    const Patch& small = s.patches.back();
    CHECK(s.parents[small.parent].kind == GridKind::Single);
    CHECK(s.parents[small.parent].sourcePatch == 1);
    CHECK_THROWS_WITH_AS(subdivide(b.scene, 0.0), doctest::Contains("must be a positive number"), Error);
    CHECK_THROWS_WITH_AS(subdivide(b.scene, 1e-9), doctest::Contains("would need"), Error);
}

TEST_CASE("Subdividing the Cornell box to 25 mm keeps its total area and materials") {
    Warnings w = quietWarnings();
    const Scene s = loadObj(sourcePath("scenes/cornell_box.obj"), w);
    const Scene t = subdivide(s, 25.0);
    CHECK(t.size() > 2000);
    CHECK(t.totalArea() == relative(s.totalArea(), 1e-9));
    double light = 0;
    for (const Patch& p : t.patches)
        if ((p.emission > 0).any()) light += p.area;
    CHECK(light == doctest::Approx(130.0 * 105.0));
    for (const Patch& p : t.patches) {
        for (std::uint32_t k = 0; k < p.cornerCount; ++k)
            CHECK((t.corner(p, (k + 1) % p.cornerCount) - t.corner(p, k)).norm() <= 25.0 + 1e-9);
    }
}

TEST_CASE("Per-object subdivision refines only the chosen objects, and its size is known before it is made") {
    Warnings w = quietWarnings();
    const Scene s = loadObj(sourcePath("scenes/cornell_box.obj"), w);
    REQUIRE(s.objects.size() >= 3);
    std::vector<double> edges(s.objects.size(), 0.0);
    CHECK(subdividedSize(s, edges) == s.size());
    CHECK(subdivide(s, edges).size() == s.size());
    edges[1] = 40.0;
    const Scene t = subdivide(s, edges);
    CHECK(subdividedSize(s, edges) == t.size());
    CHECK(t.size() > s.size());
    CHECK(t.totalArea() == relative(s.totalArea(), 1e-9));
    for (const Patch& p : t.patches) {
        double longest = 0.0;
        for (std::uint32_t k = 0; k < p.cornerCount; ++k)
            longest = std::max(longest, (t.corner(p, (k + 1) % p.cornerCount) - t.corner(p, k)).norm());
        if (p.object == 1) CHECK(longest <= 40.0 + 1e-9);
        else CHECK(t.parents[p.parent].kind == GridKind::Single);
    }
    std::size_t others = 0;
    for (const Patch& p : s.patches) others += p.object != 1;
    std::size_t kept = 0;
    for (const Patch& p : t.patches) kept += p.object != 1 && t.parents[p.parent].kind == GridKind::Single;
    CHECK(kept == others);
    // Every object at once equals the scalar form, patch for patch.
    for (double edge : {25.0, 100.0, 1000.0}) {
        const Scene a = subdivide(s, edge), b = subdivide(s, std::vector<double>(s.objects.size(), edge));
        CHECK(subdividedSize(s, std::vector<double>(s.objects.size(), edge)) == a.size());
        REQUIRE(a.size() == b.size());
        CHECK(a.geometryHash() == b.geometryHash());
    }
    CHECK_THROWS_WITH_AS(subdivide(s, std::vector<double>(1, 10.0)), doctest::Contains("edge lengths for"), Error);
    edges[0] = -1.0;
    CHECK_THROWS_WITH_AS(subdividedSize(s, edges), doctest::Contains("positive number"), Error);
}

TEST_CASE("coveringPatches maps each patch to the patch of the other mesh that holds its centroid") {
    Warnings w = quietWarnings();
    const Scene s = loadObj(sourcePath("scenes/cornell_box.obj"), w);
    const Scene coarse = subdivide(s, 200.0), fine = subdivide(s, 45.0);
    const auto holds = [](const Scene& scene, PatchId i, const Vec3& point) {
        const Patch& p = scene.patches[i];
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const Vec3 a = scene.corner(p, k), b = scene.corner(p, (k + 1) % p.cornerCount);
            if ((b - a).cross(point - a).dot(p.normal) < -1e-9) return false;
        }
        return std::abs((point - p.centroid).dot(p.normal)) < 1e-9;
    };
    const std::vector<PatchId> down = coveringPatches(coarse, fine);
    REQUIRE(down.size() == fine.size());
    std::vector<int> covered(coarse.size(), 0);
    for (PatchId j = 0; j < fine.size(); ++j) {
        CHECK(holds(coarse, down[j], fine.patches[j].centroid));
        CHECK(coarse.patches[down[j]].object == fine.patches[j].object);
        ++covered[down[j]];
    }
    CHECK(std::count(covered.begin(), covered.end(), 0) == 0);  // every coarse patch is refined, none lost
    const std::vector<PatchId> up = coveringPatches(fine, coarse);
    for (PatchId i = 0; i < coarse.size(); ++i) CHECK(holds(fine, up[i], coarse.patches[i].centroid));
    // From the source scene itself.
    const std::vector<PatchId> fromSource = coveringPatches(s, fine);
    for (PatchId j = 0; j < fine.size(); ++j) CHECK(fromSource[j] == fine.parents[fine.patches[j].parent].sourcePatch);
}
