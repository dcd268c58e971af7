// Running hemirad-gui under Xvfb and checking its screenshot, for test_gui.cpp and the build without
// Embree (test_without_embree.cpp). Needs xvfb-run (scripts/install-deps.sh); without it a test fails.
#pragma once

#include "support.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdlib>
#include <string>
#include <sys/wait.h>
#include <vector>

#include <stb/stb_image.h>

namespace hemirad::test {


struct Image {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
    const unsigned char* at(int x, int y) const { return &rgb[(std::size_t(y) * width + x) * 3]; }
    /// Mean colour over a rectangle.
    std::array<double, 3> mean(int x0, int y0, int x1, int y1) const {
        std::array<double, 3> sum{};
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                for (int c = 0; c < 3; ++c) sum[c] += at(x, y)[c];
        const double n = double(x1 - x0) * (y1 - y0);
        return {sum[0] / n, sum[1] / n, sum[2] / n};
    }
};

/// A panel's rectangle in window pixels.
struct Panel {
    std::string name;
    double x, y, w, h;
};

/// The panel rectangles a scripted run prints ("hemirad-gui: panel NAME at X,Y size WxH"), or with
/// `kind` "item" the controls' ("hemirad-gui: item NAME ...").
inline std::vector<Panel> panelsOf(const std::string& log, const std::string& kind = "panel") {
    std::vector<Panel> panels;
    std::size_t at = 0;
    const std::string prefix = "hemirad-gui: " + kind + " ";
    while ((at = log.find(prefix, at)) != std::string::npos) {
        char name[64] = {};
        Panel p;
        REQUIRE(std::sscanf(log.c_str() + at + prefix.size(), "%63s at %lf,%lf size %lfx%lf", name, &p.x, &p.y, &p.w, &p.h) == 5);
        p.name = name;
        panels.push_back(p);
        ++at;
    }
    return panels;
}

/// The panel (or with `kind` "item", the control) `name` a scripted run printed; fails the test
/// when there is none.
inline Panel panelOf(const std::string& log, const std::string& name, const std::string& kind = "panel") {
    for (const Panel& p : panelsOf(log, kind))
        if (p.name == name) return p;
    FAIL("no " << kind << " " << name << " in the log");
    return {};
}

/// A PNG's pixels as 8-bit RGB.
inline Image loadImage(const std::string& png) {
    Image image;
    int channels = 0;
    unsigned char* data = stbi_load(png.c_str(), &image.width, &image.height, &channels, 3);
    REQUIRE_MESSAGE(data != nullptr, "cannot read " << png);
    image.rgb.assign(data, data + std::size_t(image.width) * image.height * 3);
    stbi_image_free(data);
    return image;
}

/// Runs `hemirad-gui ARGUMENTS --screenshot ... --exit` under Xvfb (1280x800 window) and requires a
/// clean exit. Returns the screenshot; the log goes to `log`.
inline Image runGui(const std::string& name, const std::string& arguments, std::string& log) {
    REQUIRE_MESSAGE(std::system("command -v xvfb-run > /dev/null") == 0, "xvfb-run is missing (scripts/install-deps.sh)");
    const auto dir = tempDir(name);
    const std::string png = (dir / "gui.png").string();
    const std::string logPath = (dir / "log.txt").string();
    // Under `make test-sanitize` the GUI process runs without LeakSanitizer: Mesa's driver is unloaded
    // at exit and its allocations can no longer be attributed (or suppressed) by module name.
    const std::string command = "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 "
                                "xvfb-run -a -s '-screen 0 1400x900x24' " + std::string(HEMIRAD_GUI_BINARY) + " " +
                                arguments + " --screenshot " + png + " --exit > " + logPath + " 2>&1";
    const int status = std::system(command.c_str());
    log = readText(logPath);
    INFO(log);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
    Image image = loadImage(png);
    CHECK(image.width == 1280);
    CHECK(image.height == 800);
    return image;
}

/// Runs tests/ui/SCRIPT, a keyboard script (xdotool taps keys into hemirad-gui under Xvfb), with the
/// GUI's binary and `arguments` (in `folder` when given), and checks that the script and the GUI
/// exited 0. Returns the script's output; the GUI's log is where `arguments` told the script to put it.
inline std::string runKeyboardScript(const std::string& script, const std::string& arguments, const std::string& folder = "") {
    REQUIRE_MESSAGE(std::system("command -v xvfb-run > /dev/null && command -v xdotool > /dev/null") == 0,
                    "xvfb-run or xdotool is missing (scripts/install-deps.sh)");
    const CommandResult run = runCommand((folder.empty() ? std::string() : "cd '" + folder + "' && ") + "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 xvfb-run -a -s '-screen 0 1400x900x24' " +
                                         sourcePath("tests/ui/" + script) + " " + HEMIRAD_GUI_BINARY + " " + arguments + " 2>&1");
    INFO(run.output);
    CHECK(run.status == 0);
    CHECK(run.output.find("hemirad-gui exit 0") != std::string::npos);
    return run.output;
}

/// Runs hemirad-gui on the subdivided Cornell box with `methodFlags`, then checks the screenshot:
/// not blank, the red wall left and the green one right (`walls` false: not checked, for a selection
/// panel over the right side or a false-colour view), ImGui's menu bar drawn. Returns the log; the
/// screenshot goes to `picture` when given.
inline std::string runGuiAndCheckPicture(const std::string& name, const std::string& methodFlags, bool walls = true,
                                         Image* picture = nullptr) {
    std::string output;
    Image image = runGui(name, sourcePath("scenes/cornell_box.obj") + " --subdivide 60 " + methodFlags + " --run", output);
    INFO(output);

    // Not blank: the view has bright and dark pixels.
    const auto whole = image.mean(0, 0, image.width, image.height);
    CHECK(whole[0] + whole[1] + whole[2] > 60.0);
    // The Cornell camera sees the red wall (x = 556) on the left, the green one (x = 0) on the right.
    const int y0 = image.height * 40 / 100, y1 = image.height * 60 / 100;
    const auto left = image.mean(image.width * 22 / 100, y0, image.width * 28 / 100, y1);
    const auto right = image.mean(image.width * 72 / 100, y0, image.width * 78 / 100, y1);
    if (walls) {
        CHECK(left[0] > 1.8 * left[1]);    // red
        CHECK(right[1] > 1.3 * right[0]);  // green
    }
    // The UI is drawn: ImGui's menu bar (grey 36) runs along the top of the window.
    const auto menu = image.mean(200, 2, image.width - 200, 16);
    for (int c = 0; c < 3; ++c) CHECK(menu[c] == doctest::Approx(36.0).epsilon(0.3));
    if (picture) *picture = std::move(image);
    return output;
}

}  // namespace hemirad::test
