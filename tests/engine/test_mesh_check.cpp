// The mesh check (engine/mesh_check): one small mesh per defect class, counts and example patches.
#include "support.hpp"

#include "engine/box_grid.hpp"
#include "engine/mesh_check.hpp"

#include <doctest/doctest.h>

#include <limits>
#include <random>
#include <set>

using namespace hemirad;
using namespace hemirad::test;

namespace {

class NoLibraries final : public MaterialSource {
public:
    bool find(const std::string&, std::string&, std::string&) override { return false; }
};

Scene fromObj(const std::string& text, Warnings& warnings) {
    NoLibraries none;
    return parseObj("mesh.obj", text, none, warnings);
}

std::size_t count(const MeshReport& r, MeshIssueKind kind) { return r.issue(kind).count; }

/// Every issue except `except` is absent.
void checkOnly(const MeshReport& r, std::set<MeshIssueKind> except) {
    for (std::size_t k = 0; k < kMeshIssueKinds; ++k) {
        CAPTURE(r.issues[k].key);
        if (!except.count(MeshIssueKind(k))) CHECK(r.issues[k].count == 0);
    }
}

// The unit cube with its ceiling (y = 1) split into three triangles around M = (1, 1, 0.5), a
// vertex inside the top edge of the x = 1 wall (line 12). Faces from line 10; patches 0..7.
const char* kTJunctionCube = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
v 1 1 0.5
f 2 1 5 6
f 5 1 4 8
f 2 6 7 3
f 2 3 4 1
f 6 5 8 7
f 4 3 9
f 4 9 7
f 4 7 8
)";

Scene unitSquare(SceneBuilder& b, double x0, double y0, bool up = true) {
    b.rectangle(2, 0, x0, x0 + 1, y0, y0 + 1, up);
    return b.scene;
}

}  // namespace

TEST_CASE("A conforming closed cube is closed and has no mesh issue") {
    const MeshReport r = checkMesh(unitCube());  // each quad with its own corners: welding joins them
    checkOnly(r, {});
    CHECK(r.vertices == 8);
    CHECK(r.edges == 12);
    CHECK(r.openEdgesRaw == 0);
    CHECK(r.watertight);
    CHECK(r.closed);
    CHECK(r.signedVolume == doctest::Approx(-1.0));
    CHECK_FALSE(r.meaningless);
}

TEST_CASE("A cube facing outward is watertight but not closed") {
    Scene cube = unitCube();
    for (Patch& p : cube.patches) std::reverse(cube.corners.begin() + p.firstCorner, cube.corners.begin() + p.firstCorner + p.cornerCount);
    cube.updateMeasures();
    const MeshReport r = checkMesh(cube);
    checkOnly(r, {});
    CHECK(r.watertight);
    CHECK_FALSE(r.closed);
    CHECK(r.signedVolume == doctest::Approx(1.0));
    CHECK(r.closedReason.find("face out") != std::string::npos);
}

TEST_CASE("A T-junction chain is one T-junction, and the edge it splits is covered: still closed") {
    Warnings warnings = quietWarnings();
    const MeshReport r = checkMesh(fromObj(kTJunctionCube, warnings));
    checkOnly(r, {MeshIssueKind::TJunctions});
    REQUIRE(count(r, MeshIssueKind::TJunctions) == 1);
    const MeshExample& t = r.issue(MeshIssueKind::TJunctions).examples.at(0);
    CHECK(t.patches == std::vector<PatchId>{2, 5});  // the wall's edge holds a triangle's corner
    CHECK(t.lines == std::vector<int>{12, 15});
    REQUIRE(t.points.size() == 1);
    CHECK((t.points[0] - Vec3(1, 1, 0.5)).norm() < 1e-12);
    CHECK(r.openEdgesRaw == 3);  // the wall's top edge and the two triangle edges along it
    CHECK(r.openEdgesCovered == 3);
    CHECK(r.watertight);
    CHECK(r.closed);
}

TEST_CASE("A T-junction whose split edge is not covered leaves open edges") {
    Warnings warnings = quietWarnings();
    std::string text = kTJunctionCube;
    text.replace(text.find("f 4 9 7\n"), 8, "");  // a triangle missing: M-C is no edge any more
    const MeshReport r = checkMesh(fromObj(text, warnings));
    CHECK(count(r, MeshIssueKind::TJunctions) == 1);
    CHECK(count(r, MeshIssueKind::OpenEdges) == 3);  // the wall's top edge, and the hole's two inner edges
    CHECK(r.openEdgesRaw == 4);
    CHECK(r.openEdgesCovered == 1);  // B-M lies along the wall's edge
    CHECK_FALSE(r.closed);
    CHECK(r.closedReason.find("3 open edges, 4 before T-junction covering") != std::string::npos);
}

TEST_CASE("A duplicate patch is counted once as a pair, a reversed duplicate also as back-to-back") {
    Scene cube = unitCube();
    std::vector<std::uint32_t> floor(cube.corners.begin(), cube.corners.begin() + 4);
    cube.addPatch(floor, 0, 0, 99);  // patch 6: the floor again
    MeshReport r = checkMesh(cube);
    REQUIRE(count(r, MeshIssueKind::Duplicates) == 1);
    CHECK(r.issue(MeshIssueKind::Duplicates).examples[0].patches == std::vector<PatchId>{0, 6});
    CHECK(r.issue(MeshIssueKind::Duplicates).examples[0].lines == std::vector<int>{0, 99});
    CHECK(r.duplicatesReversed == 0);
    CHECK(count(r, MeshIssueKind::BackToBack) == 0);
    CHECK(count(r, MeshIssueKind::Overlaps) == 0);
    CHECK(count(r, MeshIssueKind::NonManifold) == 4);  // each floor edge: the floor twice and a wall
    CHECK_FALSE(r.closed);

    std::reverse(floor.begin(), floor.end());
    cube.patches.pop_back();
    cube.corners.resize(cube.corners.size() - 4);
    cube.addPatch(floor, 0, 0, 99);
    r = checkMesh(cube);
    CHECK(count(r, MeshIssueKind::Duplicates) == 1);
    CHECK(r.duplicatesReversed == 1);
    REQUIRE(count(r, MeshIssueKind::BackToBack) == 1);
    CHECK(r.issue(MeshIssueKind::BackToBack).examples[0].patches == std::vector<PatchId>{0, 6});
}

TEST_CASE("Coplanar patches facing the same way and overlapping are counted with the overlap area") {
    SceneBuilder b;
    unitSquare(b, 0, 0);
    unitSquare(b, 1, 0);    // beside patch 0: shares an edge, no overlap
    unitSquare(b, 0.5, 0);  // patch 2 overlaps both by half
    const MeshReport r = checkMesh(b.scene);
    REQUIRE(count(r, MeshIssueKind::Overlaps) == 2);
    const MeshExample& e = r.issue(MeshIssueKind::Overlaps).examples[0];
    CHECK(e.patches == std::vector<PatchId>{0, 2});
    CHECK(e.value == doctest::Approx(0.5));
    CHECK(r.issue(MeshIssueKind::Overlaps).examples[1].patches == std::vector<PatchId>{1, 2});
    CHECK(count(r, MeshIssueKind::Duplicates) == 0);
    CHECK(count(r, MeshIssueKind::BackToBack) == 0);
}

TEST_CASE("Coplanar patches with opposite normals that overlap are back-to-back (a shared party wall)") {
    SceneBuilder b;
    b.rectangle(0, 1, 0, 1, 0, 1, true);       // building A's wall at x = 1, facing +x
    b.rectangle(0, 1, 0.5, 1.5, 0, 1, false);  // building B's wall, facing -x, shifted by half
    b.rectangle(0, 3, 0, 1, 0, 1, false);      // far away: no partner
    const MeshReport r = checkMesh(b.scene);
    REQUIRE(count(r, MeshIssueKind::BackToBack) == 1);
    CHECK(r.issue(MeshIssueKind::BackToBack).examples[0].patches == std::vector<PatchId>{0, 1});
    CHECK(r.issue(MeshIssueKind::BackToBack).examples[0].value == doctest::Approx(0.5));
    CHECK(count(r, MeshIssueKind::Overlaps) == 0);
    CHECK(count(r, MeshIssueKind::Duplicates) == 0);
}

TEST_CASE("A flipped patch in a closed cube disagrees with its four neighbours") {
    Scene cube = unitCube();
    const Patch& wall = cube.patches[3];
    std::reverse(cube.corners.begin() + wall.firstCorner, cube.corners.begin() + wall.firstCorner + wall.cornerCount);
    cube.updateMeasures();
    const MeshReport r = checkMesh(cube);
    checkOnly(r, {MeshIssueKind::Orientation});
    REQUIRE(count(r, MeshIssueKind::Orientation) == 4);
    for (const MeshExample& e : r.issue(MeshIssueKind::Orientation).examples) {
        CHECK(std::count(e.patches.begin(), e.patches.end(), PatchId(3)) == 1);
        REQUIRE(e.points.size() == 2);  // the shared edge, on the wall x = 1
        CHECK(e.points[0].x() == 1.0);
        CHECK(e.points[1].x() == 1.0);
    }
    CHECK_FALSE(r.watertight);
    CHECK_FALSE(r.closed);
}

TEST_CASE("An edge shared by three patches is non-manifold, and a lone quad has four open edges") {
    SceneBuilder b;
    b.polygon({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)});
    b.polygon({Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1)});
    b.polygon({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, -1, -1), Vec3(0, -1, -1)});
    MeshReport r = checkMesh(b.scene);
    REQUIRE(count(r, MeshIssueKind::NonManifold) == 1);
    CHECK(r.issue(MeshIssueKind::NonManifold).examples[0].patches == std::vector<PatchId>{0, 1, 2});
    CHECK(r.issue(MeshIssueKind::NonManifold).examples[0].value == 3.0);

    SceneBuilder lone;
    lone.rectangle(2, 0, 0, 1, 0, 1, true);
    r = checkMesh(lone.scene);
    CHECK(count(r, MeshIssueKind::OpenEdges) == 4);
    CHECK(r.openEdgesRaw == 4);
    CHECK(r.issue(MeshIssueKind::OpenEdges).examples[0].points.size() == 2);
    CHECK_FALSE(r.closed);
}

TEST_CASE("A sliver is a patch whose longest edge exceeds the limit times its minimum width") {
    SceneBuilder b;
    b.polygon({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0.01, 0)});  // longest^2 / (2 area) = 100
    b.rectangle(2, 0, 0, 1, 2, 2.1, true);                          // 1 x 0.1: 10
    MeshReport r = checkMesh(b.scene);
    REQUIRE(count(r, MeshIssueKind::Slivers) == 1);
    CHECK(r.issue(MeshIssueKind::Slivers).examples[0].patches == std::vector<PatchId>{0});
    CHECK(r.issue(MeshIssueKind::Slivers).examples[0].value == doctest::Approx(100.0));
    MeshCheckOptions options;
    options.sliverRatio = 5;
    r = checkMesh(b.scene, options);
    CHECK(count(r, MeshIssueKind::Slivers) == 2);
    CHECK(r.issue(MeshIssueKind::Slivers).examples[1].value == doctest::Approx(10.0));
}

TEST_CASE("Zero-area patches are counted, skip the other checks, and the loader's skipped faces are added") {
    SceneBuilder b;
    b.rectangle(2, 0, 0, 1, 0, 1, true);
    b.polygon({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)});                    // collinear: area 0
    b.polygon({Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0.5, 1e-9, 1)});               // narrower than the tolerance
    MeshReport r = checkMesh(b.scene);
    REQUIRE(count(r, MeshIssueKind::ZeroArea) == 2);
    CHECK(r.issue(MeshIssueKind::ZeroArea).examples[0].patches == std::vector<PatchId>{1});
    CHECK(r.issue(MeshIssueKind::ZeroArea).examples[1].patches == std::vector<PatchId>{2});
    CHECK(count(r, MeshIssueKind::Slivers) == 0);
    CHECK(count(r, MeshIssueKind::OpenEdges) == 4);  // the square's only
    CHECK_FALSE(r.meaningless);

    Warnings warnings = quietWarnings();
    const Scene loaded = fromObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n", warnings);
    CHECK(loaded.size() == 1);
    r = checkMesh(loaded);
    addSkippedZeroArea(r, warnings.count("degenerate patches skipped"), warnings.firstMessage("degenerate patches skipped"));
    CHECK(count(r, MeshIssueKind::ZeroArea) == 1);
    CHECK(r.zeroAreaSkipped == 1);
    CHECK(r.zeroAreaSkippedNote.find("mesh.obj:6:") != std::string::npos);
}

TEST_CASE("A quad with a corner off its Newell plane is non-planar, by its deviation over its longest edge") {
    SceneBuilder b;
    b.polygon({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0.01), Vec3(0, 1, 0)});
    b.rectangle(2, 0, 2, 3, 0, 1, true);
    const MeshReport r = checkMesh(b.scene);
    REQUIRE(count(r, MeshIssueKind::NonPlanar) == 1);
    CHECK(r.issue(MeshIssueKind::NonPlanar).examples[0].patches == std::vector<PatchId>{0});
    CHECK(r.issue(MeshIssueKind::NonPlanar).examples[0].value == doctest::Approx(0.0025).epsilon(0.01));
}

TEST_CASE("F is meaningless without patches, with non-finite coordinates or with every patch of zero area") {
    Scene empty;
    MeshReport r = checkMesh(empty);
    CHECK(r.meaningless);
    CHECK(r.meaninglessReason == "the scene has no patches");

    Scene cube = unitCube();
    cube.vertices[5].y() = std::numeric_limits<double>::quiet_NaN();
    r = checkMesh(cube);
    CHECK(r.meaningless);
    CHECK(r.meaninglessReason.find("non-finite") != std::string::npos);
    CHECK_FALSE(r.closed);

    SceneBuilder b;
    b.polygon({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1e-9, 0)});
    r = checkMesh(b.scene);
    CHECK(r.meaningless);
    CHECK(count(r, MeshIssueKind::ZeroArea) == 1);
    CHECK_FALSE(checkMesh(unitCube()).meaningless);
}

TEST_CASE("Examples stop at the limit while the count goes on") {
    SceneBuilder b;
    for (int k = 0; k < 8; ++k) b.polygon({Vec3(0, k, 0), Vec3(1, k, 0), Vec3(0.5, k + 0.01, 0)});
    const MeshReport r = checkMesh(b.scene);
    CHECK(count(r, MeshIssueKind::Slivers) == 8);
    REQUIRE(r.issue(MeshIssueKind::Slivers).examples.size() == 5);
    CHECK(r.issue(MeshIssueKind::Slivers).examples[4].patches == std::vector<PatchId>{4});
}

TEST_CASE("Overlapping box pairs are found once each, as by testing every pair") {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> place(0.0, 100.0), logSize(-3.0, 1.7);
    std::vector<Box> boxes(600);
    for (Box& box : boxes) {
        box.lo = Vec3(place(random), place(random), place(random));
        box.hi = box.lo + Vec3(std::pow(10.0, logSize(random)), std::pow(10.0, logSize(random)), std::pow(10.0, logSize(random)));
    }
    boxes[1] = boxes[0];  // identical boxes
    boxes[2].lo = boxes[0].hi;  // touching at a corner
    boxes[2].hi = boxes[2].lo + Vec3::Constant(1.0);
    std::set<std::pair<std::uint32_t, std::uint32_t>> expected;
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
        for (std::uint32_t j = i + 1; j < boxes.size(); ++j)
            if (boxes[i].overlaps(boxes[j])) expected.emplace(i, j);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> found;
    forEachOverlappingPair(boxes, [&](std::uint32_t i, std::uint32_t j) { found.emplace_back(i, j); });
    const std::set<std::pair<std::uint32_t, std::uint32_t>> unique(found.begin(), found.end());
    CHECK(found.size() == unique.size());
    CHECK(unique == expected);
    CHECK(expected.count({0, 1}) == 1);
    CHECK(expected.count({0, 2}) == 1);
    CHECK(expected.size() > 100);
}
