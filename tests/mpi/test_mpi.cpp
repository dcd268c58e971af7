// hemirad under mpirun (2 ranks, as root in CI): F byte-identical to one process, the PETSc solve
// against the one-process LU solve, and errors that end every rank with one message and no hang.
#include "support.hpp"

#include "engine/form_factor_file.hpp"
#include "engine/form_factor_shards.hpp"

#include <doctest/doctest.h>

#include <array>
#include <set>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <sys/wait.h>

using namespace hemirad::test;

namespace {

using Run = CommandResult;

/// Runs hemirad in `dir`, under `mpirun -np ranks` when ranks > 0; a hang fails after 120 s (status 124).
Run runHemirad(const std::filesystem::path& dir, int ranks, const std::string& arguments) {
    std::string command = "cd '" + dir.string() + "' && timeout 120 ";
    if (ranks > 0)
        command += std::string(HEMIRAD_MPIEXEC) + " --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " ";
    command += std::string(HEMIRAD_BINARY) + " " + arguments + " 2>&1";
    return runCommand(command);
}

/// Runs mpirun in `dir` with `contexts`, its application contexts ("-np 1 --wdir A PROGRAM ARGS : -np
/// 1 ..."): ranks started in other folders or with other arguments; a hang fails after 120 s (124).
Run runMpirun(const std::filesystem::path& dir, const std::string& contexts) {
    return runCommand("cd '" + dir.string() + "' && timeout 120 " + HEMIRAD_MPIEXEC + " --allow-run-as-root --oversubscribe " +
                      contexts + " 2>&1");
}

std::string bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE(in.good());
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

/// Two CSV tables of the same shape: text cells (and empty ones) equal, and the largest difference
/// of the numeric cells, each relative to its column's largest magnitude in `a`.
double tableDifference(const std::filesystem::path& a, const std::filesystem::path& b) {
    auto rows = [](const std::filesystem::path& path) {
        std::ifstream in(path);
        std::vector<std::vector<std::string>> cells;
        for (std::string line; std::getline(in, line);) {
            cells.emplace_back();
            std::stringstream row(line);
            for (std::string cell; std::getline(row, cell, ',');) cells.back().push_back(cell);
        }
        return cells;
    };
    auto number = [](const std::string& cell, double& value) {
        char* end = nullptr;
        value = std::strtod(cell.c_str(), &end);
        return !cell.empty() && end == cell.c_str() + cell.size();
    };
    const auto x = rows(a), y = rows(b);
    REQUIRE(x.size() == y.size());
    REQUIRE(x.size() > 1);
    double worst = 0.0;
    for (std::size_t c = 0; c < x[0].size(); ++c) {
        double largest = 0.0, difference = 0.0, u = 0.0, v = 0.0;
        for (std::size_t r = 1; r < x.size(); ++r) {
            REQUIRE(x[r].size() == x[0].size());
            REQUIRE(y[r].size() == x[0].size());
            if (number(x[r][c], u) && number(y[r][c], v)) {
                largest = std::max(largest, std::abs(u));
                difference = std::max(difference, std::abs(u - v));
            } else {
                CHECK(x[r][c] == y[r][c]);
            }
        }
        worst = std::max(worst, largest > 0.0 ? difference / largest : difference);
    }
    return worst;
}

/// The report's line that starts with `start` ("" if none).
std::string reportLine(const std::string& output, const std::string& start) {
    std::stringstream in(output);
    for (std::string line; std::getline(in, line);)
        if (line.rfind(start, 0) == 0) return line;
    return "";
}

/// The thermal report's |sum Q + Q_env| / max |Q| (infinity if it has none).
double energyBalance(const std::string& output) {
    const std::string line = reportLine(output, "energy balance: |sum Q + Q_env| / max |Q| = ");
    return line.empty() ? std::numeric_limits<double>::infinity() : std::stod(line.substr(44));
}

/// B_r, B_g, B_b per patch from a solve CSV.
std::vector<double> radiosityColumns(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);  // header
    std::vector<double> B;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream row(line);
        for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
        REQUIRE(cells.size() == 12);
        for (int c = 9; c < 12; ++c) B.push_back(std::stod(cells[std::size_t(c)]));
    }
    return B;
}

/// max_k |B_k - exact_k| / max(|exact_k|, 1e-6): the worst relative difference (absolute near 0).
double largestRelativeDifference(const std::vector<double>& B, const std::vector<double>& exact) {
    REQUIRE(B.size() == exact.size());
    double worst = 0;
    for (std::size_t k = 0; k < B.size(); ++k)
        worst = std::max(worst, std::abs(B[k] - exact[k]) / std::max(std::abs(exact[k]), 1e-6));
    return worst;
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

/// For a command or one rank's program: "env LD_PRELOAD=PROBE HEMIRAD_TEST_MEMINFO=FILE ", FILE (at
/// `path`) being this machine's /proc/meminfo with MemAvailable set to `bytes` (tests/fake_meminfo.cpp).
std::string withAvailableMemory(const std::filesystem::path& path, std::uintmax_t bytes) {
    std::istringstream real(readText("/proc/meminfo"));
    std::string text;
    for (std::string line; std::getline(real, line);)
        text += (line.rfind("MemAvailable:", 0) == 0 ? "MemAvailable:   " + std::to_string(bytes / 1024) + " kB" : line) + '\n';
    REQUIRE(text.find("MemAvailable:") != std::string::npos);
    writeFile(path, text);
    return "env LD_PRELOAD=" + std::string(HEMIRAD_TEST_FAKE_MEMINFO) + " HEMIRAD_TEST_MEMINFO='" + path.string() + "' ";
}

/// Returns the two-rank run's output.
std::string checkSameF(const std::string& scene, const std::string& flags) {
    const auto dir = tempDir("mpi-f");
    const Run one = runHemirad(dir, 0, "formfactors " + sourcePath("scenes/" + scene) + " -o one.hff --quiet " + flags);
    REQUIRE_MESSAGE(one.status == 0, one.output);
    const Run two = runHemirad(dir, 2, "formfactors " + sourcePath("scenes/" + scene) + " -o two.hff --threads 1 " + flags);
    REQUIRE_MESSAGE(two.status == 0, two.output);
    CHECK(two.output.find("on 2 MPI ranks") != std::string::npos);
    CHECK(bytes(dir / "one.hff").size() > 1000);
    CHECK(bytes(dir / "one.hff") == bytes(dir / "two.hff"));
    return two.output;
}

}  // namespace

TEST_CASE("F from 2 MPI ranks is byte-identical to one process: hemisphere rays with mirrors") {
    checkSameF("cornell_mirror.obj", "--subdivide 60 --estimator rays --samples 256 --origins 2");
}

TEST_CASE("F from 2 MPI ranks is byte-identical to one process: hemisphere analytic with mirrors") {
    const std::string two = checkSameF("cornell_mirror.obj", "--subdivide 80 --estimator analytic --samples 256");
    // The scene's two blocks, counted once for the run, not once per rank.
    CHECK(two.find("their faces turned away from a point cast no shadow from it): 2 (114 faces)") != std::string::npos);
}

TEST_CASE("F from 2 MPI ranks is byte-identical to one process: reciprocity enforced across ranks, rows normalised") {
    checkSameF("cornell_mirror.obj", "--subdivide 80 --samples 256 --enforce-reciprocity");
    checkSameF("cornell_box.obj", "--subdivide 80 --samples 256 --enforce-reciprocity --normalize-rows");
    // A closed box: rows scaled to 1, the Newton steps' sums taken in one order on every rank.
    const std::string closed = checkSameF("unit_cube.obj", "--subdivide 0.2 --enforce-reciprocity");
    // --drop-below: the same pairs dropped on every rank (each row's cut shared), the same closure.
    const std::string dropped = checkSameF("cornell_box.obj", "--subdivide 80 --drop-below 1e-3");
    CHECK(dropped.find("pairs with both entries below 0.001 dropped") != std::string::npos);
    CHECK(closed.find("rows sum to 1 (a closed scene") != std::string::npos);
}

#ifdef HEMIRAD_TEST_HEMICUBE
TEST_CASE("F from 2 MPI ranks is byte-identical to one process: hemicube on the software GL") {
    checkSameF("cornell_mirror.obj", "--subdivide 100 --method hemicube --resolution 32");
}
#endif

TEST_CASE("The distributed PETSc solve matches the one-process LU solve to the CSV's 9 digits") {
    const auto dir = tempDir("mpi-solve");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 80 --samples 256 --ff F.hff";
    const Run one = runHemirad(dir, 0, "solve " + scene + " --solver lu -o lu.csv --quiet");
    REQUIRE_MESSAGE(one.status == 0, one.output);
    const std::vector<double> exact = radiosityColumns(dir / "lu.csv");
    REQUIRE(exact.size() > 300);
    for (const char* solver : {"bicgstab", "jacobi"}) {
        CAPTURE(solver);
        const Run two = runHemirad(dir, 2, "solve " + scene + " --threads 1 --tolerance 1e-13 --solver " + solver +
                                            " -o " + solver + ".csv");
        REQUIRE_MESSAGE(two.status == 0, two.output);
        CHECK(two.output.find("form factors: reused F.hff") != std::string::npos);  // F rows read, not recomputed
        CHECK(count(two.output, "(PETSc, 2 ranks), channel(s)") == 3);
        CHECK(count(two.output, ": converged in") == 3);
        // The CSV prints 9 significant digits (rounding 5e-9).
        CHECK(largestRelativeDifference(radiosityColumns(dir / (std::string(solver) + ".csv")), exact) < 1e-8);
    }
    // From scratch too: F computed on the ranks, solved where its rows are.
    const Run fresh = runHemirad(dir, 2, "solve " + sourcePath("scenes/cornell_box.obj") +
                                          " --subdivide 80 --samples 256 --threads 1 --tolerance 1e-13 -o fresh.csv");
    REQUIRE_MESSAGE(fresh.status == 0, fresh.output);
    CHECK(largestRelativeDifference(radiosityColumns(dir / "fresh.csv"), exact) < 1e-8);
}

TEST_CASE("solve -o - on 2 ranks writes the CSV alone to standard output (the report to standard error)") {
    const auto dir = tempDir("mpi-stdout");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --samples 256 --threads 1";
    const Run file = runHemirad(dir, 2, "solve " + scene + " -o B.csv --quiet");
    REQUIRE_MESSAGE(file.status == 0, file.output);
    const Run out = runCommand("cd '" + dir.string() + "' && timeout 120 " + HEMIRAD_MPIEXEC +
                               " --allow-run-as-root --oversubscribe -np 2 " + HEMIRAD_BINARY + " solve " + scene +
                               " -o - 2> err.txt");
    REQUIRE(out.status == 0);
    CHECK(bytes(dir / "B.csv").size() > 500);
    CHECK(out.output == bytes(dir / "B.csv"));
    CHECK(count(bytes(dir / "err.txt"), "wrote standard output") == 1);
}

TEST_CASE("solve --sky-view on 2 ranks writes one process's sky_view_factor column, and the sky view map runs on rank 0") {
    const auto dir = tempDir("mpi-sky-view");
    // The Cornell box with a mirror wall is open at the front: its patches see sky, some through the mirror.
    const std::string scene = sourcePath("scenes/cornell_mirror.obj") + " --threads 1";
    const Run one = runHemirad(dir, 0, "solve " + scene + " --sky-view -o one.csv --quiet");
    REQUIRE_MESSAGE(one.status == 0, one.output);
    const Run two = runHemirad(dir, 2, "solve " + scene + " --sky-view -o two.csv");
    REQUIRE_MESSAGE(two.status == 0, two.output);
    CHECK(count(two.output, "sky view factor (") == 1);  // computed once, by rank 0
    auto skyColumn = [&](const char* name) {
        std::istringstream in(bytes(dir / name));
        std::vector<std::string> column;
        for (std::string line; std::getline(in, line);) column.push_back(line.substr(line.rfind(',') + 1));
        return column;
    };
    const std::vector<std::string> expected = skyColumn("one.csv");
    REQUIRE(expected.size() == 21);
    CHECK(expected[0] == "sky_view_factor");
    CHECK(skyColumn("two.csv") == expected);
    const Run map = runHemirad(dir, 2, "render " + scene + " --false-color sky_view_factor --size 64x64 -o svf.png");
    REQUIRE_MESSAGE(map.status == 0, map.output);
    CHECK(count(map.output, "false colour: sky view factor (unitless, 0..1)") == 1);
    CHECK(bytes(dir / "svf.png").size() > 1000);
}

TEST_CASE("Distributed CG on the symmetric form matches LU for a reciprocal F, and refuses a non-reciprocal one") {
    const auto dir = tempDir("mpi-cg");
    // With mirrors: their chains allow row sums above 1, so the averaged pairs stay within the file's bound.
    const std::string scene = sourcePath("scenes/cornell_mirror.obj") + " --subdivide 100 --samples 256";
    // One process stores F made reciprocal (a new file stores F as post-processed).
    const Run stored = runHemirad(dir, 0, "solve " + scene + " --enforce-reciprocity --ff F.hff --solver lu -o lu.csv --quiet");
    REQUIRE_MESSAGE(stored.status == 0, stored.output);
    const Run one = runHemirad(dir, 0, "solve " + scene + " --ff F.hff --solver cg --tolerance 1e-12 -o cg1.csv --quiet");
    REQUIRE_MESSAGE(one.status == 0, one.output);
    const Run cg = runHemirad(dir, 2, "solve " + scene + " --ff F.hff --threads 1 --solver cg --tolerance 1e-12 -o cg.csv");
    REQUIRE_MESSAGE(cg.status == 0, cg.output);
    CHECK(count(cg.output, "cg (PETSc, 2 ranks), channel(s)") == 3);
    CHECK(count(cg.output, ": converged in") == 3);
    const std::vector<double> B = radiosityColumns(dir / "cg.csv");
    // The same symmetric system as one process's CG, to the CSV's 9 digits.
    CHECK(largestRelativeDifference(B, radiosityColumns(dir / "cg1.csv")) < 1e-8);
    // LU solves I - R F itself, the same system to F's reciprocity (1e-16) and CG's tolerance.
    CHECK(largestRelativeDifference(B, radiosityColumns(dir / "lu.csv")) < 1e-8);
    // A black emitter (rho = 0, its row not computed): its light enters the right-hand side whole.
    std::filesystem::copy_file(sourcePath("scenes/cornell_mirror.obj"), dir / "black.obj");
    std::string mtl = readText(sourcePath("scenes/cornell_mirror.mtl"));
    const std::string light = "Kd 0.78 0.78 0.78\nKs 0 0 0\nKe 17";
    REQUIRE(mtl.find(light) != std::string::npos);
    mtl.replace(mtl.find(light), 17, "Kd 0 0 0");
    writeFile(dir / "cornell_mirror.mtl", mtl);
    const std::string blackScene = "black.obj --subdivide 100 --samples 256";
    REQUIRE(runHemirad(dir, 0, "formfactors " + blackScene + " --enforce-reciprocity -o black.hff --quiet").status == 0);
    const Run blackOne = runHemirad(dir, 0, "solve " + blackScene + " --ff black.hff --solver cg --tolerance 1e-12 -o b1.csv");
    REQUIRE_MESSAGE(blackOne.status == 0, blackOne.output);
    const Run blackTwo = runHemirad(dir, 2, "solve " + blackScene + " --ff black.hff --threads 1 --solver cg --tolerance 1e-12 -o b2.csv");
    REQUIRE_MESSAGE(blackTwo.status == 0, blackTwo.output);
    CHECK(largestRelativeDifference(radiosityColumns(dir / "b2.csv"), radiosityColumns(dir / "b1.csv")) < 1e-8);
    // F from the rays (not reciprocal; the analytic estimator's pairs are): the symmetrised system
    // converges, the posed one does not.
    REQUIRE(runHemirad(dir, 0, "formfactors " + scene + " --estimator rays -o raw.hff --quiet").status == 0);
    const Run refused = runHemirad(dir, 2, "solve " + scene + " --estimator rays --ff raw.hff --threads 1 --solver cg -o raw.csv");
    CHECK(refused.status == 1);
    CHECK(count(refused.output, "F is not reciprocal enough for the symmetric form") >= 1);
    CHECK(count(refused.output, "hemirad: error: ") == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "raw.csv"));
}

TEST_CASE("A reused F gains the rows it lacks on 2 ranks, and the updated file is byte-identical to one process's") {
    const auto dir = tempDir("mpi-merge");
    std::filesystem::copy_file(sourcePath("scenes/cornell_box.obj"), dir / "box.obj");
    const std::string mtl = readText(sourcePath("scenes/cornell_box.mtl"));
    const std::string red = "Kd 0.65 0.05 0.05";
    REQUIRE(mtl.find(red) != std::string::npos);
    std::string black = mtl;
    black.replace(black.find(red), red.size(), "Kd 0 0 0");
    writeFile(dir / "cornell_box.mtl", black);  // the red wall black: its rows are skipped
    const std::string flags = " --subdivide 80 --samples 256 --quiet";
    REQUIRE(runHemirad(dir, 0, "solve box.obj --ff one.hff -o B.csv" + flags).status == 0);
    std::filesystem::copy_file(dir / "one.hff", dir / "two.hff");
    writeFile(dir / "cornell_box.mtl", mtl);  // red again: the same geometry, rows missing
    const Run one = runHemirad(dir, 0, "solve box.obj --ff one.hff -o B.csv" + flags);
    REQUIRE_MESSAGE(one.status == 0, one.output);
    const Run two = runHemirad(dir, 2, "solve box.obj --ff two.hff -o B.csv --threads 1 --subdivide 80 --samples 256");
    REQUIRE_MESSAGE(two.status == 0, two.output);
    CHECK(two.output.find("rows on 2 MPI ranks") != std::string::npos);
    CHECK(bytes(dir / "two.hff") == bytes(dir / "one.hff"));
    CHECK(readText(dir / "two.hff").find("rows_added=") != std::string::npos);
}

TEST_CASE("--ff --drop-below on 2 ranks drops once and keeps every pair with the light, as one process does") {
    // issue 35 #2 and #3: a stored F dropped again on each reuse; a patch's only entry to the light dropped.
    const auto dir = tempDir("mpi-drop");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 150 --drop-below 0.01 --tolerance 1e-13";
    const Run one = runHemirad(dir, 0, "solve " + scene + " --ff one.hff -o one.csv --quiet");
    REQUIRE_MESSAGE(one.status == 0, one.output);
    const Run two = runHemirad(dir, 2, "solve " + scene + " --ff two.hff -o two.csv --threads 1");
    REQUIRE_MESSAGE(two.status == 0, two.output);
    CHECK(two.output.find("pairs with both entries below 0.01 dropped") != std::string::npos);
    CHECK(bytes(dir / "two.hff") == bytes(dir / "one.hff"));
    // Reused on 2 ranks, the file of either: stored as dropped, not dropped again.
    for (const char* file : {"two.hff", "one.hff"}) {
        CAPTURE(file);
        const std::string stored = bytes(dir / file);
        const Run again = runHemirad(dir, 2, "solve " + scene + " --ff " + file + " -o again.csv --threads 1");
        REQUIRE_MESSAGE(again.status == 0, again.output);
        CHECK(again.output.find("form factors: reused") != std::string::npos);
        CHECK(again.output.find("dropped:") == std::string::npos);
        CHECK(bytes(dir / file) == stored);
        // The rows spread over the ranks otherwise: the same B to the solve's tolerance.
        CHECK(largestRelativeDifference(radiosityColumns(dir / "again.csv"), radiosityColumns(dir / "two.csv")) < 1e-8);
    }
    // Every patch that saw the light before the drop still sees it.
    const hemirad::FormFactors F = hemirad::loadFormFactors((dir / "two.hff").string());
    const std::string full = sourcePath("scenes/cornell_box.obj") + " --subdivide 150";
    REQUIRE(runHemirad(dir, 0, "formfactors " + full + " -o full.hff --quiet").status == 0);
    const hemirad::FormFactors undropped = hemirad::loadFormFactors((dir / "full.hff").string());
    std::vector<std::uint32_t> lights;
    {
        std::ifstream in(dir / "one.csv");
        std::string line;
        std::getline(in, line);
        for (std::uint32_t i = 0; std::getline(in, line); ++i)
            if (std::stod(line.substr(line.find(',', line.find(',') + 1) + 1)) > 0) lights.push_back(i);
    }
    REQUIRE_FALSE(lights.empty());
    std::size_t kept = 0;
    for (std::uint32_t i = 0; i < F.size(); ++i)
        for (const std::uint32_t light : lights)
            if (undropped.at(i, light) > 0) {
                CHECK(F.at(i, light) > 0);
                ++kept;
            }
    CHECK(kept > 100);
}

TEST_CASE("A scene of black patches on 2 ranks: F is N x N with the scene's hash, as one process writes it, and serves --ff") {
    // issue 35 #18: under MPI the F of a scene that needs no rows got scene hash 0000000000000000.
    const auto dir = tempDir("mpi-black");
    const std::string scene = sourcePath("tests/data/black/black_pair.obj");
    for (const char* name : {"F.hff", "F.mtx"}) {
        CAPTURE(name);
        const std::string ext = std::string(name).substr(1);
        REQUIRE(runHemirad(dir, 0, "formfactors " + scene + " -o one" + ext + " --quiet").status == 0);
        const Run two = runHemirad(dir, 2, "formfactors " + scene + " -o two" + ext + " --threads 1");
        REQUIRE_MESSAGE(two.status == 0, two.output);
        CHECK(two.output.find("scene hash 0000000000000000") == std::string::npos);
        CHECK(bytes(dir / ("two" + ext)) == bytes(dir / ("one" + ext)));
        const Run info = runHemirad(dir, 0, "info two" + ext);
        CHECK_MESSAGE(info.status == 0, info.output);
        CHECK(info.output.find("patches 2, computed rows 0 (skipped 2)") != std::string::npos);
        const Run solve = runHemirad(dir, 2, "solve " + scene + " --ff two" + ext + " -o B.csv --threads 1");
        REQUIRE_MESSAGE(solve.status == 0, solve.output);
        CHECK(solve.output.find("form factors: reused two" + ext) != std::string::npos);
        CHECK(largestRelativeDifference(radiosityColumns(dir / "B.csv"), {1, 2, 3, 0, 0, 0}) < 1e-12);
    }
    const Run fresh = runHemirad(dir, 2, "solve " + scene + " --ff new.hff -o B.csv --threads 1");
    REQUIRE_MESSAGE(fresh.status == 0, fresh.output);
    CHECK(largestRelativeDifference(radiosityColumns(dir / "B.csv"), {1, 2, 3, 0, 0, 0}) < 1e-12);
    CHECK(bytes(dir / "new.hff") == bytes(dir / "one.hff"));
}

TEST_CASE("A sharded F from 2 ranks round-trips through info and solve --ff, in one process and on 2 or 3 ranks") {
    const auto dir = tempDir("mpi-shards");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 80 --samples 256";
    REQUIRE(runHemirad(dir, 0, "formfactors " + scene + " -o one.hff --quiet").status == 0);
    const Run write = runHemirad(dir, 2, "formfactors " + scene + " -o sharded.hff --shards --threads 1");
    REQUIRE_MESSAGE(write.status == 0, write.output);
    CHECK(write.output.find("(a shard manifest; 2 shards of") != std::string::npos);
    const hemirad::ShardManifest manifest = hemirad::readShardManifest((dir / "sharded.hff").string());
    REQUIRE(manifest.shards.size() == 2);
    const std::string shard1 = manifest.shards[1].file;
    CHECK(shard1.rfind("sharded.shard-1-of-2.", 0) == 0);
    CHECK(std::filesystem::exists(dir / manifest.shards[0].file));
    CHECK(std::filesystem::exists(dir / shard1));
    // The shards together are the one-process F, entry for entry.
    const hemirad::FormFactors one = hemirad::loadFormFactors((dir / "one.hff").string());
    const hemirad::FormFactors merged = hemirad::loadFormFactors((dir / "sharded.hff").string());
    CHECK(merged.rowStarts() == one.rowStarts());
    CHECK(merged.columnVector() == one.columnVector());
    CHECK(merged.valueVector() == one.valueVector());
    CHECK(merged.computedFlags() == one.computedFlags());
    CHECK(merged.parameters == one.parameters);
    CHECK(merged.sceneHash == one.sceneHash);

    const Run info = runHemirad(dir, 0, "info sharded.hff");
    REQUIRE_MESSAGE(info.status == 0, info.output);
    CHECK(info.output.find("a manifest of 2 shards") != std::string::npos);
    CHECK(info.output.find("nonzeros " + std::to_string(one.nonZeros()) + " (") != std::string::npos);
    CHECK(info.output.find("shard 1: " + shard1) != std::string::npos);

    REQUIRE(runHemirad(dir, 0, "solve " + scene + " --ff one.hff --solver lu -o lu.csv --quiet").status == 0);
    const Run solveOne = runHemirad(dir, 0, "solve " + scene + " --ff sharded.hff --solver lu -o lu-sharded.csv");
    REQUIRE_MESSAGE(solveOne.status == 0, solveOne.output);
    CHECK(solveOne.output.find("form factors: reused sharded.hff") != std::string::npos);
    CHECK(bytes(dir / "lu-sharded.csv") == bytes(dir / "lu.csv"));
    const std::vector<double> exact = radiosityColumns(dir / "lu.csv");
    for (int ranks : {2, 3}) {  // 3 ranks: one rank holds no shard
        CAPTURE(ranks);
        const Run solve = runHemirad(dir, ranks, "solve " + scene + " --ff sharded.hff --threads 1 --tolerance 1e-13 -o B.csv");
        REQUIRE_MESSAGE(solve.status == 0, solve.output);
        CHECK(solve.output.find("each rank reading its own shards") != std::string::npos);
        CHECK(solve.output.find("rows on") == std::string::npos);  // nothing recomputed
        CHECK(largestRelativeDifference(radiosityColumns(dir / "B.csv"), exact) < 1e-8);
    }
    // Written again on 2 ranks: a new set, the old one removed, nothing else left behind.
    REQUIRE(runHemirad(dir, 2, "formfactors " + scene + " -o again.hff --shards --threads 1 --quiet").status == 0);
    const auto first = hemirad::readShardManifest((dir / "again.hff").string());
    REQUIRE(runHemirad(dir, 2, "formfactors " + scene + " -o again.hff --shards --threads 1 --quiet").status == 0);
    const auto second = hemirad::readShardManifest((dir / "again.hff").string());
    CHECK(first.shards[0].file != second.shards[0].file);
    for (const auto& s : first.shards) CHECK_FALSE(std::filesystem::exists(dir / s.file));
    for (const auto& s : second.shards) CHECK(std::filesystem::exists(dir / s.file));
    // A damaged shard: every rank stops with one message naming it, exit 1.
    std::string damaged = bytes(dir / shard1);
    damaged[damaged.size() / 2] = char(damaged[damaged.size() / 2] ^ 0x5a);
    writeFile(dir / shard1, damaged);
    const Run broken = runHemirad(dir, 2, "solve " + scene + " --ff sharded.hff --threads 1 -o B2.csv");
    CHECK(broken.status == 1);
    CHECK(count(broken.output, "hemirad: error: ") == 1);
    CHECK(count(broken.output, shard1 + ": checksum mismatch") == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "B2.csv"));
}

TEST_CASE("bench-run on 2 ranks records the one-process measurement: the same F, the same errors, and the ranks") {
    const auto dir = tempDir("mpi-bench-run");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 80";
    REQUIRE(runHemirad(dir, 0, "formfactors " + scene + " --samples 1024 --origins 4 -o ref.hff --quiet").status == 0);
    const Run one = runHemirad(dir, 0, "bench-run " + scene + " --samples 256 --reference ref.hff --solver bicgstab");
    const Run two = runHemirad(dir, 2, "bench-run " + scene + " --samples 256 --reference ref.hff --threads 1");
    REQUIRE_MESSAGE(one.status == 0, one.output);
    REQUIRE_MESSAGE(two.status == 0, two.output);
    CHECK(count(two.output, "{\"scene\": ") == 1);  // one JSON line, from rank 0 alone
    CHECK(two.output.find("\"ranks\": 2") != std::string::npos);
    CHECK(two.output.find("\"peak_rss_mib_total\": ") != std::string::npos);
    // F is byte-identical, so its size, row sums and errors against the reference are the same text.
    for (const char* key : {"\"nnz\": ", "\"row_sum_mean\": ", "\"reciprocity_mean\": ", "\"err_mean\": ",
                            "\"err_worst_row_l1\": "}) {
        CAPTURE(key);
        const std::size_t a = one.output.find(key), b = two.output.find(key);
        REQUIRE(a != std::string::npos);
        REQUIRE(b != std::string::npos);
        CHECK(one.output.substr(a, one.output.find(',', a) - a) == two.output.substr(b, two.output.find(',', b) - b));
    }
}

TEST_CASE("A malformed scene or a missing file on 2 ranks gives the one-process message once, exit 1, no hang") {
    const auto dir = tempDir("mpi-errors");
    writeFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n");
    for (const char* input : {"bad.obj", "missing.obj"}) {
        CAPTURE(input);
        const Run one = runHemirad(dir, 0, std::string("formfactors ") + input + " -o F.hff");
        const Run two = runHemirad(dir, 2, std::string("formfactors ") + input + " -o F.hff");
        CHECK(one.status == 1);
        CHECK(two.status == 1);  // mpirun passes the ranks' status on; 124 would be the timeout (a hang)
        REQUIRE(count(one.output, "hemirad: error: ") == 1);
        const std::string message = one.output.substr(one.output.find("hemirad: error: "));
        CHECK(count(two.output, message) == 1);
        CHECK(count(two.output, "hemirad: error: ") == 1);
        CHECK_FALSE(std::filesystem::exists(dir / "F.hff"));
    }
}

TEST_CASE("Options that cannot run across ranks are usage errors on every rank, said once") {
    const auto dir = tempDir("mpi-usage");
    const std::string scene = sourcePath("scenes/unit_cube.obj");
    Run r = runHemirad(dir, 2, "solve " + scene + " -o B.csv --solver gauss-seidel");
    CHECK(r.status == 2);
    CHECK(count(r.output, "--solver gauss-seidel does not run across MPI ranks") == 1);
    r = runHemirad(dir, 2, "bench " + scene + " -o results.csv");
    CHECK(r.status == 2);
    CHECK(count(r.output, "'bench' runs each measurement as a child process of one process") == 1);
    r = runHemirad(dir, 2, "render " + scene + " -o - > image.png");  // mpirun's forwarding: no terminal check
    CHECK(r.status == 2);
    CHECK(count(bytes(dir / "image.png"), "the binary .png needs -o FILE") == 1);  // the messages went there too
    r = runHemirad(dir, 2, "formfactors " + scene + " -o F.hff --bogus");
    CHECK(r.status == 2);
    CHECK(count(r.output, "unknown option '--bogus'") == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "F.hff"));
}

TEST_CASE("A plain hemirad run loads no MPI or PETSc library, and under a launcher without its MPI module each rank says so and fails") {
    // MPI and PETSc come in through hemirad-mpi.so, loaded only under a launcher (~100 libraries).
    const Run needed = runCommand("ldd " + std::string(HEMIRAD_BINARY) + " 2>&1");  // direct and indirect
    REQUIRE(needed.status == 0);
    CHECK(needed.output.find("libmpi") == std::string::npos);
    CHECK(needed.output.find("libpetsc") == std::string::npos);
    CHECK(std::filesystem::exists(std::filesystem::path(HEMIRAD_BINARY).parent_path() / "hemirad-mpi.so"));
    // A copy of hemirad without the module beside it, started as rank 0 and as rank 1 of a launcher.
    const auto dir = tempDir("mpi-no-module");
    std::filesystem::copy_file(HEMIRAD_BINARY, dir / "hemirad");
    const std::string plain = "cd '" + dir.string() + "' && ./hemirad help 2>&1";
    CHECK(runCommand(plain).status == 0);  // no launcher: no module needed
    for (const char* rank : {"0", "1"}) {
        CAPTURE(rank);
        const Run r = runCommand("cd '" + dir.string() + "' && OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=" + rank +
                                 " ./hemirad help 2>&1");
        CHECK(r.status == 1);
        // Every rank that fails says so, once, naming itself (issue 35 #19: rank 1 said nothing).
        CHECK(count(r.output, "hemirad: error: ") == 1);
        CHECK(r.output.find("hemirad: error: rank " + std::string(rank) + " of 2: started by an MPI launcher, but its MPI module " +
                            (std::filesystem::canonical(dir) / "hemirad-mpi.so").string() + " cannot be used") !=
              std::string::npos);
    }
}

TEST_CASE("Ranks that loaded different scene files or were given other options stop with one message naming the rank") {
    // issue 35 #16: a rank given a copy of the scene with another Kd gave "converged" and B up to 87 %
    // off; the F hash covers geometry and mirrors only. Here each rank starts in its own folder (a
    // node's own copy), or with its own arguments.
    const auto dir = tempDir("mpi-agree");
    const std::string mtl = readText(sourcePath("scenes/cornell_box.mtl"));
    const std::string red = "Kd 0.65 0.05 0.05";
    REQUIRE(mtl.find(red) != std::string::npos);
    std::string redder = mtl;
    redder.replace(redder.find(red), red.size(), "Kd 0.85 0.05 0.05");
    for (const char* node : {"a", "b"}) {
        std::filesystem::create_directories(dir / node);
        std::filesystem::copy_file(sourcePath("scenes/cornell_box.obj"), dir / node / "box.obj");
        writeFile(dir / node / "cornell_box.mtl", std::string(node) == "a" ? mtl : redder);
    }
    const std::string a = " --wdir '" + (dir / "a").string() + "' " + HEMIRAD_BINARY;
    const std::string b = " --wdir '" + (dir / "b").string() + "' " + HEMIRAD_BINARY;
    const std::string solve = " solve box.obj --subdivide 80 --samples 256 -o B.csv --threads 1";
    Run r = runMpirun(dir, "-np 1" + a + solve + " : -np 1" + b + solve);
    CHECK(r.status == 1);
    CHECK(count(r.output, "hemirad: error: ") == 1);
    CHECK(count(r.output, "hemirad: error: rank 1 of 2 loaded another scene than rank 0 from box.obj (geometry, "
                          "materials or subdivision differ)") == 1);
    CHECK(count(r.output, "interrupted") == 0);
    CHECK_FALSE(std::filesystem::exists(dir / "a" / "B.csv"));
    // One vertex moved (geometry), 3 ranks: the two that differ are named as one message.
    std::string obj = readText(sourcePath("scenes/cornell_box.obj"));
    const std::string corner = "\nv 552.8 0.0 0.0\n";
    REQUIRE(obj.find(corner) != std::string::npos);
    obj.replace(obj.find(corner), corner.size(), "\nv 552.9 0.0 0.0\n");
    writeFile(dir / "b" / "box.obj", obj);
    writeFile(dir / "b" / "cornell_box.mtl", mtl);
    const std::string formfactors = " formfactors box.obj --subdivide 80 --samples 256 -o F.hff --threads 1";
    r = runMpirun(dir, "-np 1" + a + formfactors + " : -np 2" + b + formfactors);
    CHECK(r.status == 1);
    CHECK(count(r.output, "hemirad: error: ") == 1);
    CHECK(count(r.output, "hemirad: error: rank 1 of 3 (and 1 more) loaded another scene than rank 0") == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "a" / "F.hff"));
    // The same files, other options on rank 1: refused before the scene is read.
    std::filesystem::copy_file(dir / "a" / "box.obj", dir / "b" / "box.obj", std::filesystem::copy_options::overwrite_existing);
    r = runMpirun(dir, "-np 1" + a + solve + " : -np 1" + b + solve + " --solver jacobi");
    CHECK(r.status == 1);
    CHECK(count(r.output, "hemirad: error: ") == 1);
    CHECK(count(r.output, "hemirad: error: rank 1 of 2 was given other options than rank 0") == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "a" / "B.csv"));
    // The same files and options but --threads, which each rank may take from its own machine: it runs.
    r = runMpirun(dir, "-np 1" + a + solve + " : -np 1" + b + " solve box.obj --subdivide 80 --samples 256 -o B.csv --threads 2");
    CHECK_MESSAGE(r.status == 0, r.output);
    CHECK(std::filesystem::exists(dir / "a" / "B.csv"));
}

TEST_CASE("Rank 0 reads a shard manifest for every rank: a rank that would read another one still gets rank 0's") {
    // issue 35 #21: each rank read the manifest itself, so a manifest replaced between two ranks' reads
    // combined two sets. Here rank 1 starts in a folder whose manifest lists the same shards swapped.
    const auto dir = tempDir("mpi-manifest");
    std::filesystem::create_directories(dir / "a");
    std::filesystem::create_directories(dir / "b");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 80 --samples 256";
    const Run write = runHemirad(dir / "a", 2, "formfactors " + scene + " -o sharded.hff --shards --threads 1 --quiet");
    REQUIRE_MESSAGE(write.status == 0, write.output);
    const hemirad::ShardManifest manifest = hemirad::readShardManifest((dir / "a" / "sharded.hff").string());
    REQUIRE(manifest.shards.size() == 2);
    for (const auto& shard : manifest.shards) std::filesystem::copy_file(dir / "a" / shard.file, dir / "b" / shard.file);
    std::string text = readText(dir / "a" / "sharded.hff");
    const std::size_t first = text.find("\nshard "), second = text.find("\nshard ", first + 1);
    REQUIRE(second != std::string::npos);
    const std::string line0 = text.substr(first, second - first), line1 = text.substr(second, text.find('\n', second + 1) - second);
    text.replace(second, line1.size(), line0);
    text.replace(first, line0.size(), line1);
    writeFile(dir / "b" / "sharded.hff", text);
    REQUIRE(hemirad::readShardManifest((dir / "b" / "sharded.hff").string()).shards[0].file == manifest.shards[1].file);
    REQUIRE(runHemirad(dir / "a", 0, "solve " + scene + " --ff sharded.hff --solver lu -o lu.csv --quiet").status == 0);
    const std::string solve = " solve " + scene + " --ff sharded.hff --threads 1 --tolerance 1e-13 -o B.csv";
    const Run r = runMpirun(dir, "-np 1 --wdir '" + (dir / "a").string() + "' " + HEMIRAD_BINARY + solve + " : -np 1 --wdir '" +
                                     (dir / "b").string() + "' " + HEMIRAD_BINARY + solve);
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(r.output.find("each rank reading its own shards") != std::string::npos);
    CHECK(r.output.find("rows on") == std::string::npos);  // nothing recomputed: rank 0's set, whole
    CHECK(largestRelativeDifference(radiosityColumns(dir / "a" / "B.csv"), radiosityColumns(dir / "a" / "lu.csv")) < 1e-8);
}

TEST_CASE("Under mpirun the error and the report lines reach their streams in one write each") {
    // issue 35 #20: "hemirad: error: " and the message were separate writes, and in 1 of 7 runs mpirun
    // forwarded the prefix glued to a report line. Rank 0 runs with a preloaded probe that logs each
    // write(2) with its whole text.
    const auto dir = tempDir("mpi-one-write");
    writeFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n");
    const Run one = runHemirad(dir, 0, "formfactors bad.obj -o F.hff");
    REQUIRE(one.status == 1);
    const std::string message = one.output.substr(one.output.find("hemirad: error: "));
    const auto log = dir / "writes.log";
    const std::string command = std::string(HEMIRAD_BINARY) + " formfactors bad.obj -o F.hff";
    const Run two = runMpirun(dir, "-np 1 " + logWrites(log.string()) + command + " : -np 1 " + command);
    CHECK(two.status == 1);
    CHECK(count(two.output, "hemirad: error: ") == 1);
    const std::vector<LoggedWrite> failed = loggedWrites(log);
    CHECK_MESSAGE(wroteWhole(failed, 2, message), describeWrites(failed));
    // A report line of a run that works, from rank 0 alone.
    std::filesystem::remove(log);
    const std::string run = std::string(HEMIRAD_BINARY) + " formfactors " + sourcePath("scenes/unit_cube.obj") + " -o F.hff --threads 1";
    const Run fine = runMpirun(dir, "-np 1 " + logWrites(log.string()) + run + " : -np 1 " + run);
    REQUIRE_MESSAGE(fine.status == 0, fine.output);
    const std::size_t wrote = fine.output.find("wrote F.hff (scene hash ");
    REQUIRE(wrote != std::string::npos);
    const std::vector<LoggedWrite> worked = loggedWrites(log);
    CHECK_MESSAGE(wroteWhole(worked, 1, fine.output.substr(wrote, fine.output.find('\n', wrote) + 1 - wrote)),
                  describeWrites(worked));
}

TEST_CASE("A sharded write interrupted between the ranks' shards and the manifest leaves no shard for good") {
    // issue 35 #17: every rank had renamed its shard into place when Ctrl-C came, before rank 0 wrote
    // the manifest; those shards, listed nowhere, stayed forever. Rank 0 here is interrupted at the
    // manifest's rename (a preloaded fault: SIGINT to mpirun, which ends both ranks).
    const auto dir = tempDir("mpi-interrupted-shards");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 150 --samples 256";
    const std::string write = std::string(HEMIRAD_BINARY) + " formfactors " + scene + " -o F.hff --shards --threads 1 --quiet";
    const auto shardFiles = [&dir] {
        std::set<std::string> names;
        for (const auto& entry : std::filesystem::directory_iterator(dir))
            if (entry.path().filename().string().rfind("F.shard-", 0) == 0) names.insert(entry.path().filename().string());
        return names;
    };
    const auto listed = [&dir] {
        std::set<std::string> names;
        for (const auto& s : hemirad::readShardManifest((dir / "F.hff").string()).shards) names.insert(s.file);
        return names;
    };
    REQUIRE(runMpirun(dir, "-np 2 " + write).status == 0);
    const std::set<std::string> before = listed();
    REQUIRE(shardFiles() == before);

    const Run interrupted = runMpirun(dir, "-np 1 env LD_PRELOAD=" + std::string(HEMIRAD_TEST_INTERRUPT_AT_RENAME) +
                                               " HEMIRAD_TEST_INTERRUPT_AT=F.hff " + write + " : -np 1 " + write);
    CHECK(interrupted.status != 0);
    CHECK(interrupted.status != 124);  // no hang
    REQUIRE_MESSAGE(count(interrupted.output, "interrupt_at_rename: interrupting") == 1, interrupted.output);
    CHECK(listed() == before);  // the old manifest and its set are whole
    std::set<std::string> orphans;
    for (const std::string& name : shardFiles())
        if (!before.count(name)) orphans.insert(name);
    CHECK(orphans.size() == 2);  // both ranks had committed their shard: the fault hit in between

    // The next write of F removes them: only the shards its manifest lists stay.
    REQUIRE(runMpirun(dir, "-np 2 " + write).status == 0);
    CHECK(shardFiles() == listed());
    for (const std::string& name : orphans) CHECK_FALSE(std::filesystem::exists(dir / name));
}

TEST_CASE("A rank still finalising when mpirun ends the job after an agreed failure does not say it was interrupted") {
    // issue 35 #20: after a clean agreed failure, mpirun sent SIGTERM to a rank still finalising, which
    // printed "interrupted; no partial output was written" after the real message. Rank 1 here waits
    // 20 s after MPI_Finalize (a preloaded fault), so that rank 0's exit ends it while it waits.
    const auto dir = tempDir("mpi-no-interrupted");
    writeFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n");
    const std::string command = std::string(HEMIRAD_BINARY) + " formfactors bad.obj -o F.hff";
    const Run r = runMpirun(dir, "-np 1 " + command + " : -np 1 env LD_PRELOAD=" + HEMIRAD_TEST_SLOW_FINALIZE + " " + command);
    CHECK(r.status == 1);
    CHECK(count(r.output, "hemirad: error: ") == 1);
    CHECK(count(r.output, "bad.obj:3: ") == 1);
    CHECK(count(r.output, "slow_finalize: waiting") == 1);  // the fault was in place
    CHECK(count(r.output, "slow_finalize: done") == 0);     // and mpirun ended the rank while it waited
    CHECK(count(r.output, "interrupted") == 0);
}

TEST_CASE("A rank that cannot load the MPI module says why when rank 0 could and the job ends") {
    // issue 35 #19: only rank 0 said why; with rank 1 failing, the user read rank 0's "interrupted".
    const auto dir = tempDir("mpi-module-rank1");
    std::filesystem::copy_file(HEMIRAD_BINARY, dir / "hemirad");  // no hemirad-mpi.so beside it
    const Run r = runMpirun(dir, std::string("-np 1 ") + HEMIRAD_BINARY + " help : -np 1 ./hemirad help");
    CHECK(r.status != 0);
    CHECK(r.status != 124);  // no hang
    CHECK(count(r.output, "hemirad: error: rank 1 of 2: started by an MPI launcher, but its MPI module " +
                              (std::filesystem::canonical(dir) / "hemirad-mpi.so").string() + " cannot be used") == 1);
}

TEST_CASE("A failure while MPI ranks start (PETSc cannot open its options file) is one message, exit 1, no hang") {
    // issue 35 #12: the failure was thrown from the MPI context's constructor, outside any try: each
    // rank printed PETSc's traceback and ended in std::terminate, without MPI_Finalize.
    const auto dir = tempDir("mpi-start");
    const std::string solve = std::string(HEMIRAD_BINARY) + " solve " + sourcePath("scenes/unit_cube.obj") + " -o B.csv";
    const Run r = runMpirun(dir, "-np 2 -x PETSC_OPTIONS='-options_file missing.opts' " + solve);
    CHECK(r.status == 1);
    CHECK(count(r.output, "hemirad: error: ") == 1);
    CHECK(count(r.output, "hemirad: error: PETSc: initialisation failed: Unable to open options file missing.opts") == 1);
    CHECK(count(r.output, "terminate called") == 0);
    CHECK(count(r.output, "PETSC ERROR") == 0);
    CHECK_FALSE(std::filesystem::exists(dir / "B.csv"));
}

TEST_CASE("A rank whose main thread fails while its worker waits for rows ends the job with its message, no hang") {
    // issue 35 #12: an exception on a rank's main thread (here MPI_Test failing, a preloaded fault on
    // rank 1) left its worker thread waiting in the row queue, and the worker's join waited forever.
    // The failure is outside any agreement point: rank 1 says why and ends every rank (MPI_Abort).
    const auto dir = tempDir("mpi-main-thread-fails");
    const std::string command = std::string(HEMIRAD_BINARY) + " formfactors " + sourcePath("scenes/cornell_box.obj") +
                                " --subdivide 80 --samples 256 --threads 1 -o F.hff";
    const Run r = runMpirun(dir, "-np 1 " + command + " : -np 1 env LD_PRELOAD=" + HEMIRAD_TEST_MPI_TEST_FAILS + " " + command);
    CHECK(r.status == 1);  // 124: the timeout (a hang)
    CHECK(count(r.output, "mpi_test_fails: MPI_Test fails") == 1);  // the fault was in place
    CHECK(count(r.output, "hemirad: error: ") == 1);
    CHECK(count(r.output, "hemirad: error: rank 1 of 2: MPI: waiting for rows: ") == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "F.hff"));
}

TEST_CASE("One F file reused on 2 ranks: each rank reads its share of the rows, checked against the node's memory") {
    // issue 35 #12: every rank loaded all of F, with no memory check: the ranks of a node held it
    // that many times over. Here the available memory the ranks see is the test's (a preloaded probe).
    const auto dir = tempDir("mpi-reuse-memory");
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 80 --samples 256";
    for (const char* file : {"F.hff", "F.mtx"}) {
        const Run one = runHemirad(dir, 0, "solve " + scene + " --ff " + file + " --solver lu -o lu.csv --quiet");
        REQUIRE_MESSAGE(one.status == 0, one.output);
    }
    const std::uintmax_t size = std::filesystem::file_size(dir / "F.hff");
    REQUIRE(size > 1000000);  // 144620 entries; the N-sized arrays are 1 % of it
    const std::string roomy = withAvailableMemory(dir / "roomy", 2 * size), small = withAvailableMemory(dir / "small", size / 2);
    const std::string solve = std::string(HEMIRAD_BINARY) + " solve " + scene + " --threads 1 --tolerance 1e-13 -o B.csv --ff ";
    // 80 % of 2 |F|: room for each rank's share of the rows, not for all of F on each rank.
    Run r = runMpirun(dir, "-np 2 " + roomy + solve + "F.hff");
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(r.output.find("form factors: reused F.hff (519 rows") != std::string::npos);
    CHECK(largestRelativeDifference(radiosityColumns(dir / "B.csv"), radiosityColumns(dir / "lu.csv")) < 1e-8);
    // Half of |F|: refused on every rank before it is read, said once.
    std::filesystem::remove(dir / "B.csv");
    r = runMpirun(dir, "-np 2 " + small + solve + "F.hff");
    CHECK(r.status == 1);
    CHECK(count(r.output, "hemirad: error: ") == 1);
    CHECK(count(r.output, "hemirad: error: F.hff: the 2 ranks on this node would hold about ") == 1);
    CHECK(count(r.output, " of F together (each rank a share of its rows), more than the 0.7 MiB available") == 1);
    CHECK(count(r.output, "run fewer ranks on each node, or pass --no-memory-check") == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "B.csv"));
    r = runMpirun(dir, "-np 2 " + small + solve + "F.hff --no-memory-check");
    CHECK_MESSAGE(r.status == 0, r.output);
    CHECK(std::filesystem::exists(dir / "B.csv"));
    // An .mtx is read whole by every rank: refused where an .hff of the same F fits.
    r = runMpirun(dir, "-np 2 " + roomy + solve + "F.mtx");
    CHECK(r.status == 1);
    CHECK(count(r.output, "hemirad: error: ") == 1);
    CHECK(count(r.output, "hemirad: error: F.mtx: the 2 ranks on this node would hold about ") == 1);
    CHECK(count(r.output, "store F as .hff, whose rows each rank reads alone") == 1);
}

TEST_CASE("thermal on 2 MPI ranks solves the model on the ranks' rows (PETSc) within 1e-9 of one process, bands too") {
    // The radiator's model with the aluminium's solar mirror equal to its IR one: the solar band runs
    // on the same F, so nothing needs F whole. An isothermal node (power), adiabatic patches (flux
    // rows of reflectance 1), a held temperature, the sun and deep space: every part of the gray solve.
    const auto dir = tempDir("mpi-thermal-rows");
    const std::string example = sourcePath("examples/thermal/");
    writeFile(dir / "props.toml", "[materials.white_paint]\nemissivity = 0.88\nsolar_absorptance = 0.2\n"
                                  "[materials.aluminium]\nemissivity = 0.05\nspecular = 0.9\nsolar_absorptance = 0.08\n"
                                  "solar_specular = 0.9\n[materials.black_paint]\nemissivity = 0.9\nsolar_absorptance = 0.95\n");
    const std::string args = "thermal '" + example + "radiator.obj' --properties props.toml --bc '" + example +
                             "radiator_bc.toml' --subdivide 0.2 --threads 1";
    const Run one = runHemirad(dir, 0, args + " -o T1.csv --objects O1.csv");
    REQUIRE_MESSAGE(one.status == 0, one.output);
    CHECK(one.output.find("thermal solve: lu") != std::string::npos);
    const Run two = runHemirad(dir, 2, args + " -o T2.csv --objects O2.csv");
    REQUIRE_MESSAGE(two.status == 0, two.output);
    CHECK(count(two.output, "thermal: solved on F's rows where the 2 ranks hold them (PETSc)") == 1);
    CHECK(count(two.output, "thermal solve: bicgstab (PETSc, 2 ranks)") == 1);
    CHECK(two.output.find("F gathered") == std::string::npos);
    CHECK(count(two.output, "energy balance: ") == 1);
    CHECK(energyBalance(two.output) < 1e-9);
    // Per patch (T, J, H, absorbed sun, q, Q) and per object with the environment's power (what the
    // surfaces absorb of each patch's emission: F's columns, summed across the ranks).
    const double difference = tableDifference(dir / "T1.csv", dir / "T2.csv");
    const double objects = tableDifference(dir / "O1.csv", dir / "O2.csv");
    MESSAGE("largest relative difference, 1 process (LU) against 2 ranks (PETSc): patches " << difference << ", objects "
                                                                                           << objects);
    CHECK(difference < 1e-9);
    CHECK(objects < 1e-9);
    CHECK(difference > 0.0);  // another solver: not the one process's numbers copied
    // The solar band's powers (its escape from F's columns) to the 6 digits reported.
    CHECK(reportLine(one.output, "solar band: ").find(" W leave; balance ") != std::string::npos);
    CHECK(reportLine(one.output, "solar band: ").substr(0, 60) == reportLine(two.output, "solar band: ").substr(0, 60));
    CHECK(reportLine(one.output, "isothermal 'radiator': ") == reportLine(two.output, "isothermal 'radiator': "));
    // Two IR bands (limits at 5 um) with one mirror for both: the band model's fixed point, each step's
    // bands on the ranks' rows, against one process. At 1e-12: the fixed point's balance at the
    // default 1e-10 is about 1e-9, in one process's BiCGSTAB too.
    writeFile(dir / "bands.toml", "[bands]\nlimits_um = [5.0]\n[materials.white_paint]\nemissivity = [0.6, 0.9]\n"
                                  "solar_absorptance = 0.2\n[materials.aluminium]\nemissivity = [0.03, 0.08]\n"
                                  "specular = 0.9\nsolar_absorptance = 0.08\nsolar_specular = 0.9\n"
                                  "[materials.black_paint]\nemissivity = [0.8, 0.9]\nsolar_absorptance = 0.95\n");
    const std::string banded = "thermal '" + example + "radiator.obj' --properties bands.toml --bc '" + example +
                               "radiator_bc.toml' --subdivide 0.2 --threads 1 --tolerance 1e-12";
    const Run oneBands = runHemirad(dir, 0, banded + " -o B1.csv --objects BO1.csv");
    REQUIRE_MESSAGE(oneBands.status == 0, oneBands.output);
    const Run twoBands = runHemirad(dir, 2, banded + " -o B2.csv --objects BO2.csv");
    REQUIRE_MESSAGE(twoBands.status == 0, twoBands.output);
    CHECK(count(twoBands.output, "thermal: solved on F's rows where the 2 ranks hold them (PETSc)") == 1);
    CHECK(count(twoBands.output, "IR bands: 2 split at 5 um") == 1);
    CHECK(energyBalance(twoBands.output) < 1e-9);
    const double bands = tableDifference(dir / "B1.csv", dir / "B2.csv");
    const double bandObjects = tableDifference(dir / "BO1.csv", dir / "BO2.csv");
    MESSAGE("two IR bands: patches " << bands << ", objects " << bandObjects);
    CHECK(bands < 1e-9);
    CHECK(bandObjects < 1e-9);
    CHECK(tableDifference(dir / "T1.csv", dir / "B1.csv") > 1e-3);  // the bands change the answer
    // A solver that runs in one process: the rows are gathered for rank 0, the same bytes.
    const Run lu = runHemirad(dir, 2, args + " --solver lu -o T3.csv");
    REQUIRE_MESSAGE(lu.status == 0, lu.output);
    CHECK(count(lu.output, "thermal: F gathered on rank 0 (--solver lu runs in one process)") == 1);
    CHECK(bytes(dir / "T1.csv") == bytes(dir / "T3.csv"));
    // Every flux, no temperature, no environment in a closed box (faces inward): the same refusal on
    // every rank, one message, nothing written.
    writeFile(dir / "closed.toml", "[default]\nadiabatic = true\n");
    writeFile(dir / "closed.obj", "o box\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                  "f 1 2 3 4\nf 8 7 6 5\nf 5 6 2 1\nf 6 7 3 2\nf 7 8 4 3\nf 8 5 1 4\n");
    const Run closed = runHemirad(dir, 2, "thermal closed.obj --bc closed.toml --unit m -o T4.csv");
    CHECK(closed.status == 1);
    // Every rank loads the box and finds its faces without a material: rank 0 alone says so.
    CHECK(count(closed.output, "face(s) before any usemtl get the default material") == 1);
    // The same with an environment that the closed box cannot see: refused before any solve (BiCGSTAB
    // across the ranks would have found the adiabatic box's source 0 and written 0 K).
    writeFile(dir / "closed_env.toml", "[environment]\ntemperature_K = 3\n[default]\nadiabatic = true\n");
    const Run unseen = runHemirad(dir, 2, "thermal closed.obj --bc closed_env.toml --unit m -o T5.csv");
    CHECK(unseen.status == 1);
    CHECK(count(unseen.output, "hemirad: error: ") == 1);
    CHECK(count(unseen.output, "in a closed enclosure that sees nothing of the environment") == 1);
    CHECK(!std::filesystem::exists(dir / "T5.csv"));
    CHECK(count(closed.output, "hemirad: error: ") == 1);
    CHECK(count(closed.output, "the temperatures are not determined") == 1);
    CHECK(count(closed.output, "thermal: solved on F's rows where the 2 ranks hold them (PETSc)") == 1);
    CHECK(!std::filesystem::exists(dir / "T4.csv"));
}

TEST_CASE("thermal on 2 MPI ranks writes the one-process temperatures, conductors and exchange byte for byte") {
    // F's rows computed across the ranks (and a stored F's rows read by each), gathered for rank 0's
    // solve: the same F, so the same numbers (issue 36: 1 and 2 ranks agree). One thread in both: the
    // conductors' dense factorisation (LAPACK) blocks by thread count, so its last bits follow it.
    const auto dir = tempDir("mpi-thermal");
    const std::string example = sourcePath("examples/thermal/");
    const std::string args = "thermal '" + example + "radiator.obj' --properties '" + example +
                             "radiator_properties.toml' --bc '" + example + "radiator_bc.toml' --subdivide 0.2";
    const Run one = runHemirad(dir, 0, args + " --quiet --threads 1 -o T1.csv --conductors GR1.esatan --exchange Q1.csv");
    REQUIRE_MESSAGE(one.status == 0, one.output);
    const Run two = runHemirad(dir, 2, args + " --threads 1 -o T2.csv --conductors GR2.esatan --exchange Q2.csv --ff F.hff");
    REQUIRE_MESSAGE(two.status == 0, two.output);
    CHECK(two.output.find("ranks 2: rows ") != std::string::npos);  // the rows were shared
    CHECK(bytes(dir / "T1.csv") == bytes(dir / "T2.csv"));
    CHECK(bytes(dir / "GR1.esatan") == bytes(dir / "GR2.esatan"));
    CHECK(bytes(dir / "Q1.csv") == bytes(dir / "Q2.csv"));
    CHECK(count(two.output, "thermal: F gathered on rank 0 (a solar band with mirrors of its own, --conductors, --exchange: F whole in one process)") == 1);
    // The stored F serves a second run across the ranks: read, not recomputed, the same answer (the
    // solar band's own mirrors keep this model's solve on rank 0: the same bytes).
    const Run again = runHemirad(dir, 2, args + " --threads 1 -o T3.csv --ff F.hff");
    REQUIRE_MESSAGE(again.status == 0, again.output);
    CHECK(again.output.find("form factors: reused F.hff") != std::string::npos);
    CHECK(count(again.output, "thermal: F gathered on rank 0 (a solar band with mirrors of its own: F whole in one process)") == 1);
    CHECK(bytes(dir / "T1.csv") == bytes(dir / "T3.csv"));
    // A mistake in the model: one message, every rank stops, nothing written.
    writeFile(dir / "bad.toml", "[default]\nadiabatic = true\n[objects.nothing]\npower_W = 1\n");
    const Run bad = runHemirad(dir, 2, "thermal '" + example + "radiator.obj' --bc bad.toml -o T4.csv");
    CHECK(bad.status == 1);
    CHECK(count(bad.output, "bad.toml:3: [objects.nothing] names no object") == 1);
    CHECK(!std::filesystem::exists(dir / "T4.csv"));
}
