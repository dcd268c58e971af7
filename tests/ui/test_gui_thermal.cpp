// hemirad-gui's thermal section under Xvfb: the bundled radiator's files loaded and run, the
// radiator's T drawn in the Scene panel as `hemirad thermal` reports it, T in false colour with its
// legend (title and unit), the exchange table drawn; a refused boundary-condition file.
#include "render/false_colour.hpp"
#include "ui/gui_run.hpp"

#include <algorithm>
#include <cstdio>

using namespace hemirad::test;

namespace {

const std::string kScene = "examples/thermal/radiator.obj";

std::string thermalFiles() {
    return " --properties " + sourcePath("examples/thermal/radiator_properties.toml") + " --bc " +
           sourcePath("examples/thermal/radiator_bc.toml");
}

/// The number after `prefix` in `text`.
double numberAfter(const std::string& text, const std::string& prefix) {
    const std::size_t at = text.find(prefix);
    INFO(prefix);
    REQUIRE(at != std::string::npos);
    return std::stod(text.substr(at + prefix.size()));
}

double cliRadiatorT() {
    const auto dir = tempDir("gui-thermal-panel-cli");
    const CommandResult cli = runCommand(std::string(HEMIRAD_BINARY) + " thermal " + sourcePath(kScene) + thermalFiles() + " -o " +
                                         (dir / "T.csv").string() + " 2>&1");
    INFO(cli.output);
    REQUIRE(cli.status == 0);
    return numberAfter(cli.output, "isothermal 'radiator': T = ");
}

}  // namespace

TEST_CASE("hemirad-gui runs thermal on the radiator: its T in the Scene panel as hemirad thermal's, T in false colour in K") {
    const double cliT = cliRadiatorT();
    std::string log;
    const std::string flags = " --thermal --false-color temperature --thermal-window --hover 0";
    Image image = runGui("gui-thermal", sourcePath(kScene) + thermalFiles() + flags, log);
    INFO(log);
    // The status bar reads the hovered radiator patch's T (4 digits) and q out.
    char expected[64];
    std::snprintf(expected, sizeof expected, " | T %.4g K, q ", cliT);
    const std::size_t status = log.find("hemirad-gui: status: patch 0 'radiator'");
    REQUIRE(status != std::string::npos);
    CHECK(log.find(expected, status) != std::string::npos);
    // The Scene panel's Thermal section draws the isothermal node's T and the balance.
    CHECK(numberAfter(log, "hemirad-gui: thermal panel: isothermal 'radiator': T = ") == doctest::Approx(cliT).epsilon(1e-5));
    CHECK(log.find("hemirad-gui: thermal panel: energy balance ") != std::string::npos);
    CHECK(log.find("hemirad-gui: isothermal 'radiator': T = ") != std::string::npos);  // and the log
    // The legend as drawn: the thermal quantity's title and its unit.
    CHECK(log.find("hemirad-gui: legend: temperature T | K\n") != std::string::npos);
    double lo = 0, hi = 0;
    const std::size_t at = log.find("hemirad-gui: false colour: temperature T, linear scale ");
    REQUIRE(at != std::string::npos);
    REQUIRE(std::sscanf(log.c_str() + at, "hemirad-gui: false colour: temperature T, linear scale %lf .. %lf", &lo, &hi) == 2);
    CHECK(lo > 3.0);  // kelvin, above deep space
    CHECK(hi >= cliT - 1e-3);
    // The exchange table's window: headings with the unit, one row per object.
    CHECK(log.find("hemirad-gui: exchange table: Q from \\ to (W) | radiator | shield | baffle | environment | total") !=
          std::string::npos);
    CHECK(log.find("hemirad-gui: exchange table: radiator | ") != std::string::npos);
    // The legend's bar is drawn in the map's colours (its top row viridis(1)).
    const std::size_t bar = log.find("hemirad-gui: panel LegendBar at ");
    REQUIRE(bar != std::string::npos);
    double x = 0, y = 0, w = 0, h = 0;
    REQUIRE(std::sscanf(log.c_str() + bar, "hemirad-gui: panel LegendBar at %lf,%lf size %lfx%lf", &x, &y, &w, &h) == 4);
    const auto top = hemirad::viridis(1.0);
    const unsigned char* pixel = image.at(int(x + w / 2), int(y));
    CHECK(int(pixel[0]) == int(top[0]));
    CHECK(int(pixel[1]) == int(top[1]));
    CHECK(int(pixel[2]) == int(top[2]));
}

TEST_CASE("hemirad-gui shows an invalid boundary-condition file's file:line error and keeps the conditions it had") {
    const double cliT = cliRadiatorT();
    const auto dir = tempDir("gui-thermal-bad-bc");
    const std::string bad = (dir / "bad_bc.toml").string();
    {
        std::FILE* f = std::fopen(bad.c_str(), "w");
        REQUIRE(f != nullptr);
        std::fputs("[objects.radiator]\npower_W = 250\n[objects.shield]\ntemperature_K = -4\n", f);
        std::fclose(f);
    }
    // The good file, then the bad one (as pressing Load twice), then Run thermal.
    const CommandResult run = runCommand("ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 xvfb-run -a -s '-screen 0 1400x900x24' " +
                                         std::string(HEMIRAD_GUI_BINARY) + " " + sourcePath(kScene) + thermalFiles() + " --bc " + bad +
                                         " --thermal --exit 2>&1");
    INFO(run.output);
    CHECK(run.status != 0);  // an error was logged
    CHECK(run.output.find("hemirad-gui: error: " + bad + ":4:") != std::string::npos);
    // Nothing changed: the run used the good file's conditions.
    CHECK(numberAfter(run.output, "hemirad-gui: thermal panel: isothermal 'radiator': T = ") == doctest::Approx(cliT).epsilon(1e-5));
}
