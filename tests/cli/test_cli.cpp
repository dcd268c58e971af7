// The `hemirad` command end to end: exit statuses, messages, files, and F reuse across material edits.
#include "support.hpp"

#include "preprocess/backend_registry.hpp"
#include "solve/solver_registry.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <sys/wait.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

using Result = CommandResult;

Result runHemirad(const std::string& arguments) { return runCommand(std::string(HEMIRAD_BINARY) + " " + arguments + " 2>&1"); }

std::string scene(const char* name) { return sourcePath(std::string("scenes/") + name); }

/// Copies an OBJ and its MTL into `dir`, with `edit` applied to the MTL text.
std::string copyScene(const std::filesystem::path& dir, const char* name, const std::string& from,
                      const std::string& to) {
    const std::string base = std::string(name);
    std::filesystem::copy_file(scene((base + ".obj").c_str()), dir / (base + ".obj"),
                               std::filesystem::copy_options::overwrite_existing);
    std::ifstream in(scene((base + ".mtl").c_str()));
    std::string mtl((std::istreambuf_iterator<char>(in)), {});
    if (!from.empty()) {
        const std::size_t at = mtl.find(from);
        REQUIRE(at != std::string::npos);
        mtl.replace(at, from.size(), to);
    }
    writeFile(dir / (base + ".mtl"), mtl);
    return (dir / (base + ".obj")).string();
}

}  // namespace

TEST_CASE("Usage errors exit with status 2 and say what is wrong") {
    Result r = runHemirad("");
    CHECK(r.status == 2);
    CHECK(r.output.find("hemirad: error: no command given") != std::string::npos);
    r = runHemirad("frobnicate x.obj");
    CHECK(r.status == 2);
    CHECK(r.output.find("unknown command 'frobnicate'") != std::string::npos);
    r = runHemirad("solve " + scene("unit_cube.obj") + " -o x.csv --bogus");
    CHECK(r.status == 2);
    CHECK(r.output.find("unknown option '--bogus'") != std::string::npos);
    r = runHemirad("solve " + scene("unit_cube.obj") + " -o x.csv --samples");
    CHECK(r.status == 2);
    CHECK(r.output.find("'--samples' needs a value") != std::string::npos);
    r = runHemirad("solve " + scene("unit_cube.obj") + " -o x.csv --samples 0");
    CHECK(r.status == 2);
    CHECK(r.output.find("--samples 0 is out of range") != std::string::npos);
    r = runHemirad("formfactors " + scene("unit_cube.obj") + " -o F.hff --size 10x10");
    CHECK(r.status == 2);
    CHECK(r.output.find("'--size' does not apply to 'formfactors'") != std::string::npos);
    r = runHemirad("solve " + scene("unit_cube.obj") + " -o x.csv --solver magic");
    CHECK(r.status == 2);
    CHECK(r.output.find("unknown solver 'magic'") != std::string::npos);
    r = runHemirad("formfactors " + scene("unit_cube.obj") + " -o F.hff --drop-below 0");
    CHECK(r.status == 2);
    CHECK(r.output.find("--drop-below 0 is out of range") != std::string::npos);
    r = runHemirad("bench " + scene("unit_cube.obj") + " -o x.csv --drop-below 1e-3");
    CHECK(r.status == 2);
    CHECK(r.output.find("'--drop-below' does not apply to 'bench'") != std::string::npos);
    CHECK(runHemirad("help").status == 0);
}

TEST_CASE("Every back-end flag is a usage error with a back end that does not take it, before any work") {
    // Each option of each back end, given to every other back end: exit 2, naming the flag and the
    // method (pbrt-v4 and Mitsuba treat unused parameters so), before the scene is even read.
    const std::string missing = "/nonexistent/scene.obj";
    int pairs = 0;
    for (const BackendDescriptor* owner : formFactorBackends())
        for (const BackendOption& option : owner->options)
            for (const BackendDescriptor* other : formFactorBackends()) {
                if (other->option(option.flag) || !other->notBuilt.empty()) continue;
                CAPTURE(option.flag);
                CAPTURE(other->name);
                const std::string value = option.kind == OptionKind::Switch ? "" : " " + option.get(defaultSettings(owner->name));
                const Result r = runHemirad("formfactors " + missing + " -o F.hff --method " + other->name + " " + option.flag + value);
                CHECK(r.status == 2);
                CHECK(r.output.find("option '" + option.flag + "' does not apply to --method " + other->name) !=
                      std::string::npos);
                ++pairs;
            }
    // --method is checked while parsing, also before the scene is read.
    Result r = runHemirad("formfactors " + missing + " -o F.hff --method raytrace");
    CHECK(r.status == 2);
    CHECK(r.output.find("unknown --method 'raytrace' (hemisphere, hemicube)") != std::string::npos);
    // bench compares --methods; --method is not its flag.
    r = runHemirad("bench " + missing + " -o b.csv --method hemisphere");
    CHECK(r.status == 2);
    CHECK(r.output.find("'--method' does not apply to 'bench' (use --methods)") != std::string::npos);
    // Back-end flags do not apply to commands that compute no F.
    r = runHemirad("info F.hff --samples 96");
    CHECK(r.status == 2);
    CHECK(r.output.find("'--samples' does not apply to 'info'") != std::string::npos);

    if (!findBackend("hemicube").notBuilt.empty()) {
        // A build configured with HEMIRAD_WITH_OPENGL=OFF lists the hemicube and says how to get it.
        r = runHemirad("formfactors " + missing + " -o F.hff --method hemicube");
        CHECK(r.status == 2);
        CHECK(r.output.find("--method hemicube is not built: configure with -DHEMIRAD_WITH_OPENGL=ON") != std::string::npos);
        CHECK(runHemirad("help").output.find("hemicube (--method hemicube): OpenGL hemicubes (Cohen & Greenberg) -- not built") !=
              std::string::npos);
        return;
    }
    CHECK(pairs >= 11);  // hemisphere: 6 flags, hemicube: 5
    // Flags given before --method count for the chosen back end too.
    r = runHemirad("formfactors " + missing + " -o F.hff --samples 3072 --method hemicube");
    CHECK(r.status == 2);
    CHECK(r.output.find("option '--samples' does not apply to --method hemicube") != std::string::npos);
    // A flag no listed back end takes is an error for bench.
    r = runHemirad("bench " + missing + " -o b.csv --methods hemisphere --resolution 64");
    CHECK(r.status == 2);
    CHECK(r.output.find("'--resolution' does not apply to any of the --methods") != std::string::npos);
}

TEST_CASE("Iteration flags are usage errors for a solver that does not iterate") {
    const std::string missing = "/nonexistent/scene.obj";
    for (const SolverDescriptor* solver : solverRegistry())
        for (const char* flag : {"--tolerance 1e-8", "--max-iterations 50"}) {
            CAPTURE(solver->name);
            CAPTURE(flag);
            const Result r = runHemirad("solve " + missing + " -o B.csv --solver " + solver->name + " " + flag);
            const std::string name = std::string(flag).substr(0, std::string(flag).find(' '));
            if (std::find(solver->flags.begin(), solver->flags.end(), name) == solver->flags.end()) {
                CHECK(r.status == 2);
                CHECK(r.output.find("option '" + name + "' does not apply to --solver " + solver->name) != std::string::npos);
            } else {
                CHECK(r.status == 1);  // accepted: the missing scene is what fails
                CHECK(r.output.find("scene.obj: cannot open") != std::string::npos);
            }
        }
    CHECK(findSolver("lu").flags.empty());
    CHECK(findSolver("gauss-seidel").flags.size() == 2);
}

TEST_CASE("The usage text lists every back end and its flags from the registry") {
    const Result r = runHemirad("help");
    REQUIRE(r.status == 0);
    for (const BackendDescriptor* d : formFactorBackends()) {
        CHECK(r.output.find(d->name + " (--method " + d->name + "): " + d->summary) != std::string::npos);
        for (const BackendOption& option : d->options) CHECK(r.output.find("  " + option.flag) != std::string::npos);
    }
}

TEST_CASE("Runtime errors exit with status 1 and name the file") {
    const Result r = runHemirad("solve /nonexistent/box.obj -o x.csv");
    CHECK(r.status == 1);
    CHECK(r.output.find("hemirad: error: /nonexistent/box.obj: cannot open") != std::string::npos);
}

TEST_CASE("solve writes the documented CSV, the unit cube's floor emits and everything is finite") {
    const auto dir = tempDir("cli-solve");
    const std::string csv = (dir / "B.csv").string();
    const Result r = runHemirad("solve " + scene("unit_cube.obj") + " -o " + csv + " --samples 768 --origins 16 --quiet");
    REQUIRE(r.status == 0);
    std::ifstream in(csv);
    std::string header;
    std::getline(in, header);
    CHECK(header == "patch,area,E_r,E_g,E_b,rho_r,rho_g,rho_b,specular,B_r,B_g,B_b");
    int rows = 0;
    std::string line;
    double floorB = 0, ceilingB = 0;
    while (std::getline(in, line)) {
        double v[12];
        REQUIRE(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3],
                            &v[4], &v[5], &v[6], &v[7], &v[8], &v[9], &v[10], &v[11]) == 12);
        if (rows == 0) floorB = v[9];
        if (rows == 1) ceilingB = v[9];
        ++rows;
    }
    CHECK(rows == 6);
    // physics.md §5, rho = 0.5: floor 1.0909, ceiling 0.18175 (estimated F: 1% on the ceiling).
    CHECK(floorB == doctest::Approx(1.0909090981).epsilon(2e-3));
    CHECK(ceilingB == doctest::Approx(0.1817458261).epsilon(1e-2));
}

TEST_CASE("A stored F is reused after emission and diffuse edits, and refused after a mirror edit") {
    const auto dir = tempDir("cli-reuse");
    const std::string ff = (dir / "F.hff").string();
    const std::string obj = copyScene(dir, "cornell_mirror", "", "");
    const std::string common = " -o " + (dir / "B.csv").string() + " --samples 96 --subdivide 150 --ff " + ff;
    Result r = runHemirad("solve " + obj + common);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("form factors: stored in") != std::string::npos);
    CHECK(std::filesystem::exists(ff));

    Result info = runHemirad("info " + ff);
    CHECK(info.status == 0);
    CHECK(info.output.find("valid Hemirad form factors") != std::string::npos);
    CHECK(info.output.find("method = hemisphere") != std::string::npos);

    copyScene(dir, "cornell_mirror", "Ke 17 11.8 4", "Ke 5 5 5");  // emission edit
    r = runHemirad("solve " + obj + common);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("form factors: reused") != std::string::npos);
    CHECK(r.output.find("rays") == std::string::npos);  // nothing was cast

    copyScene(dir, "cornell_mirror", "Ks 0.9 0.9 0.9", "Ks 0.5 0.5 0.5");  // mirror edit
    r = runHemirad("solve " + obj + common);
    CHECK(r.status == 1);
    CHECK(r.output.find("computed for another scene") != std::string::npos);
    r = runHemirad("solve " + obj + common + " --recompute-ff");
    CHECK(r.status == 0);
}

TEST_CASE("render writes a PNG of the Cornell box and prints a timing table") {
    const auto dir = tempDir("cli-render");
    const std::string png = (dir / "box.png").string();
    const Result r = runHemirad("render " + scene("cornell_box.obj") + " -o " + png +
                             " --samples 96 --subdivide 100 --size 64x48 --spp 1");
    REQUIRE(r.status == 0);
    CHECK(r.output.find("total") != std::string::npos);
    std::ifstream in(png, std::ios::binary);
    unsigned char head[24] = {};
    in.read(reinterpret_cast<char*>(head), 24);
    CHECK(head[1] == 'P');
    CHECK(head[2] == 'N');
    CHECK(head[3] == 'G');
    const unsigned width = head[16] << 24 | head[17] << 16 | head[18] << 8 | head[19];
    const unsigned height = head[20] << 24 | head[21] << 16 | head[22] << 8 | head[23];
    CHECK(width == 64);
    CHECK(height == 48);
}

TEST_CASE("Ctrl-C leaves the previous output intact and no temporary files") {
    const auto dir = tempDir("cli-interrupt");
    const std::string ff = (dir / "F.hff").string();
    REQUIRE(runHemirad("formfactors " + scene("unit_cube.obj") + " -o " + ff + " --samples 96 --quiet").status == 0);
    std::ifstream before(ff, std::ios::binary);
    const std::string original((std::istreambuf_iterator<char>(before)), {});
    // A computation of several seconds, interrupted after one.
    const Result r = runCommand("(" + std::string(HEMIRAD_BINARY) + " formfactors " + scene("unit_cube.obj") + " -o " + ff +
                                " --subdivide 0.02 --samples 3072 --origins 16 --estimator rays --quiet 2>&1 & pid=$!; sleep 1; "
                                "kill -INT $pid; wait $pid)");
    CHECK(r.status == 130);
    CHECK(r.output.find("interrupted; no partial output was written") != std::string::npos);
    std::ifstream after(ff, std::ios::binary);
    CHECK(std::string((std::istreambuf_iterator<char>(after)), {}) == original);
    int files = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
    CHECK(files == 1);
}
