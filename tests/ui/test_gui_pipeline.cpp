// hemirad-gui's Pipeline panel and log under Xvfb (issue 38 #15): what Run will do, and what F's
// statistics mean, worded as the CLI's report. Needs xvfb-run (scripts/install-deps.sh).
#include "ui/gui_run.hpp"

using namespace hemirad::test;

TEST_CASE("hemirad-gui's Run line for the analytic estimator counts shadow rays and says no directions are cast (issue 38 #15)") {
    // It read "Run: 20 rows x 20 rays", as if directions were cast.
    std::string log;
    runGui("gui-run-line", sourcePath("scenes/cornell_box.obj"), log);
    INFO(log);
    const std::size_t at = log.find("hemirad-gui: Run: ");
    REQUIRE(at != std::string::npos);
    const std::string line = log.substr(at, log.find('\n', at) - at);
    CHECK(line.find("Run: 20 rows of analytic factors (20 shadow rays a row, no directions cast)") != std::string::npos);
    CHECK(line.find(" x 20 rays") == std::string::npos);
}

TEST_CASE("hemirad-gui explains a row sum of 0 and a reciprocity max near 1 as the CLI does (issue 38 #15)") {
    // A floor and a light above it facing away: neither sees the other (row sums 0); 16 directions
    // decide single pairs (reciprocity max near 1).
    const auto dir = tempDir("gui-stats-notes");
    writeFile(dir / "apart.mtl", "newmtl white\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0.5 0.5 0.5\nKe 10 10 10\n");
    const std::string scene = writeFile(dir / "apart.obj", "mtllib apart.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
                                                            "v 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\no floor\nusemtl white\nf 1 4 3 2\n"
                                                            "o light\nusemtl light\nf 5 8 7 6\n");
    std::string log;
    runGui("gui-stats-notes-run", scene + " --estimator rays --samples 16 --run", log);
    INFO(log);
    const std::string zero = "a row sum of 0 is a patch that sees no patch";
    CHECK(log.find("form factors: " + zero) != std::string::npos);
    const CommandResult cli = runCommand(std::string(HEMIRAD_BINARY) + " formfactors " + scene + " --estimator rays --samples 16 -o " +
                                         (dir / "F.mtx").string() + " 2>&1");
    INFO(cli.output);
    REQUIRE(cli.status == 0);
    CHECK(cli.output.find(zero) != std::string::npos);
    // Reciprocity: the Cornell box with 16 directions.
    runGui("gui-stats-notes-cornell", sourcePath("scenes/cornell_box.obj") + " --subdivide 60 --estimator rays --samples 16 --run", log);
    CHECK(log.find("form factors: the reciprocity max compares single pairs") != std::string::npos);
}
