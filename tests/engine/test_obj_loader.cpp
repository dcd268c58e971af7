// OBJ/MTL loading: the bundled scenes, and every malformed input named with file:line and value.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "engine/obj_writer.hpp"
#include "engine/subdivide.hpp"

#include <doctest/doctest.h>

#include <limits>
#include <map>
#include <sstream>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// Writes an OBJ (and optionally an MTL beside it) and loads it.
Scene loadText(const std::string& name, const std::string& obj, const std::string& mtl, Warnings& warnings) {
    const auto dir = tempDir("obj");
    if (!mtl.empty()) writeFile(dir / "m.mtl", mtl);
    return loadObj(writeFile(dir / name, obj), warnings);
}

const std::string kMtl = "newmtl white\nKd 0.5 0.5 0.5\n";
const std::string kTriangleHead = "mtllib m.mtl\nusemtl white\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";

}  // namespace

TEST_CASE("The Cornell box loads as 20 patches facing into the box, with its camera") {
    Warnings w = quietWarnings();
    const Scene s = loadObj(sourcePath("scenes/cornell_box.obj"), w);
    CHECK(s.size() == 20);
    REQUIRE(s.camera.has_value());
    CHECK(s.camera->eye.isApprox(Vec3(278, 273, -800)));
    CHECK(s.camera->fovY == doctest::Approx(39.3077));
    CHECK_FALSE(s.hasMirrors());
    double emitting = 0;
    for (const Patch& p : s.patches) {
        CHECK(p.area > 0);
        CHECK(p.normal.norm() == doctest::Approx(1.0));
        if ((p.emission > 0).any()) emitting += p.area;
    }
    CHECK(emitting == doctest::Approx(130.0 * 105.0));
    CHECK(w.count("non-planar patches") == 0);  // the red wall is given as two triangles
}

TEST_CASE("The mirror Cornell box has one mirror with s = mean(Ks) = 0.9") {
    Warnings w = quietWarnings();
    const Scene s = loadObj(sourcePath("scenes/cornell_mirror.obj"), w);
    int mirrors = 0;
    for (const Patch& p : s.patches)
        if (p.specular > 0) {
            ++mirrors;
            CHECK(p.specular == doctest::Approx(0.9));
        }
    CHECK(mirrors == 1);
}

TEST_CASE("OBJ: a vertex index out of range names file, line and index") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadText("a.obj", kTriangleHead + "f 1 2 3\nf 1 2 9\n", kMtl, w),
                         doctest::Contains("a.obj:7: vertex index 9 is out of range (the file has 3 vertices)"),
                         Error);
}

TEST_CASE("OBJ: a NaN vertex coordinate names file, line and value") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadText("nan.obj", "v 0 0 0\nv 1 nan 0\n", "", w),
                         doctest::Contains("nan.obj:2: vertex y 'nan' is not a finite number"), Error);
    CHECK_THROWS_WITH_AS(loadText("inf.obj", "v 0 0 1e999\n", "", w), doctest::Contains("inf.obj:1: vertex z '1e999'"),
                         Error);
}

TEST_CASE("OBJ: a missing material library names the library and the line") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadText("b.obj", "# scene\nmtllib nothere.mtl\n", "", w),
                         doctest::Contains("b.obj:2: material library 'nothere.mtl' not found"), Error);
}

TEST_CASE("OBJ: index 0, relative indices before the first vertex and short faces are errors") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadText("z.obj", kTriangleHead + "f 0 1 2\n", kMtl, w),
                         doctest::Contains("z.obj:6: face vertex '0': index 0 is invalid"), Error);
    CHECK_THROWS_WITH_AS(loadText("r.obj", kTriangleHead + "f -1 -2 -4\n", kMtl, w),
                         doctest::Contains("r.obj:6: relative vertex index -4 reaches before the first vertex"), Error);
    CHECK_THROWS_WITH_AS(loadText("s.obj", kTriangleHead + "f 1 2\n", kMtl, w),
                         doctest::Contains("s.obj:6: face has 2 vertices; a patch needs at least 3"), Error);
    CHECK_THROWS_WITH_AS(loadText("t.obj", kTriangleHead + "f 1/7 2 3\n", kMtl, w),
                         doctest::Contains("t.obj:6: texture coordinate index 7"), Error);
}

TEST_CASE("OBJ: relative indices, v/vt/vn forms, CRLF and tabs load") {
    Warnings w = quietWarnings();
    const Scene s = loadText("ok.obj",
                             "mtllib m.mtl\r\nusemtl white\r\nv 0 0 0\r\nv\t1 0 0\r\nv 0 1 0\r\nvt 0 0\r\nvn 0 0 1\r\n"
                             "f -3/1/1 -2//1 -1/1\r\n",
                             kMtl, w);
    REQUIRE(s.size() == 1);
    CHECK(s.patches[0].area == doctest::Approx(0.5));
    CHECK(s.patches[0].normal.isApprox(Vec3(0, 0, 1)));
    CHECK(s.patches[0].sourceLine == 8);
}

TEST_CASE("OBJ: an unknown usemtl is an error at its line") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadText("u.obj", "mtllib m.mtl\nusemtl gold\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", kMtl, w),
                         doctest::Contains("u.obj:2: usemtl 'gold': no such material"), Error);
}

TEST_CASE("OBJ: empty, binary, line-only and unknown-statement files are rejected clearly") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadText("e.obj", "", "", w), doctest::Contains("e.obj: no faces"), Error);
    CHECK_THROWS_WITH_AS(loadText("bin.obj", std::string("v 0 0 0\n\x7f" "ELF\0\x01", 13), "", w),
                         doctest::Contains("bin.obj:2: contains a NUL byte"), Error);
    CHECK_THROWS_WITH_AS(loadText("l.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n", "", w),
                         doctest::Contains("no faces: only lines, points or curves"), Error);
    CHECK_THROWS_WITH_AS(loadText("k.obj", "v 0 0 0\nfoo 1 2\n", "", w),
                         doctest::Contains("k.obj:2: unknown OBJ statement 'foo'"), Error);
    CHECK_THROWS_WITH_AS(loadObj("/nonexistent/scene.obj", w), doctest::Contains("/nonexistent/scene.obj: cannot open"),
                         Error);
    CHECK_THROWS_WITH_AS(loadObj(tempDir("dir").string(), w), doctest::Contains("is a directory"), Error);
}

TEST_CASE("OBJ: degenerate faces are skipped and counted, non-planar ones warned with the deviation") {
    std::vector<std::string> printed;
    Warnings w([&](const std::string& m) { printed.push_back(m); });
    const Scene s = loadText("d.obj",
                             kTriangleHead + "v 2 0 0\nv 1 1 0.5\nv 0 1 0\n"
                                             "f 1 2 3\nf 1 2 4\nf 1 2 5 6\n",
                             kMtl, w);
    CHECK(s.size() == 2);
    CHECK(w.count("degenerate patches skipped") == 1);
    CHECK(w.count("non-planar patches") == 1);
    REQUIRE(printed.size() == 2);
    CHECK(printed[0].find("d.obj:10: 1 zero-area face(s) skipped") != std::string::npos);
    CHECK(printed[1].find("non-planar patch(es); worst deviation") != std::string::npos);
    CHECK(w.summary().find("2 warnings") == 0);
}

TEST_CASE("OBJ: a concave polygon is an error (fan triangulation would change its shape)") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(
        loadText("c.obj", "mtllib m.mtl\nusemtl white\nv 0 0 0\nv 2 0 0\nv 1 0.2 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4 5\n",
                 kMtl, w),
        doctest::Contains("c.obj:8: face with 5 vertices is not convex"), Error);
}

TEST_CASE("MTL: Kd, Ke and mirror reflectance s = mean(Ks) only for illum 3, 5, 7") {
    Warnings w = quietWarnings();
    std::vector<Material> m;
    const auto dir = tempDir("mtl");
    loadMtl(writeFile(dir / "a.mtl", "newmtl a\nKd .2 .3 .3\nKe 1 2 3\nKs .6 .6 .9\nillum 3\n"
                                     "newmtl b\nKd 0.5\nKs 1 1 1\nillum 2\nNs 10\nmap_Kd tex.png\n"),
            m, w);
    REQUIRE(m.size() == 2);
    CHECK((m[0].rho == Rgb(.2, .3, .3)).all());
    CHECK((m[0].emission == Rgb(1, 2, 3)).all());
    CHECK(m[0].specular == doctest::Approx(0.7));
    CHECK(m[1].specular == 0.0);
    CHECK((m[1].rho == Rgb::Constant(0.5)).all());
    CHECK(w.count() == 0);
}

TEST_CASE("MTL: a mirror without Kd has no diffuse part, and rho + s > 1 is an error naming file and line") {
    Warnings w = quietWarnings();
    std::vector<Material> m;
    const auto dir = tempDir("mtl-energy");
    // Ks 0.9 / illum 3 alone once took the default rho 0.5: rho + s = 1.4 created energy.
    loadMtl(writeFile(dir / "mirror.mtl", "newmtl glass\nKs 0.9 0.9 0.9\nillum 3\nnewmtl plain\n"), m, w);
    REQUIRE(m.size() == 2);
    CHECK(m[0].specular == doctest::Approx(0.9));
    CHECK((m[0].rho == Rgb::Zero()).all());
    CHECK((m[1].rho == Rgb::Constant(0.5)).all());  // not a mirror: the default diffuse material
    CHECK_THROWS_WITH_AS(loadMtl(writeFile(dir / "over.mtl", "# c\nnewmtl shiny\nKd .5 .2 .2\nKs .8 .8 .8\nillum 3\n"), m, w),
                         doctest::Contains("over.mtl:2: material 'shiny' reflects more than it receives: Kd + mean(Ks) = 1.3"),
                         Error);
    CHECK_THROWS_WITH_AS(loadMtl(writeFile(dir / "bright.mtl", "newmtl bright\nKd 1.5 .5 .5\n"), m, w),
                         doctest::Contains("bright.mtl:1: material 'bright' reflects more than it receives: Kd = 1.5"), Error);
    // s = 1 with no Kd is a perfect mirror, allowed.
    CHECK_NOTHROW(loadMtl(writeFile(dir / "perfect.mtl", "newmtl perfect\nKs 1 1 1\nillum 3\n"), m, w));
}

TEST_CASE("MTL: negative or non-numeric values are errors with file:line") {
    Warnings w = quietWarnings();
    std::vector<Material> m;
    const auto dir = tempDir("mtl-bad");
    CHECK_THROWS_WITH_AS(loadMtl(writeFile(dir / "n.mtl", "newmtl a\nKd .5 -.1 .5\n"), m, w),
                         doctest::Contains("n.mtl:2: Kd '.5 -.1 .5' has a negative value"), Error);
    CHECK_THROWS_WITH_AS(loadMtl(writeFile(dir / "x.mtl", "newmtl a\nKe 1 nan 1\n"), m, w),
                         doctest::Contains("x.mtl:2: Ke 'nan' is not a finite number"), Error);
    CHECK_THROWS_WITH_AS(loadMtl(writeFile(dir / "y.mtl", "Kd 1 1 1\n"), m, w),
                         doctest::Contains("y.mtl:1: 'Kd' before any newmtl"), Error);
}

TEST_CASE("Saving a scene as OBJ + MTL and loading it back keeps geometry, materials and edits") {
    Warnings w = quietWarnings();
    Scene s = loadObj(sourcePath("scenes/cornell_mirror.obj"), w);
    s.patches[3].emission = Rgb(1, 2, 3);  // an edit: the writer must derive a material for it
    const auto dir = tempDir("save");
    saveObj(s, (dir / "copy.obj").string());
    const Scene t = loadObj((dir / "copy.obj").string(), w);
    REQUIRE(t.size() == s.size());
    CHECK(t.geometryHash() == s.geometryHash());
    for (PatchId i = 0; i < s.size(); ++i) {
        CHECK((t.patches[i].rho == s.patches[i].rho).all());
        CHECK((t.patches[i].emission == s.patches[i].emission).all());
        CHECK(t.patches[i].specular == doctest::Approx(s.patches[i].specular));
    }
    REQUIRE(t.camera.has_value());
    CHECK(t.camera->eye.isApprox(s.camera->eye));
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        CHECK(entry.path().string().find("hemirad-tmp") == std::string::npos);
        ++files;
    }
    CHECK(files == 2);
}

TEST_CASE("A saved derived material keeps its original's illum, and a mirror made by an edit gets illum 3 (issue 38 #14)") {
    // An edited diffuse material was written with illum 2 beside the Cornell box's illum 1 ones.
    Warnings w = quietWarnings();
    Scene s = bundledScene("cornell_box.obj");
    s.patches[0].rho = Rgb(0.5, 0.5, 0.5);  // the floor: a derived material of its illum 1 one
    PatchId wall = 0;  // a patch of the red wall, made a mirror
    while (s.materials[s.patches[wall].material].name != "red") ++wall;
    s.patches[wall].specular = 0.2;
    s.patches[wall].rho = Rgb(0.5, 0.05, 0.05);
    const auto dir = tempDir("illum");
    saveObj(s, (dir / "copy.obj").string());
    // Each material's block in the MTL: its name, then its lines up to the next newmtl.
    std::map<std::string, std::string> blocks;
    std::istringstream mtl(readText(dir / "copy.mtl"));
    std::string line, name;
    while (std::getline(mtl, line)) {
        if (line.rfind("newmtl ", 0) == 0) name = line.substr(7);
        else if (!name.empty()) blocks[name] += line + "\n";
    }
    REQUIRE(blocks.count("white~1") == 1);
    REQUIRE(blocks.count("red~1") == 1);
    CHECK(blocks["white"].find("illum 1\n") != std::string::npos);
    CHECK(blocks["white~1"].find("illum 1\n") != std::string::npos);
    CHECK(blocks["red~1"].find("illum 3\n") != std::string::npos);
    for (const auto& [material, text] : blocks) {
        CAPTURE(material);
        CHECK(text.find("illum 2") == std::string::npos);
    }
    const Scene t = loadObj((dir / "copy.obj").string(), w);
    CHECK(t.patches[wall].specular == doctest::Approx(0.2));
    CHECK((t.patches[0].rho == Rgb(0.5, 0.5, 0.5)).all());
}

TEST_CASE("OBJ and MTL numbers are written in the shortest form that reads back to the same double") {
    // Issue 14, defect 2: a mirror edited to 0.9 through a 32-bit slider (0.89999997615814209) was
    // written with 9 digits, read back as another double, and the scene hash (so F's match) changed;
    // coordinates carried 17-digit noise (552.79999999999995).
    Warnings w = quietWarnings();
    Scene s = loadObj(sourcePath("scenes/cornell_mirror.obj"), w);
    PatchId mirror = 0;
    while (!(s.patches[mirror].specular > 0.0)) ++mirror;
    s.patches[mirror].specular = double(0.9f);
    s.patches[mirror].rho = Rgb::Constant(double(0.1f) / 2.0);
    s.patches[0].emission = Rgb(1.0 / 3.0, 2e-300, 123456789.125);
    const auto dir = tempDir("shortest");
    saveObj(s, (dir / "copy.obj").string());
    const Scene t = loadObj((dir / "copy.obj").string(), w);
    REQUIRE(t.size() == s.size());
    CHECK(t.geometryHash() == s.geometryHash());
    CHECK(t.vertices == s.vertices);
    for (PatchId i = 0; i < s.size(); ++i) {
        CAPTURE(i);
        CHECK((t.patches[i].rho == s.patches[i].rho).all());
        CHECK((t.patches[i].emission == s.patches[i].emission).all());
        CHECK(t.patches[i].specular == s.patches[i].specular);  // bit for bit
    }
    const std::string obj = readText(dir / "copy.obj"), mtl = readText(dir / "copy.mtl");
    CHECK(obj.find("v 552.8 0 0\n") != std::string::npos);
    CHECK(obj.find("552.79999") == std::string::npos);
    CHECK(mtl.find("Ks 0.8999999761581421 0.8999999761581421 0.8999999761581421\n") != std::string::npos);
    CHECK(mtl.find("Kd 0.73 0.73 0.73\n") != std::string::npos);
    CHECK(mtl.find("Ke 0.3333333333333333 2e-300 123456789.125\n") != std::string::npos);
}

TEST_CASE("OBJ: a hemirad unit line states the length unit, an unknown one names file, line and value, saving keeps it") {
    Warnings w = quietWarnings();
    CHECK(bundledScene("cornell_box.obj").unit == "mm");
    CHECK(loadText("none.obj", kTriangleHead + "f 1 2 3\n", kMtl, w).unit.empty());
    const Scene s = loadText("cm.obj", "# hemirad unit cm\n" + kTriangleHead + "f 1 2 3\n", kMtl, w);
    CHECK(s.unit == "cm");
    CHECK(metresPerUnit(s.unit) == 0.01);
    CHECK(metresPerUnit("") == 0.0);
    CHECK_THROWS_WITH_AS(loadText("pc.obj", kTriangleHead + "# hemirad unit parsec\nf 1 2 3\n", kMtl, w),
                         doctest::Contains("pc.obj:6: unknown length unit 'parsec' (m, cm, mm, in or ft)"), Error);
    CHECK_THROWS_WITH_AS(loadText("two.obj", "# hemirad unit m mm\n" + kTriangleHead, kMtl, w),
                         doctest::Contains("two.obj:1: '# hemirad unit' needs one length unit"), Error);
    const auto dir = tempDir("unit");
    saveObj(s, (dir / "copy.obj").string());
    CHECK(loadObj((dir / "copy.obj").string(), w).unit == "cm");
}

TEST_CASE("OBJ: a hemirad up line states the up axis (y or z), another value names file, line and value, saving keeps it") {
    // Issue 38 #12: Z-up models open edge-on in the GUI unless it knows their up axis.
    Warnings w = quietWarnings();
    CHECK(loadText("none.obj", kTriangleHead + "f 1 2 3\n", kMtl, w).up == 0);
    CHECK(loadText("y.obj", "# hemirad up y\n" + kTriangleHead + "f 1 2 3\n", kMtl, w).up == 1);
    const Scene s = loadText("z.obj", "# hemirad up z\n" + kTriangleHead + "f 1 2 3\n", kMtl, w);
    CHECK(s.up == 2);
    CHECK_THROWS_WITH_AS(loadText("x.obj", kTriangleHead + "# hemirad up x\nf 1 2 3\n", kMtl, w),
                         doctest::Contains("x.obj:6: '# hemirad up' needs the up axis, y or z, got 'x'"), Error);
    const auto dir = tempDir("up");
    saveObj(s, (dir / "copy.obj").string());
    CHECK(readText(dir / "copy.obj").find("# hemirad up z\n") != std::string::npos);
    CHECK(loadObj((dir / "copy.obj").string(), w).up == 2);
    CHECK(subdivide(s, 0.1).up == 2);
}

TEST_CASE("checkCamera refuses a non-finite eye or target, a field of view outside (0, 180) and a coinciding eye and target, naming the value") {
    // Issue 35 #7: the one check behind the CLI's --camera, the OBJ camera line and Python's render().
    Camera c;
    c.eye = Vec3(1, 2, 3);
    c.target = Vec3(0, 0, 0);
    c.fovY = 40;
    CHECK_NOTHROW(checkCamera(c));
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const struct {
        Vec3 eye, target;
        double fov;
        const char* message;
    } refused[] = {
        {Vec3(nan, 0, 1), Vec3(0, 0, 0), 40, "camera eye (nan, 0, 1) is not a finite point"},
        {Vec3(0, 0, 1), Vec3(0, -inf, 0), 40, "camera target (0, -inf, 0) is not a finite point"},
        {Vec3(1e300, 0, 0), Vec3(-1e300, 0, 0), 40, "camera eye (1e+300, 0, 0) and target (-1e+300, 0, 0) are too far apart"},
        {Vec3(0, 0, 1), Vec3(0, 0, 0), 0, "camera field of view 0 is outside (0, 180) degrees"},
        {Vec3(0, 0, 1), Vec3(0, 0, 0), 180, "camera field of view 180 is outside (0, 180) degrees"},
        {Vec3(0, 0, 1), Vec3(0, 0, 0), 200, "camera field of view 200 is outside (0, 180) degrees"},
        {Vec3(0, 0, 1), Vec3(0, 0, 0), nan, "camera field of view nan is outside (0, 180) degrees"},
        {Vec3(1, 2, 3), Vec3(1, 2, 3), 40, "camera eye and target coincide at (1, 2, 3)"},
    };
    for (const auto& r : refused) {
        CAPTURE(r.message);
        c.eye = r.eye;
        c.target = r.target;
        c.fovY = r.fov;
        CHECK_THROWS_WITH_AS(checkCamera(c), doctest::Contains(r.message), Error);
    }
    // The OBJ camera line goes through it, with its file and line.
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadText("cam.obj", "# hemirad camera 0 0 1 0 0 0 200\n" + kTriangleHead + "f 1 2 3\n", kMtl, w),
                         doctest::Contains("cam.obj:1: camera field of view 200 is outside (0, 180) degrees"), Error);
}
