// hemirad under mpirun (2 ranks, as root in CI): F byte-identical to one process, the PETSc solve
// against the one-process LU solve, and errors that end every rank with one message and no hang.
#include "support.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
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

std::string bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE(in.good());
    return std::string((std::istreambuf_iterator<char>(in)), {});
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

void checkSameF(const std::string& scene, const std::string& flags) {
    const auto dir = tempDir("mpi-f");
    const Run one = runHemirad(dir, 0, "formfactors " + sourcePath("scenes/" + scene) + " -o one.hff --quiet " + flags);
    REQUIRE_MESSAGE(one.status == 0, one.output);
    const Run two = runHemirad(dir, 2, "formfactors " + sourcePath("scenes/" + scene) + " -o two.hff --threads 1 " + flags);
    REQUIRE_MESSAGE(two.status == 0, two.output);
    CHECK(two.output.find("on 2 MPI ranks") != std::string::npos);
    CHECK(bytes(dir / "one.hff").size() > 1000);
    CHECK(bytes(dir / "one.hff") == bytes(dir / "two.hff"));
}

}  // namespace

TEST_CASE("F from 2 MPI ranks is byte-identical to one process: hemisphere rays with mirrors") {
    checkSameF("cornell_mirror.obj", "--subdivide 60 --estimator rays --samples 256 --origins 2");
}

TEST_CASE("F from 2 MPI ranks is byte-identical to one process: hemisphere analytic with mirrors") {
    checkSameF("cornell_mirror.obj", "--subdivide 80 --estimator analytic --samples 256");
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
    r = runHemirad(dir, 2, "solve " + scene + " -o B.csv --enforce-reciprocity");
    CHECK(r.status == 2);
    CHECK(count(r.output, "--enforce-reciprocity averages pairs of rows that different ranks hold") == 1);
    r = runHemirad(dir, 2, "formfactors " + scene + " -o F.hff --bogus");
    CHECK(r.status == 2);
    CHECK(count(r.output, "unknown option '--bogus'") == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "F.hff"));
}
