// The committed corpus of malformed scenes (tests/data/malformed): each file gives a clear error
// naming file:line (a binary STL: file and triangle) and the value, or a counted warning where
// loading can go on, and never a crash. Files are read through loadScene, as every front end reads them.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/obj_loader.hpp"
#include "engine/scene_loader.hpp"

#include <doctest/doctest.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

std::string corpus(const std::string& name) { return sourcePath("tests/data/malformed/" + name); }

void expectError(const std::string& file, const std::string& message) {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadScene(corpus(file), w), doctest::Contains(message.c_str()), Error);
}

void expectWarning(const std::string& file, const std::string& kind, const std::string& message, std::size_t patches) {
    std::vector<std::string> printed;
    Warnings w([&](const std::string& m) { printed.push_back(m); });
    const Scene s = loadScene(corpus(file), w);
    CHECK(s.size() == patches);
    CHECK(w.count(kind) == 1);
    bool found = false;
    for (const std::string& m : printed) found |= m.find(message) != std::string::npos;
    CHECK_MESSAGE(found, "expected a warning containing '" << message << "'");
}

/// Runs `hemirad ARGUMENTS` with its output to `log`; returns its exit status (-1: not an exit) and
/// sets `maxRssKiB` to the peak resident memory of that one process (wait4's rusage).
int runMeasured(const std::vector<std::string>& arguments, const std::string& log, long& maxRssKiB) {
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (out < 0) ::_exit(92);
        ::dup2(out, 1);
        ::dup2(out, 2);
        std::vector<char*> argv{const_cast<char*>(HEMIRAD_BINARY)};
        for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(HEMIRAD_BINARY, argv.data());
        ::_exit(91);
    }
    int status = 0;
    struct rusage usage {};
    REQUIRE(::wait4(child, &status, 0, &usage) == child);
    maxRssKiB = usage.ru_maxrss;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

#define MALFORMED_ERROR(file, message) \
    TEST_CASE("Malformed corpus: " file " is refused with its location") { expectError(file, message); }
#define MALFORMED_WARNING(file, kind, message, patches) \
    TEST_CASE("Malformed corpus: " file " loads with a counted warning") { expectWarning(file, kind, message, patches); }

MALFORMED_ERROR("empty.obj", "empty.obj: no faces: nothing to compute")
MALFORMED_ERROR("binary.obj", "binary.obj:7: contains a NUL byte")
MALFORMED_ERROR("nan_vertex.obj", "nan_vertex.obj:5: vertex z 'nan' is not a finite number")
MALFORMED_ERROR("inf_vertex.obj", "inf_vertex.obj:4: vertex x 'inf' is not a finite number")
MALFORMED_ERROR("huge_vertex.obj", "huge_vertex.obj:4: vertex '1e300 0 0' is too far out")
MALFORMED_ERROR("index_out_of_range.obj", "index_out_of_range.obj:6: vertex index 7 is out of range (the file has 3 vertices)")
MALFORMED_ERROR("index_zero.obj", "index_zero.obj:6: face vertex '0': index 0 is invalid")
MALFORMED_ERROR("index_negative_past_start.obj", "index_negative_past_start.obj:6: relative vertex index -5 reaches before the first vertex")
MALFORMED_ERROR("face_two_vertices.obj", "face_two_vertices.obj:6: face has 2 vertices; a patch needs at least 3")
MALFORMED_ERROR("face_garbage_index.obj", "face_garbage_index.obj:6: face vertex '3x' is not an index")
MALFORMED_ERROR("texcoord_out_of_range.obj", "texcoord_out_of_range.obj:6: texture coordinate index 9 in '1/9' is out of range")
MALFORMED_ERROR("vertex_two_values.obj", "vertex_two_values.obj:3: vertex needs x y z")
MALFORMED_ERROR("lines_points_only.obj", "lines_points_only.obj: no faces: only lines, points or curves")
MALFORMED_ERROR("missing_mtl.obj", "missing_mtl.obj:1: material library 'nowhere.mtl' not found")
MALFORMED_ERROR("unreadable_mtl.obj", "unreadable_mtl.obj:1: material library 'directory.mtl': ")
MALFORMED_ERROR("unknown_usemtl.obj", "unknown_usemtl.obj:3: usemtl 'gold': no such material")
MALFORMED_ERROR("negative_kd.obj", "negative_kd.mtl:2: Kd '0.5 -0.2 0.5' has a negative value")
MALFORMED_ERROR("nan_ke.obj", "nan_ke.mtl:3: Ke 'nan' is not a finite number")
MALFORMED_ERROR("kd_above_one.obj", "kd_above_one.mtl:1: material 'bright' reflects more than it receives: Kd = 1.5")
MALFORMED_ERROR("rho_plus_s.obj", "rho_plus_s.mtl:1: material 'shiny' reflects more than it receives: Kd + mean(Ks) = 1.3")
MALFORMED_ERROR("specular_above_one.obj", "specular_above_one.mtl:1: material 'over': mirror reflectance mean(Ks) = 2 exceeds 1")
MALFORMED_ERROR("concave.obj", "concave.obj:8: face with 5 vertices is not convex")
MALFORMED_ERROR("unknown_statement.obj", "unknown_statement.obj:5: unknown OBJ statement 'foo'")
MALFORMED_ERROR("camera_degenerate.obj", "camera_degenerate.obj:3: camera eye and target coincide")

MALFORMED_WARNING("duplicate_faces.obj", "duplicate patches", "duplicate_faces.obj:8: 1 face(s) repeat the vertices", 3)
MALFORMED_WARNING("zero_area.obj", "degenerate patches skipped", "zero_area.obj:7: 1 zero-area face(s) skipped", 1)
MALFORMED_WARNING("non_planar.obj", "non-planar patches", "non_planar.obj:7: 1 non-planar patch(es); worst deviation", 1)

// STL (tests/data/make_malformed_stl.py writes these): binary errors name the triangle, ASCII ones the line.
MALFORMED_ERROR("stl_empty.stl", "stl_empty.stl: empty file: no triangles")
MALFORMED_ERROR("stl_truncated.stl",
                "stl_truncated.stl: truncated in triangle 1: the header announces 2 triangles (184 bytes), the file has 164")
MALFORMED_ERROR("stl_wrong_count.stl",
                "stl_wrong_count.stl: triangle count does not match the file size: the header announces 2 triangles "
                "(184 bytes), the file has 234 (3 triangles and 0 bytes)")
MALFORMED_ERROR("stl_nan_vertex.stl", "stl_nan_vertex.stl: triangle 1: third vertex x = nan is not a finite number")
MALFORMED_ERROR("stl_solid_header_truncated.stl",
                "stl_solid_header_truncated.stl: truncated in triangle 1: the header announces 2 triangles")
MALFORMED_ERROR("stl_facet_not_closed.stl",
                "stl_facet_not_closed.stl:8: the facet of line 2 is not closed: expected 'endfacet', found 'endsolid'")
MALFORMED_ERROR("stl_four_vertices.stl", "stl_four_vertices.stl:7: a 4th vertex in the loop of the facet of line 2")
MALFORMED_WARNING("stl_zero_area.stl", "degenerate patches skipped",
                  "stl_zero_area.stl:9: triangle 1: 1 zero-area triangle(s) skipped", 1)

TEST_CASE("Malformed corpus: CRLF, tabs, odd whitespace and a trailing continuation load cleanly") {
    for (const char* file : {"crlf_whitespace.obj", "continuation_at_end.obj"}) {
        CAPTURE(file);
        Warnings w = quietWarnings();
        const Scene s = loadObj(corpus(file), w);
        CHECK(s.size() == 1);
        CHECK(w.count() == 0);
        CHECK(s.patches[0].area == doctest::Approx(0.5));
    }
}

TEST_CASE("Malformed corpus: a missing path and a directory are refused by name") {
    Warnings w = quietWarnings();
    CHECK_THROWS_WITH_AS(loadObj(corpus("no_such_scene.obj"), w), doctest::Contains("no_such_scene.obj: cannot open: No such file"), Error);
    CHECK_THROWS_WITH_AS(loadObj(sourcePath("tests/data/malformed"), w), doctest::Contains("malformed: is a directory"), Error);
}

// F files: what they declare must not decide what they cost (issue 35 #11). 68 bytes declaring
// N = 2^28 patches and no entry: a valid (if useless) F whose CSR would take 2.3 GB of row arrays.
TEST_CASE("Malformed corpus: mtx_huge_declared_size.mtx (68 bytes declaring N = 2^28) costs what its entries cost") {
    const std::string path = corpus("mtx_huge_declared_size.mtx");
    REQUIRE(std::filesystem::file_size(path) == 68);
    // hemirad info checks every entry and describes F without its N-sized row arrays: its peak memory
    // is the program's own (about 10 MB), not the 2.3 GB (and 12 s) that the declared N costed.
    long maxRssKiB = 0;
    const std::string log = (tempDir("huge-mtx") / "info.log").string();
    CHECK(runMeasured({"info", path}, log, maxRssKiB) == 0);
    const std::string printed = readText(log);
    CAPTURE(printed);
    CHECK(printed.find("mtx_huge_declared_size.mtx: valid Hemirad form factors") != std::string::npos);
    CHECK(printed.find("patches 268435456, computed rows 268435456 (skipped 0)") != std::string::npos);
    CHECK(printed.find("nonzeros 0") != std::string::npos);
    CHECK(maxRssKiB < 200 * 1024);
    // What the reader decides, in process: the description comes from the entries (no row arrays),
    // and a load for a scene of another size is refused at the size line, naming the file.
    const FormFactorFileInfo info = readFormFactorInfo(path);
    CHECK(info.size == (1u << 28));
    CHECK(info.nonZeros == 0);
    CHECK(info.computedRows == (1u << 28));
    REQUIRE(info.mtxRows.has_value());
    CHECK(info.mtxRows->rowsWithEntries == 0);
    CHECK(info.mtxRows->min == 0.0);
    CHECK_FALSE(info.mtxRows->provenance.sceneHashKnown);
    CHECK_THROWS_WITH_AS(loadFormFactors(path, 20),
                         doctest::Contains("mtx_huge_declared_size.mtx: F has 268435456 patches but the scene has 20"), Error);
}

TEST_CASE("Malformed corpus: every file of the corpus is covered by a test above") {
    // A new corpus file needs its expected message here too.
    std::size_t obj = 0, stl = 0, mtx = 0;
    for (const auto& entry : std::filesystem::directory_iterator(sourcePath("tests/data/malformed"))) {
        obj += entry.path().extension() == ".obj";
        stl += entry.path().extension() == ".stl";
        mtx += entry.path().extension() == ".mtx";
    }
    CHECK(obj == 29);
    CHECK(stl == 8);
    CHECK(mtx == 1);
}
