// STL loading (binary and ASCII), the loader chosen by extension, and materials by object name.
#include "stl_files.hpp"
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/scene_loader.hpp"
#include "engine/stl_loader.hpp"

#include <doctest/doctest.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// The unit cube as 12 triangles, facing inward, normals as computed.
std::vector<StlTriangle> cubeTriangles() { return stlTriangles(unitCube()); }

/// Loads `bytes` written to `dir/name` through loadScene (the loader chosen by extension).
Scene loadBytes(const std::string& name, const std::string& bytes, Warnings& warnings,
                const std::string& materials = "", const std::string& materialFile = "m.mtl") {
    const auto dir = tempDir("stl");
    SceneLoadOptions options;
    if (!materials.empty()) options.materials = writeFile(dir / materialFile, materials);
    return loadScene(writeFile(dir / name, bytes), warnings, options);
}

/// Warnings whose printed lines are kept.
struct Printed {
    std::vector<std::string> lines;
    Warnings warnings{[this](const std::string& m) { lines.push_back(m); }};
    bool contains(const std::string& text) const {
        for (const std::string& line : lines)
            if (line.find(text) != std::string::npos) return true;
        return false;
    }
};

/// Every patch edge (as a pair of vertex ids) with the number of patches that have it.
std::map<std::pair<std::uint32_t, std::uint32_t>, int> edgeUses(const Scene& s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const Patch& p : s.patches)
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            std::uint32_t a = s.corners[p.firstCorner + k], b = s.corners[p.firstCorner + (k + 1) % p.cornerCount];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    return uses;
}

const double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

// --- Round trips and vertex merging ---------------------------------------------------------------

TEST_CASE("STL: a binary file gives one patch per triangle, positions and vertex order as written") {
    Warnings w = quietWarnings();
    const std::vector<StlTriangle> written = cubeTriangles();
    const Scene s = loadBytes("cube.stl", binaryStl(written), w);
    REQUIRE(s.size() == 12);
    for (PatchId i = 0; i < s.size(); ++i) {
        CAPTURE(i);
        REQUIRE(s.patches[i].cornerCount == 3);
        for (std::uint32_t k = 0; k < 3; ++k) CHECK(s.corner(s.patches[i], k) == written[i].vertices[k]);
        CHECK(s.patches[i].normal.isApprox(written[i].normal));
        CHECK(s.patches[i].area == doctest::Approx(0.5));
        CHECK(s.patches[i].object == 0);
        CHECK(s.patches[i].sourceLine == 0);
        CHECK((s.patches[i].rho == Rgb::Constant(0.5)).all());
    }
    CHECK(s.objects == std::vector<std::string>{"cube"});
    CHECK(s.unit.empty());
    CHECK(s.totalArea() == doctest::Approx(6.0));
    CHECK(w.count("objects without a material") == 1);  // STL has no materials: said once
}

TEST_CASE("STL: an ASCII file keeps every double bit for bit, and each solid is an object with its lines") {
    Warnings w = quietWarnings();
    // Coordinates no float can hold: ASCII is read as doubles.
    const Vec3 a(0.1, 0.2, 0.3), b(1.0 / 3.0, 0.2, 0.3), c(0.1, 2.0 / 3.0, 0.3), d(0.1, 0.2, 1e-7);
    const StlSolid first{"base plate", {{Vec3(0, 0, 1), {a, b, c}, 0}}};
    const StlSolid second{"fin", {{Vec3::Zero(), {a, c, d}, 0}, {Vec3::Zero(), {a, d, b}, 0}}};
    const Scene s = loadBytes("parts.STL", asciiStl({first, second}), w);
    REQUIRE(s.size() == 3);
    CHECK(s.objects == std::vector<std::string>{"base plate", "fin"});
    CHECK(s.patches[0].object == 0);
    CHECK(s.patches[1].object == 1);
    CHECK(s.patches[2].object == 1);
    CHECK(s.corner(s.patches[0], 1) == b);
    CHECK(s.corner(s.patches[1], 2) == d);
    CHECK(s.vertices.size() == 4);  // a and c are shared by the solids, a, b, d within the fin
    CHECK(s.patches[0].sourceLine == 2);
    CHECK(s.patches[1].sourceLine == 11);
    CHECK(s.patches[2].sourceLine == 18);
    CHECK(s.unit.empty());
}

TEST_CASE("STL: a closed cube of 12 triangles has 8 vertices, so every edge is shared by two patches") {
    Warnings w = quietWarnings();
    for (const bool binary : {true, false}) {
        CAPTURE(binary);
        std::vector<StlTriangle> triangles = cubeTriangles();
        // -0 and +0 are one coordinate: an exporter may write either for the same corner.
        for (StlTriangle& t : triangles)
            if (t.vertices[0].x() == 0.0) t.vertices[0].x() = -0.0;
        const Scene s = binary ? loadBytes("cube.stl", binaryStl(triangles), w)
                               : loadBytes("cube.stl", asciiStl({{"cube", triangles}}), w);
        REQUIRE(s.size() == 12);
        CHECK(s.vertices.size() == 8);
        for (const Vec3& v : s.vertices) CHECK_FALSE(std::signbit(v.x()));
        const auto uses = edgeUses(s);
        CHECK(uses.size() == 18);  // 12 cube edges + 6 face diagonals
        for (const auto& [edge, n] : uses) CHECK(n == 2);
    }
}

TEST_CASE("STL: vertices are merged only when bitwise equal, never by a tolerance") {
    Warnings w = quietWarnings();
    std::vector<StlTriangle> triangles = cubeTriangles();
    // One corner one ulp off in one triangle: a distinct vertex, an edge no longer shared.
    triangles[5].vertices[1].y() = std::nextafter(triangles[5].vertices[1].y(), 2.0);
    const Scene s = loadBytes("cube.stl", asciiStl({{"cube", triangles}}), w);
    CHECK(s.vertices.size() == 9);
}

TEST_CASE("STL: a binary file whose header starts with 'solid' is read as binary (the size decides)") {
    Warnings w = quietWarnings();
    const Scene s = loadBytes("solid.stl", binaryStl(cubeTriangles(), "solid cube exported by a CAD program"), w);
    CHECK(s.size() == 12);
    CHECK(s.objects == std::vector<std::string>{"solid"});
}

TEST_CASE("STL: unnamed ASCII solids are named after the file, numbered when there are several") {
    Warnings w = quietWarnings();
    const std::vector<StlTriangle> t = cubeTriangles();
    const Scene one = loadBytes("part.stl", asciiStl({{"", {t[0], t[1]}}}), w);
    CHECK(one.objects == std::vector<std::string>{"part"});
    const Scene three = loadBytes("part.stl", asciiStl({{"", {t[0]}}, {"lid", {t[1]}}, {"", {t[2]}}}), w);
    CHECK(three.objects == std::vector<std::string>{"part_1", "lid", "part_2"});
    CHECK(three.patches[2].object == 2);
}

TEST_CASE("STL: uppercase keywords, CRLF and blank lines are accepted, and solids of one name are one object") {
    Warnings w = quietWarnings();
    const std::vector<StlTriangle> t = cubeTriangles();
    std::string text = asciiStl({{"wall", {t[0]}}, {"wall", {t[1]}}});
    std::string crlf;
    for (char ch : text) crlf += ch == '\n' ? std::string("\r\n\r\n") : std::string(1, ch);
    for (const char* word : {"facet", "normal", "outer", "loop", "vertex", "endloop", "endfacet"})
        for (std::size_t at = crlf.find(word); at != std::string::npos; at = crlf.find(word, at + 1))
            for (std::size_t k = 0; k < std::strlen(word); ++k) crlf[at + k] = char(std::toupper(crlf[at + k]));
    const Scene s = loadBytes("upper.stl", crlf, w);
    CHECK(s.size() == 2);
    CHECK(s.objects == std::vector<std::string>{"wall"});
}

// --- Facet normals, zero-area, duplicates, attributes ----------------------------------------------

TEST_CASE("STL: facet normals against the vertex order are counted and named, the vertex order decides, zero normals pass") {
    std::vector<StlTriangle> triangles = cubeTriangles();
    triangles[3].normal = -triangles[3].normal;
    triangles[7].normal = -triangles[7].normal;
    triangles[9].normal = Vec3::Zero();
    for (const bool binary : {true, false}) {
        CAPTURE(binary);
        Printed p;
        const Scene s = binary ? loadBytes("n.stl", binaryStl(triangles), p.warnings)
                               : loadBytes("n.stl", asciiStl({{"n", triangles}}), p.warnings);
        CHECK(p.warnings.count("facet normals against the vertex order") == 2);
        CHECK(p.contains(binary ? "2 facet normal(s) point against their vertex order (triangle 3, triangle 7)"
                                : "(triangle 3 (line 23), triangle 7 (line 51))"));
        CHECK(p.contains("the vertex order (right-hand rule) decides the emitting side"));
        CHECK(s.patches[3].normal.isApprox(-triangles[3].normal));
        CHECK(s.patches[9].normal.isApprox(cubeTriangles()[9].normal));
    }
}

TEST_CASE("STL: zero-area triangles are skipped and counted, as the OBJ reader skips degenerate faces") {
    std::vector<StlTriangle> triangles = cubeTriangles();
    StlTriangle flat = triangles[0];
    flat.vertices[2] = flat.vertices[1];
    triangles.insert(triangles.begin() + 4, flat);
    Printed p;
    const Scene s = loadBytes("z.stl", binaryStl(triangles), p.warnings);
    CHECK(s.size() == 12);
    CHECK(p.warnings.count("degenerate patches skipped") == 1);
    CHECK(p.contains("z.stl: triangle 4: 1 zero-area triangle(s) skipped"));
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadBytes("flat.stl", binaryStl({flat}), w),
                         doctest::Contains("flat.stl: every triangle has zero area: no patches"), Error);
}

TEST_CASE("STL: a repeated triangle and attribute bytes are counted warnings") {
    std::vector<StlTriangle> triangles = cubeTriangles();
    triangles.push_back(triangles[2]);
    triangles[6].attribute = 0x7c1f;
    Printed p;
    const Scene s = loadBytes("d.stl", binaryStl(triangles), p.warnings);
    CHECK(s.size() == 13);
    CHECK(p.warnings.count("duplicate patches") == 1);
    CHECK(p.contains("d.stl: triangle 12: 1 triangle(s) repeat the vertices of an earlier triangle"));
    CHECK(p.warnings.count("STL attribute bytes ignored") == 1);
    CHECK(p.contains("d.stl: triangle 6: 1 triangle(s) carry attribute bytes"));
}

// --- Hostile binary files ------------------------------------------------------------------------

TEST_CASE("STL binary: truncation, a count that does not match the size, and a short header name the file and triangle") {
    Warnings w = quietWarnings();
    const std::string whole = binaryStl(cubeTriangles());
    CHECK_THROWS_WITH_AS(loadBytes("cut.stl", whole.substr(0, 84 + 50 * 3 + 20), w),
                         doctest::Contains("cut.stl: truncated in triangle 3: the header announces 12 triangles (684 bytes), the file has 254"),
                         Error);
    CHECK_THROWS_WITH_AS(loadBytes("long.stl", binaryStl(cubeTriangles(), "x", 11), w),
                         doctest::Contains("long.stl: triangle count does not match the file size: the header announces 11 "
                                           "triangles (634 bytes), the file has 684 (12 triangles and 0 bytes)"),
                         Error);
    CHECK_THROWS_WITH_AS(loadBytes("short.stl", whole.substr(0, 60), w),
                         doctest::Contains("short.stl: truncated: 60 bytes, shorter than a binary STL's 84-byte header"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("empty.stl", "", w), doctest::Contains("empty.stl: empty file: no triangles"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("none.stl", binaryStl({}), w),
                         doctest::Contains("none.stl: no triangles: nothing to compute"), Error);
}

TEST_CASE("STL binary: NaN, infinite and huge coordinates and a NaN normal name the triangle and the value") {
    Warnings w = quietWarnings();
    auto damaged = [](int triangle, int vertex, int axis, double value) {
        std::vector<StlTriangle> t = cubeTriangles();
        t[triangle].vertices[vertex][axis] = value;
        return binaryStl(t);
    };
    CHECK_THROWS_WITH_AS(loadBytes("nan.stl", damaged(3, 1, 1, kNaN), w),
                         doctest::Contains("nan.stl: triangle 3: second vertex y = nan is not a finite number"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("inf.stl", damaged(0, 2, 2, -INFINITY), w),
                         doctest::Contains("inf.stl: triangle 0: third vertex z = -inf is not a finite number"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("far.stl", damaged(11, 0, 0, 1e30), w),
                         doctest::Contains("far.stl: triangle 11: first vertex x = 1e+30 is too far out"), Error);
    std::vector<StlTriangle> t = cubeTriangles();
    t[5].normal = Vec3(0, 1, kNaN);
    CHECK_THROWS_WITH_AS(loadBytes("normal.stl", binaryStl(t), w),
                         doctest::Contains("normal.stl: triangle 5: facet normal (0, 1, nan) is not finite"), Error);
}

// --- Hostile ASCII files -------------------------------------------------------------------------

TEST_CASE("STL ASCII: wrong keywords, unclosed facets, short and long loops and a missing endsolid name the line") {
    Warnings w = quietWarnings();
    const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    CHECK_THROWS_WITH_AS(loadBytes("a.stl", "solid a\n" + facet + "facet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                            "vertex 1 0 0\nvertex 0 1 0\nendloop\nendsolid a\n", w),
                         doctest::Contains("a.stl:15: the facet of line 9 is not closed: expected 'endfacet', found 'endsolid'"),
                         Error);
    CHECK_THROWS_WITH_AS(loadBytes("b.stl", "solid b\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n", w),
                         doctest::Contains("b.stl:6: the loop of the facet of line 2 has 2 vertices; an STL facet needs exactly 3"),
                         Error);
    CHECK_THROWS_WITH_AS(loadBytes("c.stl", "solid c\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                            "vertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n", w),
                         doctest::Contains("c.stl:7: a 4th vertex in the loop of the facet of line 2"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("d.stl", "solid d\nfacet normal 0 0 1\nouter lop\n", w),
                         doctest::Contains("d.stl:3: expected 'outer loop' after the facet of line 2, found 'outer lop'"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("e.stl", "solid e\n" + facet + "facett normal 0 0 1\n", w),
                         doctest::Contains("e.stl:9: expected 'facet' or 'endsolid' in solid 'e' (line 1), found 'facett'"),
                         Error);
    CHECK_THROWS_WITH_AS(loadBytes("f.stl", "solid f\n" + facet, w),
                         doctest::Contains("f.stl:8: the file ends inside solid 'f' of line 1 (no 'endsolid'): truncated?"),
                         Error);
    CHECK_THROWS_WITH_AS(loadBytes("g.stl", "solid g\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", w),
                         doctest::Contains("g.stl:4: the file ends inside the facet of line 2 (no 'endfacet'): truncated?"),
                         Error);
    CHECK_THROWS_WITH_AS(loadBytes("h.stl", "solid h\nfacet 0 0 1\n", w),
                         doctest::Contains("h.stl:2: 'facet' must be followed by 'normal nx ny nz'"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("i.stl", "solid i\n" + facet + "endsolid i\nvertex 0 0 0\n", w),
                         doctest::Contains("i.stl:10: expected 'solid' or the end of the file, found 'vertex'"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("j.stl", "solid j\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n", w),
                         doctest::Contains("j.stl:4: vertex needs 3 values, found '0 0'"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("k.stl", "solid k\nendsolid k\n", w),
                         doctest::Contains("k.stl: no triangles: nothing to compute"), Error);
}

TEST_CASE("STL ASCII: NaN, infinite and huge numbers name the line and the token") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadBytes("n.stl", "solid n\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 nan 0\n", w),
                         doctest::Contains("n.stl:5: vertex y 'nan' is not a finite number"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("i.stl", "solid i\nfacet normal 0 0 1\nouter loop\nvertex 0 0 1e999\n", w),
                         doctest::Contains("i.stl:4: vertex z '1e999' is not a finite number"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("h.stl", "solid h\nfacet normal 0 0 1\nouter loop\nvertex 0 0 1e300\n", w),
                         doctest::Contains("h.stl:4: vertex '0 0 1e300' is too far out"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("m.stl", "solid m\nfacet normal inf 0 1\n", w),
                         doctest::Contains("m.stl:2: facet normal component 'inf' is not a finite number"), Error);
}

// --- The loader chosen by extension --------------------------------------------------------------

TEST_CASE("loadScene picks the reader by extension, case-insensitive, and names the types it reads otherwise") {
    Warnings w = quietWarnings();
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    CHECK(loadBytes("t.obj", obj, w).size() == 1);
    CHECK(loadBytes("t.OBJ", obj, w).size() == 1);
    CHECK(loadBytes("t.Stl", binaryStl(cubeTriangles()), w).size() == 12);
    CHECK_THROWS_WITH_AS(loadBytes("t.ply", obj, w),
                         doctest::Contains("t.ply: unknown scene file type '.ply': Hemirad reads .obj (with its .mtl "
                                           "libraries) and .stl (binary or ASCII)"),
                         Error);
    CHECK_THROWS_WITH_AS(loadBytes("scene", obj, w), doctest::Contains("scene: no file extension: Hemirad reads .obj"), Error);
    // An OBJ given the wrong extension is not taken for an STL silently either.
    CHECK_THROWS_WITH_AS(loadBytes("t.stl", obj, w), doctest::Contains("t.stl: truncated: 32 bytes"), Error);
    CHECK(sceneExtensions() == std::vector<std::string>{".obj", ".stl"});
}

// --- Materials by object name --------------------------------------------------------------------

namespace {

/// Floor (2 triangles) and walls (10) of the unit cube as two ASCII solids.
std::string twoSolids() {
    const std::vector<StlTriangle> t = cubeTriangles();
    return asciiStl({{"floor", {t[0], t[1]}}, {"walls", std::vector<StlTriangle>(t.begin() + 2, t.end())}});
}

}  // namespace

TEST_CASE("Materials by object name: each object takes the material of its name") {
    Printed p;
    const Scene s = loadBytes("room.stl", twoSolids(), p.warnings,
                              "newmtl walls\nKd 0.2 0.4 0.6\nnewmtl floor\nKd 0.1\nKe 5 5 5\n");
    REQUIRE(s.size() == 12);
    for (PatchId i = 0; i < 12; ++i) {
        CAPTURE(i);
        const bool floor = i < 2;
        CHECK(s.materials[s.patches[i].material].name == (floor ? "floor" : "walls"));
        CHECK((s.patches[i].rho == (floor ? Rgb::Constant(0.1) : Rgb(0.2, 0.4, 0.6))).all());
        CHECK((s.patches[i].emission == (floor ? Rgb::Constant(5) : Rgb::Zero())).all());
    }
    CHECK(p.warnings.count() == 0);
}

TEST_CASE("Materials by object name: 'default' goes to the objects without a match") {
    Printed p;
    const Scene s = loadBytes("room.stl", twoSolids(), p.warnings, "newmtl default\nKd 0.3\nnewmtl floor\nKe 1 1 1\n");
    CHECK((s.patches[0].emission == Rgb::Constant(1)).all());
    CHECK((s.patches[0].rho == Rgb::Constant(0.5)).all());  // floor's own: no Kd, MTL's default 0.5
    for (PatchId i = 2; i < 12; ++i) {
        CHECK(s.materials[s.patches[i].material].name == "default");
        CHECK((s.patches[i].rho == Rgb::Constant(0.3)).all());
    }
    CHECK(p.warnings.count() == 0);
    // A binary file is one object: 'default' gives it its material.
    Printed q;
    const Scene b = loadBytes("cube.stl", binaryStl(cubeTriangles()), q.warnings, "newmtl default\nKd 0.7\n");
    for (const Patch& patch : b.patches) CHECK((patch.rho == Rgb::Constant(0.7)).all());
    CHECK(q.warnings.count() == 0);
}

TEST_CASE("Materials by object name: objects left without one are counted in one warning naming them") {
    Printed p;
    const std::vector<StlTriangle> t = cubeTriangles();
    const Scene s = loadBytes("parts.stl",
                              asciiStl({{"a", {t[0]}}, {"b", {t[1]}}, {"c", {t[2]}}, {"d", {t[3]}}, {"e", {t[4]}},
                                        {"f", {t[5]}}, {"lit", {t[6]}}}),
                              p.warnings, "newmtl lit\nKe 1 1 1\n");
    CHECK(p.warnings.count("objects without a material") == 6);
    REQUIRE(p.lines.size() == 1);
    CHECK(p.contains("m.mtl: 6 object(s) match no material, and there is no 'default': 'a', 'b', 'c', 'd' and 2 more; "
                     "they get the built-in default (Kd 0.5, no emission)"));
    CHECK(s.materials[s.patches[0].material].name == kDefaultMaterialName);
    CHECK((s.patches[6].emission == Rgb::Constant(1)).all());
    // Without --materials, an STL's objects are all without one, and the warning says how to give them.
    Printed q;
    loadBytes("parts.stl", twoSolids(), q.warnings);
    CHECK(q.contains("parts.stl: 2 object(s) without a material (STL has none): 'floor', 'walls'"));
    CHECK(q.contains("--materials FILE.mtl gives materials by object name"));
}

TEST_CASE("Materials by object name: a name that matches no object is warned by name (a typo shows)") {
    Printed p;
    loadBytes("room.stl", twoSolids(), p.warnings, "newmtl flor\nKe 1 1 1\nnewmtl walls\nnewmtl default\nnewmtl lamp\n");
    CHECK(p.warnings.count("materials naming no object") == 2);
    CHECK(p.contains("m.mtl: 2 material(s) name no object of "));
    CHECK(p.contains("room.stl: 'flor', 'lamp' (its objects: 'floor', 'walls')"));
    CHECK(p.warnings.count("objects without a material") == 0);  // 'default' took the floor
}

TEST_CASE("Materials by object name: a broken material file is an error with its file and line") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadBytes("room.stl", twoSolids(), w, "newmtl floor\nKd 0.5\n\nKd 1 nan 1\n", "broken.mtl"),
                         doctest::Contains("broken.mtl:4: Kd 'nan' is not a finite number"), Error);
    CHECK_THROWS_WITH_AS(loadBytes("room.stl", twoSolids(), w, "newmtl floor\nKd 1.2\n", "bright.mtl"),
                         doctest::Contains("bright.mtl:1: material 'floor' reflects more than it receives"), Error);
    CHECK_THROWS_WITH_AS(loadScene(writeFile(tempDir("stl-missing") / "room.stl", twoSolids()), w, {"/nonexistent/m.mtl"}),
                         doctest::Contains("/nonexistent/m.mtl: cannot open"), Error);
}

TEST_CASE("Materials by object name: an OBJ's own materials are overridden only where a name matches") {
    const auto dir = tempDir("obj-by-name");
    writeFile(dir / "own.mtl", "newmtl grey\nKd 0.4\n");
    const std::string obj = "mtllib own.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\n"
                            "o bare\nf 1 2 5\no lamp\nusemtl grey\nf 1 2 3\no table\nf 2 4 3\no\nf 3 4 5\n";
    const std::string path = writeFile(dir / "room.obj", obj);
    Printed p;
    const Scene s = loadScene(path, p.warnings, {writeFile(dir / "m.mtl", "newmtl lamp\nKe 9 9 9\nnewmtl default\nKd 0.1\n")});
    REQUIRE(s.size() == 4);
    CHECK((s.patches[1].emission == Rgb::Constant(9)).all());  // matched: the library's
    CHECK((s.patches[2].rho == Rgb::Constant(0.4)).all());      // its own material stays
    CHECK((s.patches[0].rho == Rgb::Constant(0.1)).all());      // none of its own: 'default'
    CHECK(s.objects[s.patches[3].object] == "default");        // `o` without a name: OBJ's "default"
    CHECK((s.patches[3].rho == Rgb::Constant(0.4)).all());      // ... keeps its own material too
    CHECK(p.warnings.count() == 0);  // not "faces before any usemtl": --materials gave them one
    // Without --materials the OBJ reader's own warning stays.
    Printed q;
    loadScene(path, q.warnings);
    CHECK(q.warnings.count("patches without a material") == 1);
}
