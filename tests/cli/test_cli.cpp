// The `hemirad` command end to end: exit statuses, messages, files, and F reuse across material edits.
#include "stl_files.hpp"
#include "support.hpp"

#include "cli/options.hpp"
#include "engine/obj_writer.hpp"
#include "engine/subdivide.hpp"
#include "preprocess/backend_registry.hpp"
#include "solve/solver_registry.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
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

/// What an .hff file says about F itself: N, nnz, scene hash and the arrays (src/engine/
/// form_factor_file.cpp), without the parameter text and the checksum that covers it.
std::string hffMatrix(const std::string& bytes) {
    REQUIRE(bytes.size() >= 48);
    std::uint32_t parameterBytes = 0;
    std::memcpy(&parameterBytes, bytes.data() + 12, 4);
    REQUIRE(bytes.size() >= 48 + parameterBytes);
    return bytes.substr(16, 24) + bytes.substr(40 + parameterBytes, bytes.size() - 48 - parameterBytes);
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
    r = runHemirad("render " + scene("unit_cube.obj") + " -o x.png --camera 0,0,1,0,0,0,200");
    CHECK(r.status == 2);
    CHECK(r.output.find("--camera: camera field of view 200 is outside (0, 180) degrees") != std::string::npos);
    r = runHemirad("render " + scene("unit_cube.obj") + " -o x.png --camera 1,2,3,1,2,3,40");
    CHECK(r.status == 2);
    CHECK(r.output.find("--camera: camera eye and target coincide at (1, 2, 3)") != std::string::npos);
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

namespace {

/// The bundled Cornell box with its tall block alone subdivided at 30 mm, saved as DIR/fine.obj.
std::string tallBlockFiner(const std::filesystem::path& dir) {
    const Scene coarse = bundledScene("cornell_box.obj");
    std::vector<double> byObject(coarse.objects.size(), 0.0);
    const auto tall = std::find(coarse.objects.begin(), coarse.objects.end(), "tall_block");
    REQUIRE(tall != coarse.objects.end());
    byObject[std::size_t(tall - coarse.objects.begin())] = 30.0;
    const std::string fine = (dir / "fine.obj").string();
    saveObj(subdivide(coarse, byObject), fine);
    return fine;
}

}  // namespace

TEST_CASE("The report's lost power is area-weighted and says so: meshing one block finer leaves it where it was") {
    const auto dir = tempDir("lost-area");
    const std::string fine = tallBlockFiner(dir);
    const auto lostPercent = [&](const std::string& scene, const std::string& method) {
        const Result r = runCommand(std::string(HEMIRAD_BINARY) + " formfactors " + scene + " " + method + " -o " +
                                    (dir / "F.hff").string() + " 2>&1");
        INFO(r.output);
        REQUIRE(r.status == 0);
        const std::size_t at = r.output.find("% of the power");
        REQUIRE(at != std::string::npos);
        CHECK(r.output.find("area-weighted", at) < r.output.find('\n', at));
        const std::size_t start = r.output.find_last_of(" ;", at) + 1;
        return std::stod(r.output.substr(start, at - start));
    };
    for (const std::string method : {"--method hemisphere --estimator analytic", "--method hemisphere --estimator rays --samples 1024"}) {
        CAPTURE(method);
        const double before = lostPercent(sourcePath("scenes/cornell_box.obj"), method), after = lostPercent(fine, method);
        CHECK(before > 10.0);  // the open front
        CHECK(std::abs(after - before) < 1.0);  // the mean over rows went from 18.1 % to 11.45 %
    }
}

TEST_CASE("The report counts the convex solids whose far faces cast no shadow: the Cornell box's two blocks, however finely meshed") {
    const auto dir = tempDir("solids-report");
    const std::string fine = tallBlockFiner(dir);
    const auto solidsLine = [&](const std::string& scene) {
        const Result r = runCommand(std::string(HEMIRAD_BINARY) + " formfactors " + scene +
                                    " --method hemisphere --estimator analytic -o " + (dir / "F.hff").string() + " 2>&1");
        INFO(r.output);
        REQUIRE(r.status == 0);
        const std::size_t at = r.output.find("convex solids among the patches that can obstruct");
        REQUIRE(at != std::string::npos);
        const std::size_t colon = r.output.find("): ", at);
        return r.output.substr(colon + 3, r.output.find('\n', colon) - colon - 3);
    };
    CHECK(solidsLine(sourcePath("scenes/cornell_box.obj")) == "2 (10 faces)");  // two lidless blocks on the floor
    const std::string finer = solidsLine(fine);
    CHECK(finer.rfind("2 (", 0) == 0);
    CHECK(finer != "2 (10 faces)");
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

TEST_CASE("An error or warning or report line reaches its stream in one write (mpirun cannot split it)") {
    // issue 35 #20: "hemirad: error: " and the message were separate writes, which mpirun forwarded
    // apart. A preloaded probe logs each write(2) with its whole text.
    const auto dir = tempDir("cli-one-write");
    const auto log = dir / "writes.log";
    writeFile(dir / "flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");  // face 2: no area
    auto run = [&](const std::string& arguments) {
        std::filesystem::remove(log);
        const Result r = runCommand("cd '" + dir.string() + "' && " + logWrites(log.string()) + HEMIRAD_BINARY + " " +
                                    arguments + " 2>&1");
        return std::make_pair(r, loggedWrites(log));
    };
    auto [missing, missingWrites] = run("formfactors missing.obj -o F.hff");
    CHECK(missing.status == 1);
    CHECK_MESSAGE(wroteWhole(missingWrites, 2, "hemirad: error: missing.obj: cannot open: No such file or directory\n"),
                  describeWrites(missingWrites));
    auto [usage, usageWrites] = run("formfactors flat.obj -o F.hff --bogus");
    CHECK(usage.status == 2);
    CHECK_MESSAGE(wroteWhole(usageWrites, 2, "hemirad: error: unknown option '--bogus'\n(run 'hemirad help' for usage)\n"),
                  describeWrites(usageWrites));
    auto [warned, warnedWrites] = run("formfactors flat.obj -o F.hff");
    REQUIRE_MESSAGE(warned.status == 0, warned.output);
    const std::string warning = warned.output.substr(warned.output.find("hemirad: warning: "));
    CHECK_MESSAGE(wroteWhole(warnedWrites, 2, warning.substr(0, warning.find('\n') + 1)), describeWrites(warnedWrites));
    const std::size_t wrote = warned.output.find("wrote F.hff");
    REQUIRE(wrote != std::string::npos);
    const std::string line = warned.output.substr(wrote, warned.output.find('\n', wrote) + 1 - wrote);
    CHECK_MESSAGE(wroteWhole(warnedWrites, 1, line), describeWrites(warnedWrites));
}

TEST_CASE("The options hash changes with every option that changes the work and not with --threads") {
    // MPI ranks agree on it (issue 35 #16): a rank given other options computed or solved something else.
    auto hashOf = [](const std::vector<std::string>& words) {
        std::vector<const char*> argv = {"hemirad"};
        for (const std::string& w : words) argv.push_back(w.c_str());
        return optionsHash(parseOptions(int(argv.size()), argv.data()));
    };
    const std::vector<std::string> base = {"solve", "box.obj", "-o", "B.csv"};
    auto with = [&](const std::vector<std::string>& extra) {
        std::vector<std::string> words = base;
        words.insert(words.end(), extra.begin(), extra.end());
        return hashOf(words);
    };
    const std::uint64_t h = hashOf(base);
    CHECK(hashOf(base) == h);
    CHECK(with({"--threads", "3"}) == h);
    const std::vector<std::vector<std::string>> changes = {
        {"--samples", "512"}, {"--max-depth", "2"},         {"--solver", "jacobi"},      {"--tolerance", "1e-9"},
        {"--subdivide", "80"}, {"--materials", "m.mtl"},   {"--drop-below", "0.01"},   {"--enforce-reciprocity"},
        {"--ff", "F.hff"},     {"--quiet"},                 {"--objects", "objects.csv"}, {"--sky-view"}};
    for (const auto& extra : changes) {
        CAPTURE(extra[0]);
        CHECK(with(extra) != h);
    }
    CHECK(hashOf({"solve", "other.obj", "-o", "B.csv"}) != h);
    CHECK(hashOf({"solve", "box.obj", "-o", "C.csv"}) != h);
    CHECK(hashOf({"formfactors", "box.obj", "-o", "B.mtx"}) != hashOf({"formfactors", "box.obj", "-o", "B.hff"}));
    CHECK(hashOf({"help"}) == hashOf({"help"}));
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

namespace {

/// A computation of several seconds over an F written before into a folder of its own, sent
/// `signal` (kill's name for it) after one second. `kept`: F as before and alone in its folder.
struct Killed {
    Result run;
    bool kept = false;
};
Killed killComputation(const std::string& folder, const std::string& signal) {
    const auto dir = tempDir(folder);
    const std::string ff = (dir / "F.hff").string();
    REQUIRE(runHemirad("formfactors " + scene("unit_cube.obj") + " -o " + ff + " --samples 96 --quiet").status == 0);
    auto read = [&ff] {
        std::ifstream in(ff, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), {});
    };
    const std::string original = read();
    Killed killed;
    killed.run = runCommand("(" + std::string(HEMIRAD_BINARY) + " formfactors " + scene("unit_cube.obj") + " -o " + ff +
                            " --subdivide 0.02 --samples 3072 --origins 16 --estimator rays --quiet 2>&1 & pid=$!; sleep 1; "
                            "kill -" + signal + " $pid; wait $pid)");
    int files = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
    killed.kept = read() == original && files == 1;
    return killed;
}

}  // namespace

TEST_CASE("Ctrl-C leaves the previous output intact and no temporary files") {
    const Killed r = killComputation("cli-interrupt", "INT");
    CHECK(r.run.status == 130);
    CHECK(r.run.output.find("interrupted; no partial output was written") != std::string::npos);
    CHECK(r.kept);
}

#ifndef __SANITIZE_ADDRESS__  // the sanitizers' own handlers report fatal signals there
TEST_CASE("A fatal signal is reported as an internal error with the stack, leaves the previous output, and kills as before") {
    // As from a fault in a driver: SIGSEGV in the middle of a computation.
    const Killed r = killComputation("cli-fatal-signal", "SEGV");
    CHECK(r.run.status == 128 + 11);  // still dies of the signal (a core where enabled)
    CHECK(r.run.output.find("hemirad: internal error: segmentation fault (SIGSEGV); no partial output was written. Stack:") !=
          std::string::npos);
    CHECK(r.run.output.find("hemirad(") != std::string::npos);  // a frame of the program, for addr2line
    CHECK(r.run.output.find("Please report it with the command line") != std::string::npos);
    CHECK(r.kept);
}
#endif

TEST_CASE("formfactors gives the same F bit for bit from an STL with --materials as from the OBJ of its triangles") {
    const auto dir = tempDir("cli-stl");
    // A closed box of 12 triangles with float-exact corners (binary STL stores float32): floor, walls.
    const std::vector<StlTriangle> t = stlTriangles(boxScene(Vec3(0, 0, 0), Vec3(1.5, 1, 0.75)));
    REQUIRE(t.size() == 12);
    const std::vector<StlSolid> solids = {{"floor", {t[4], t[5]}},
                                          {"walls", {t[0], t[1], t[2], t[3], t[6], t[7], t[8], t[9], t[10], t[11]}}};
    const std::string materials = "newmtl floor\nKd 0.3\nKe 1 1 1\nnewmtl walls\nKd 0.6 0.5 0.4\n";
    writeFile(dir / "box.mtl", materials);
    const std::string obj = writeFile(dir / "box.obj", objText(solids, "box.mtl"));
    const std::string ascii = writeFile(dir / "box.stl", asciiStl(solids));
    const std::string byName = writeFile(dir / "by_name.mtl", materials);
    // A binary STL is one object: its material comes as 'default'.
    writeFile(dir / "grey.mtl", "newmtl grey\nKd 0.5\n");
    const std::string greyObj = writeFile(dir / "grey.obj", objText({{"grey", t}}, "grey.mtl"));
    const std::string binary = writeFile(dir / "grey_binary.stl", binaryStl(t));
    const std::string fallback = writeFile(dir / "fallback.mtl", "newmtl default\nKd 0.5\n");

    auto formFactors = [&](const std::string& input, const std::string& extra, const std::string& out) {
        const Result r = runHemirad("formfactors " + input + extra + " -o " + (dir / out).string() + " --threads 1");
        CAPTURE(r.output);
        CHECK(r.status == 0);
        CHECK(r.output.find("warning") == std::string::npos);
        return readText(dir / out);
    };
    const std::string fromObj = formFactors(obj, "", "obj.hff");
    const std::string fromAscii = formFactors(ascii, " --materials " + byName, "ascii.hff");
    REQUIRE(fromObj.size() > 48);
    CHECK(hffMatrix(fromAscii) == hffMatrix(fromObj));
    const std::string fromGreyObj = formFactors(greyObj, "", "grey_obj.hff");
    const std::string fromBinary = formFactors(binary, " --materials " + fallback, "binary.hff");
    CHECK(hffMatrix(fromBinary) == hffMatrix(fromGreyObj));
    // The same geometry and mirrors: one scene hash, so each route's F serves the other's --ff.
    const Result reuse = runHemirad("solve " + obj + " --ff " + (dir / "ascii.hff").string() + " -o " +
                                    (dir / "B.csv").string());
    CHECK(reuse.status == 0);
    CHECK(reuse.output.find("form factors: reused") != std::string::npos);
}

TEST_CASE("--materials is in the help, taken by the commands that load a scene and refused by info") {
    const Result help = runHemirad("help");
    CHECK(help.output.find("--materials FILE.mtl   (formfactors, solve, render, subdivide, check, bench) materials by object name") !=
          std::string::npos);
    CHECK(help.output.find("SCENE is an .obj (with the .mtl libraries it names) or an .stl") != std::string::npos);
    const Result info = runHemirad("info F.hff --materials m.mtl");
    CHECK(info.status == 2);
    CHECK(info.output.find("option '--materials' does not apply to 'info'") != std::string::npos);
    const auto dir = tempDir("cli-stl-subdivide");
    const std::vector<StlTriangle> t = stlTriangles(unitCube());
    const std::string stl = writeFile(dir / "cube.stl", asciiStl({{"floor", {t[0], t[1]}}, {"rest", {t[2], t[3]}}}));
    const std::string mtl = writeFile(dir / "m.mtl", "newmtl floor\nKe 2 2 2\nnewmtl flor\n");
    const Result r = runHemirad("subdivide " + stl + " --materials " + mtl + " --max-edge 0.5 -o " + (dir / "out.obj").string());
    CHECK(r.status == 0);
    CHECK(r.output.find("1 material(s) name no object of " + stl + ": 'flor'") != std::string::npos);
    CHECK(r.output.find("1 object(s) match no material, and there is no 'default': 'rest'") != std::string::npos);
    CHECK(readText(dir / "out.mtl").find("newmtl floor\n") != std::string::npos);
    CHECK(readText(dir / "out.obj").find("o floor\n") != std::string::npos);
}

namespace {

/// Three columns from `first` on (E: 2, B: 9) per patch from a solve CSV.
std::vector<std::array<double, 3>> csvColumns(const std::filesystem::path& path, int first) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);  // header
    std::vector<std::array<double, 3>> out;
    while (std::getline(in, line)) {
        double v[12];
        REQUIRE(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3],
                            &v[4], &v[5], &v[6], &v[7], &v[8], &v[9], &v[10], &v[11]) == 12);
        out.push_back({v[first], v[first + 1], v[first + 2]});
    }
    return out;
}

/// B_r, B_g, B_b per patch from a solve CSV.
std::vector<std::array<double, 3>> csvRadiosity(const std::filesystem::path& path) { return csvColumns(path, 9); }

std::string blackPair() { return sourcePath("tests/data/black/black_pair.obj"); }

}  // namespace

TEST_CASE("solve --ff --drop-below drops once: the stored F is reused as stored, the same nonzeros and B every time") {
    // issue 35 #2: the dropped F was stored, then dropped again on each reuse.
    const auto dir = tempDir("cli-drop-reuse");
    const std::string ff = (dir / "F.hff").string();
    const std::string common = "solve " + scene("cornell_box.obj") + " --subdivide 150 --ff " + ff + " --drop-below 0.01 -o ";
    const Result first = runHemirad(common + (dir / "B1.csv").string());
    REQUIRE_MESSAGE(first.status == 0, first.output);
    CHECK(first.output.find("pairs with both entries below 0.01 dropped") != std::string::npos);
    const std::string stored = readText(ff);
    const Result info = runHemirad("info " + ff);
    CHECK(info.output.find("sparsified = pairs below 0.01 dropped") != std::string::npos);
    for (const char* name : {"B2.csv", "B3.csv"}) {
        const Result again = runHemirad(common + (dir / name).string());
        REQUIRE_MESSAGE(again.status == 0, again.output);
        CHECK(again.output.find("form factors: reused") != std::string::npos);
        CHECK(again.output.find("dropped:") == std::string::npos);  // no second drop
        CHECK(readText(ff) == stored);
        CHECK(readText(dir / name) == readText(dir / "B1.csv"));
    }
    // A stored F without the drop gets it on each reuse (the file stays as computed): the same B each time.
    const std::string plain = (dir / "plain.hff").string();
    REQUIRE(runHemirad("formfactors " + scene("cornell_box.obj") + " --subdivide 150 -o " + plain + " --quiet").status == 0);
    const std::string reuse = "solve " + scene("cornell_box.obj") + " --subdivide 150 --ff " + plain + " --drop-below 0.01 -o ";
    const Result p1 = runHemirad(reuse + (dir / "P1.csv").string());
    const Result p2 = runHemirad(reuse + (dir / "P2.csv").string());
    REQUIRE(p1.status == 0);
    REQUIRE(p2.status == 0);
    CHECK(p2.output.find("pairs with both entries below 0.01 dropped") != std::string::npos);
    CHECK(readText(dir / "P1.csv") == readText(dir / "P2.csv"));
    CHECK(readText(dir / "P1.csv") == readText(dir / "B1.csv"));
}

TEST_CASE("A scene of black patches needs no row of F: solve gives B = E, its F files read back and serve --ff") {
    // issue 35 #6 and #18: "F has 0 rows but the scene has 2 patches"; F files of N = 0.
    const auto dir = tempDir("cli-black");
    Result r = runHemirad("solve " + blackPair() + " -o " + (dir / "B.csv").string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    std::vector<std::array<double, 3>> B = csvRadiosity(dir / "B.csv");
    REQUIRE(B.size() == 2);
    CHECK(B[0] == std::array<double, 3>{1, 2, 3});
    CHECK(B[1] == std::array<double, 3>{0, 0, 0});
    for (const char* name : {"F.hff", "F.mtx"}) {
        CAPTURE(name);
        const std::string ff = (dir / name).string();
        r = runHemirad("formfactors " + blackPair() + " -o " + ff);
        REQUIRE_MESSAGE(r.status == 0, r.output);
        const Result info = runHemirad("info " + ff);
        CHECK_MESSAGE(info.status == 0, info.output);
        CHECK(info.output.find("patches 2, computed rows 0 (skipped 2)") != std::string::npos);
        r = runHemirad("solve " + blackPair() + " --ff " + ff + " -o " + (dir / "B2.csv").string());
        CHECK_MESSAGE(r.status == 0, r.output);
        CHECK(r.output.find("form factors: reused " + ff) != std::string::npos);
        CHECK(readText(dir / "B2.csv") == readText(dir / "B.csv"));
    }
    // --all-rows computes the black rows too; the help says which rows are computed by default.
    r = runHemirad("formfactors " + blackPair() + " --all-rows -o " + (dir / "all.hff").string());
    REQUIRE(r.status == 0);
    CHECK(runHemirad("info " + (dir / "all.hff").string()).output.find("patches 2, computed rows 2 (skipped 0)") !=
          std::string::npos);
    const Result help = runHemirad("help");
    CHECK(help.output.find("the patches that reflect (rho > 0; --all-rows: every row)") != std::string::npos);
}

TEST_CASE("Every model of the black corpus solves to B = E, and its F files read back and serve --ff") {
    // issue 35 #6: scenes of black bodies (Kd 0: a mirror without Kd, glossy illum 2, relative
    // indices, groups) could not be solved. tests/data/black holds the models; each must solve.
    const auto dir = tempDir("cli-black-corpus");
    std::size_t models = 0;
    for (const auto& entry : std::filesystem::directory_iterator(sourcePath("tests/data/black"))) {
        if (entry.path().extension() != ".obj") continue;
        ++models;
        const std::string model = entry.path().string();
        CAPTURE(model);
        const auto csv = dir / (entry.path().stem().string() + ".csv");
        Result r = runHemirad("solve " + model + " -o " + csv.string());
        REQUIRE_MESSAGE(r.status == 0, r.output);
        CHECK(r.output.find("no row needed") != std::string::npos);
        const auto E = csvColumns(csv, 2);
        CHECK(csvRadiosity(csv) == E);
        CHECK(std::any_of(E.begin(), E.end(), [](const std::array<double, 3>& e) { return e[0] + e[1] + e[2] > 0.0; }));
        for (const char* name : {"F.hff", "F.mtx"}) {
            CAPTURE(name);
            const std::string ff = (dir / name).string();
            std::filesystem::remove(ff);
            REQUIRE(runHemirad("formfactors " + model + " -o " + ff + " --quiet").status == 0);
            const Result info = runHemirad("info " + ff);
            CHECK_MESSAGE(info.status == 0, info.output);
            CHECK(info.output.find("computed rows 0 (skipped " + std::to_string(E.size()) + ")") != std::string::npos);
            r = runHemirad("solve " + model + " --ff " + ff + " -o " + (dir / "again.csv").string());
            CHECK_MESSAGE(r.status == 0, r.output);
            CHECK(readText(dir / "again.csv") == readText(csv));
        }
    }
    CHECK(models >= 3);
}

TEST_CASE("solve --ff refuses an F made with other form-factor settings, naming them, and --reuse-ff-anyway takes it") {
    // issue 35 #22: an F of --max-depth 0 --samples 512 was reused for --max-depth 8 --samples 4096.
    const auto dir = tempDir("cli-ff-settings");
    const std::string ff = (dir / "F.hff").string();
    const std::string solve = "solve " + scene("mirror_pair.obj") + " --ff " + ff + " -o " + (dir / "B.csv").string();
    REQUIRE(runHemirad(solve + " --max-depth 0 --samples 512").status == 0);
    const std::string stored = readText(ff);
    Result r = runHemirad(solve + " --max-depth 8 --samples 4096");
    CHECK(r.status == 1);
    CHECK(r.output.find("was computed with other form-factor settings: --max-depth 0 (the file) against 8 (this run), "
                        "--samples 512 against 4096") != std::string::npos);
    CHECK(r.output.find("--recompute-ff") != std::string::npos);
    CHECK(r.output.find("--reuse-ff-anyway") != std::string::npos);
    CHECK(readText(ff) == stored);
    r = runHemirad(solve + " --max-depth 8 --samples 4096 --reuse-ff-anyway");
    CHECK(r.status == 0);
    CHECK(r.output.find("form factors: reused") != std::string::npos);
    CHECK(r.output.find("--max-depth 0 (the file) against 8 (this run)") != std::string::npos);  // said, and counted
    CHECK(r.output.find("1 F files reused with other settings") != std::string::npos);
    r = runHemirad(solve + " --samples 512 --max-depth 0");  // the same settings: reused without a word
    CHECK(r.status == 0);
    CHECK(r.output.find("form factors: reused") != std::string::npos);
    CHECK(r.output.find("warning") == std::string::npos);
    CHECK(runHemirad("help").output.find("--reuse-ff-anyway") != std::string::npos);
    r = runHemirad("solve " + scene("mirror_pair.obj") + " -o B.csv --reuse-ff-anyway");
    CHECK(r.status == 2);
    CHECK(r.output.find("--reuse-ff-anyway needs --ff FILE") != std::string::npos);
}
