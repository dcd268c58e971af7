// The build without Embree (HEMIRAD_WITH_EMBREE=OFF; make test-without-embree): the hemisphere is
// listed and refused with the way to get it, the hemicube is the default and computes and solves,
// and everything that casts rays (render, --mirrors rays, a RayScene) says it is not built before
// any work is done.
#include "support.hpp"

#include "engine/error.hpp"
#include "preprocess/backend_registry.hpp"
#include "rays/ray_scene.hpp"

#include <doctest/doctest.h>

#ifdef HEMIRAD_GUI_BINARY
#include "ui/gui_run.hpp"
#endif

using namespace hemirad;
using namespace hemirad::test;

namespace {

CommandResult runHemirad(const std::string& arguments) {
    return runCommand(std::string(HEMIRAD_BINARY) + " " + arguments + " 2>&1");
}

std::string scene(const char* name) { return sourcePath(std::string("scenes/") + name); }

constexpr const char* kHow = "not built: configure with -DHEMIRAD_WITH_EMBREE=ON (needs libembree-dev)";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("Without Embree the hemisphere is listed as not built and the hemicube is the default") {
    CHECK(rayCastingNotBuilt() == kHow);
    const BackendDescriptor& hemisphere = findBackend("hemisphere");
    CHECK(hemisphere.notBuilt == kHow);
    CHECK(defaultBackend().name == "hemicube");
    CHECK(defaultBackend().notBuilt.empty());
    const std::string refused = std::string("--method hemisphere is ") + kHow;
    CHECK_THROWS_WITH_AS(defaultSettings("hemisphere"), doctest::Contains(refused.c_str()), Error);

    const CommandResult help = runHemirad("help");
    CHECK(help.status == 0);
    CHECK(contains(help.output, "--method NAME          the form-factor back end: hemisphere, hemicube (default)"));
    CHECK(contains(help.output, std::string("hemisphere (--method hemisphere): Embree rays along Beckers directions, or "
                                            "Lambert's exact factors with shadow rays -- ") + kHow));

    const auto dir = tempDir("no-embree-method");
    const CommandResult r = runHemirad("formfactors " + scene("unit_cube.obj") + " -o " + (dir / "F.hff").string() +
                                       " --method hemisphere");
    CHECK(r.status == 2);
    CHECK(contains(r.output, std::string("--method hemisphere is ") + kHow));
    CHECK(!std::filesystem::exists(dir / "F.hff"));
}

TEST_CASE("Without Embree hemirad computes F with the hemicube, mirrors by portals, and solves") {
    const auto dir = tempDir("no-embree-solve");
    const std::string F = (dir / "F.hff").string(), B = (dir / "B.csv").string();
    CommandResult r = runHemirad("solve " + scene("cornell_box.obj") + " --subdivide 150 --resolution 64 --ff " + F +
                                 " -o " + B);
    REQUIRE(r.status == 0);
    r = runHemirad("info " + F);
    CHECK(r.status == 0);
    CHECK(contains(r.output, "method = hemicube"));
    CHECK(contains(r.output, "resolution = 64"));
    const std::string csv = readText(B);
    CHECK(std::count(csv.begin(), csv.end(), '\n') > 20);  // a header and a row per patch

    // The mirror pair by stencil portals, the default: no rays needed.
    r = runHemirad("formfactors " + scene("mirror_pair.obj") + " --resolution 64 -o " + (dir / "M.hff").string());
    CHECK(r.status == 0);
    CHECK(contains(runHemirad("info " + (dir / "M.hff").string()).output, "mirrors = portals"));
}

TEST_CASE("Without Embree whatever casts rays is refused before any work, saying how to get it") {
    const auto dir = tempDir("no-embree-rays");
    CommandResult r = runHemirad("render " + scene("cornell_box.obj") + " -o " + (dir / "image.png").string());
    CHECK(r.status == 2);
    CHECK(contains(r.output, std::string("'render' traces rays with Embree, which is ") + kHow));
    CHECK(!std::filesystem::exists(dir / "image.png"));

    r = runHemirad("formfactors " + scene("mirror_pair.obj") + " --mirrors rays -o " + (dir / "M.hff").string());
    CHECK(r.status == 2);
    CHECK(contains(r.output, std::string("--mirrors rays casts Embree rays, which are ") + kHow));
    CHECK(!std::filesystem::exists(dir / "M.hff"));

    MethodSettings cube = defaultSettings("hemicube");
    setBackendOption(cube, "--mirrors", "rays");
    const Scene s = bundledScene("mirror_pair.obj");
    CHECK_THROWS_WITH_AS(makeBackend(cube), doctest::Contains("--mirrors rays casts Embree rays"), Error);
    const std::string noRays = std::string("ray casting (Embree) is ") + kHow;
    CHECK_THROWS_WITH_AS(RayScene{s}, doctest::Contains(noRays.c_str()), Error);
}

#ifdef HEMIRAD_GUI_BINARY
TEST_CASE("hemirad-gui without Embree: the hemicube by default, the inspector says it is not built") {
    // A selected patch opens the Selection panel (over the green wall), whose inspector would cast rays.
    const std::string log = runGuiAndCheckPicture("no-embree-gui", "--resolution 32 --select 0", false);
    CHECK(contains(log, "form factors: hemicube"));
    CHECK(!contains(log, "error"));
    const auto dir = tempDir("no-embree-gui-flags");
    const std::string out = (dir / "out.txt").string();
    const int s = std::system((std::string(HEMIRAD_GUI_BINARY) + " --method hemisphere > " + out + " 2>&1").c_str());
    CHECK(WIFEXITED(s));
    CHECK(WEXITSTATUS(s) == 2);
    CHECK(contains(readText(out), std::string("--method hemisphere is ") + kHow));
}
#endif
