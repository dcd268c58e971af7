// hemirad-gui's view under Xvfb (issue 38): the up axis the camera frames and orbits about, and the
// selection drawn as an outline that leaves the selected patches' colours as they are.
// Needs xvfb-run (scripts/install-deps.sh); without it the tests fail, never skip.
#include "ui/gui_run.hpp"

#include <cctype>
#include <cstdlib>
#include <sstream>

using namespace hemirad::test;

namespace {

/// The patch-id layer's colour of patch `id` (viewer_present.frag's hashColor of id + 1), 8-bit.
std::array<int, 3> idColour(std::uint32_t id) {
    const std::uint32_t h = (id + 1) * 2654435761u;
    const auto channel = [](std::uint32_t v) { return int(std::lround((double(v & 255u) / 255.0 * 0.8 + 0.2) * 255.0)); };
    return {channel(h >> 16), channel(h >> 8), channel(h)};
}

bool near(const unsigned char* c, const std::array<int, 3>& want) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(int(c[k]) - want[k]) > 1) return false;
    return true;
}

/// A Z-up site: a 100 x 100 ground plate at z = 0 (patch 0) and a post 1 wide standing `height` high
/// on it (patch 1), in the plane y = 50. With a 100-high post the bounding box is as high as it is
/// deep: nothing says z is up but `header`.
std::string site(const std::filesystem::path& dir, const std::string& name, int height, const std::string& header = "") {
    writeFile(dir / "site.mtl", "newmtl ground\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0.5 0.5 0.5\nKe 10 10 10\n");
    const std::string h = std::to_string(height);
    return writeFile(dir / name, header + "mtllib site.mtl\nv 0 0 0\nv 100 0 0\nv 100 100 0\nv 0 100 0\no ground\nusemtl ground\n"
                                          "f 1 2 3 4\nv 50 50 0\nv 51 50 0\nv 51 50 " + h + "\nv 50 50 " + h +
                                          "\no post\nusemtl light\nf 5 6 7 8\n");
}

/// Whether the post (patch 1 in the patch-id layer) stands upright in the view, between the panels:
/// its pixels span a tall, narrow box. Lying (the view's up along y) they span a wide, flat one.
bool postStands(const Image& image) {
    int x0 = image.width, x1 = -1, y0 = image.height, y1 = -1;
    for (int y = 30; y < 600; ++y)
        for (int x = 360; x < 920; ++x)
            if (near(image.at(x, y), idColour(1))) {
                x0 = std::min(x0, x), x1 = std::max(x1, x);
                y0 = std::min(y0, y), y1 = std::max(y1, y);
            }
    MESSAGE("post: ", x1 - x0 + 1, " x ", y1 - y0 + 1, " px");
    return x1 >= 0 && y1 - y0 > 30 && y1 - y0 > 3 * (x1 - x0);
}

/// The up axis and the view direction hemirad-gui printed.
std::string upAxisLine(const std::string& log) {
    const std::size_t at = log.find("hemirad-gui: up axis ");
    REQUIRE(at != std::string::npos);
    return log.substr(at, log.find('\n', at) - at);
}

}  // namespace

TEST_CASE("hemirad-gui frames a flat Z-up site with z up: the up axis guessed from the bounding box (issue 38 #12)") {
    // With y up a Z-up model lay on its side (the post horizontal), framed from its open side.
    const auto dir = tempDir("gui-up-guess");
    std::string log;
    const Image image = runGui("gui-up-guess-run", site(dir, "flat.obj", 20) + " --layer patch-id", log);
    INFO(log);
    CHECK(upAxisLine(log).find("up axis z, guessed from the bounding box") != std::string::npos);
    CHECK(postStands(image));
}

TEST_CASE("hemirad-gui takes the up axis an OBJ states ('# hemirad up z') where the bounding box says nothing (issue 38 #12)") {
    const auto dir = tempDir("gui-up-stated");
    std::string log;
    // Without the line the site with its 100-high post is as high as deep: y is guessed, the post lies.
    Image image = runGui("gui-up-unstated-run", site(dir, "mast.obj", 100) + " --layer patch-id", log);
    CHECK(upAxisLine(log).find("up axis y, guessed from the bounding box") != std::string::npos);
    CHECK_FALSE(postStands(image));
    image = runGui("gui-up-stated-run", site(dir, "stated.obj", 100, "# hemirad up z\n") + " --layer patch-id", log);
    INFO(log);
    CHECK(upAxisLine(log).find("up axis z, stated in the OBJ") != std::string::npos);
    CHECK(postStands(image));
}

TEST_CASE("hemirad-gui's up-axis choice is remembered for the scene's file and saved with it (issue 38 #12)") {
    const auto dir = tempDir("gui-up-chosen");
    REQUIRE(setenv("XDG_CONFIG_HOME", (dir / "config").c_str(), 1) == 0);  // the GUI's memory, this test's own
    const std::string scene = site(dir, "mast.obj", 100);
    std::string log;
    // --up z is the Scene panel's choice; the next run of the same file takes it without being told.
    Image image = runGui("gui-up-chosen-run", scene + " --layer patch-id --up z", log);
    CHECK(upAxisLine(log).find("up axis z, remembered for this file") != std::string::npos);
    CHECK(postStands(image));
    image = runGui("gui-up-recalled-run", scene + " --layer patch-id", log);
    INFO(log);
    CHECK(upAxisLine(log).find("up axis z, remembered for this file") != std::string::npos);
    CHECK(postStands(image));
    const std::string view = upAxisLine(log);
    double x = 0, y = 0, z = 0;
    REQUIRE(std::sscanf(view.c_str() + view.find("view from ") + 10, "%lf %lf %lf", &x, &y, &z) == 3);
    CHECK(z > 0.2);  // from above the ground
    CHECK(readText(dir / "config/hemirad/up-axes").find("z " + scene) != std::string::npos);
    // Another user (no memory) gets the guess again.
    REQUIRE(setenv("XDG_CONFIG_HOME", (dir / "other").c_str(), 1) == 0);
    image = runGui("gui-up-forgotten-run", scene + " --layer patch-id", log);
    CHECK(upAxisLine(log).find("up axis y, guessed from the bounding box") != std::string::npos);
    CHECK_FALSE(postStands(image));
}

TEST_CASE("hemirad-gui outlines the selection: a selected patch keeps its false colour, a ring around it shows it (issue 38 #7)") {
    // The tint over the false colour changed the selected patch's colour, so its value could not be
    // read against the legend, and a single selected patch was barely visible.
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 60 --estimator rays --samples 256";
    std::string log;
    // The patch in the middle of the back wall, from the patch-id layer.
    const Image ids = runGui("gui-outline-ids", scene + " --layer patch-id", log);
    const int vx = ids.width / 2 + 60, vy = ids.height / 2 - 120;
    std::uint32_t patch = 0;
    while (patch < 5000 && !near(ids.at(vx, vy), idColour(patch))) ++patch;
    REQUIRE(patch < 5000);
    const std::string falseColour = scene + " --false-color irradiance --run";
    const Image plain = runGui("gui-outline-plain", falseColour, log);
    const Image selected = runGui("gui-outline-selected", falseColour + " --select " + std::to_string(patch), log);
    INFO(log);
    // Inside the patch (its pixels in the id layer, those next to another patch left out) the false
    // colour is as without a selection; around it, within 3 px, the outline: orange, then black.
    std::size_t inside = 0, same = 0, ring = 0, orange = 0;
    for (int y = 40; y < 590; ++y)
        for (int x = 370; x < 910; ++x) {
            bool interior = true, nearPatch = false;
            for (int dy = -3; dy <= 3; ++dy)
                for (int dx = -3; dx <= 3; ++dx) {
                    const bool on = near(ids.at(x + dx, y + dy), idColour(patch));
                    if (std::max(std::abs(dx), std::abs(dy)) <= 1) interior &= on;
                    nearPatch |= on;
                }
            const unsigned char *a = plain.at(x, y), *b = selected.at(x, y);
            const bool changed = a[0] != b[0] || a[1] != b[1] || a[2] != b[2];
            if (interior) {
                ++inside;
                same += !changed;
            } else if (changed) {
                ++ring;
                CHECK(nearPatch);  // nothing changes away from the selection
                orange += b[0] == 255 && b[1] == 89 && b[2] == 0;
            }
        }
    MESSAGE("patch ", patch, ": ", inside, " pixels inside, ", same, " unchanged; ", ring, " changed around it, ", orange, " orange");
    CHECK(inside > 200);
    CHECK(same == inside);
    CHECK(orange > 100);  // 2 px around a patch of about 20 x 20 px
    // In the radiosity view the same ring stands out of the shading.
    const Image radiosity = runGui("gui-outline-radiosity", scene + " --run --select " + std::to_string(patch), log);
    std::size_t shown = 0;
    for (int y = 40; y < 590; ++y)
        for (int x = 370; x < 910; ++x) shown += radiosity.at(x, y)[0] == 255 && radiosity.at(x, y)[1] == 89 && radiosity.at(x, y)[2] == 0;
    CHECK(shown > 100);
}

namespace {

/// The legend's tick labels a scripted run printed.
std::vector<std::string> legendTicksOf(const std::string& log) {
    const std::size_t at = log.find("hemirad-gui: legend ticks: ");
    REQUIRE(at != std::string::npos);
    std::istringstream line(log.substr(at + 27, log.find('\n', at) - at - 27));
    std::vector<std::string> ticks;
    for (std::string tick; std::getline(line, tick, '|');) ticks.push_back(tick.substr(tick.find_first_not_of(' '), tick.find_last_not_of(' ') + 1));
    return ticks;
}

/// Significant digits of a label: "0.8751" 4, "0.2" 1, "150" 2, "1e-05" 1.
int significantDigits(const std::string& label) {
    std::string digits;
    for (char c : label.substr(0, label.find('e')))
        if (std::isdigit(static_cast<unsigned char>(c))) digits += c;
    digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size()));
    while (!digits.empty() && digits.back() == '0') digits.pop_back();
    return int(digits.size());
}

}  // namespace

TEST_CASE("hemirad-gui's legend is labelled with round values: at most two significant digits each (issue 38 #15)") {
    std::string log;
    runGui("gui-legend-ticks", sourcePath("scenes/cornell_box.obj") + " --subdivide 60 --estimator rays --samples 256 --false-color irradiance --run", log);
    INFO(log);
    const std::vector<std::string> ticks = legendTicksOf(log);
    CHECK(ticks.size() >= 2);
    CHECK(ticks.size() <= 7);
    for (const std::string& t : ticks) {
        CAPTURE(t);
        CHECK(significantDigits(t) <= 2);
    }
    CHECK(significantDigits("0.8751") == 4);  // what the legend showed
}

TEST_CASE("hemirad-gui's F-row layer has a scale: the legend's bar in the layer's colours, log values from the row's largest factor (issue 38 #15)") {
    std::string log;
    const Image image =
        runGui("gui-row-legend", sourcePath("scenes/cornell_box.obj") + " --subdivide 60 --estimator rays --samples 256 --layer f-row --select 0 --run", log);
    INFO(log);
    const Panel bar = panelOf(log, "LegendBar");
    // The ramp of viewer_present.frag at its ends: dark blue at the bottom, yellow at the top.
    const unsigned char* top = image.at(int(bar.x + bar.w / 2), int(bar.y));
    const unsigned char* bottom = image.at(int(bar.x + bar.w / 2), int(bar.y + bar.h) - 1);
    CHECK(near(top, {255, 194, 25}));
    CHECK(near(bottom, {0, 26, 229}));
    const std::vector<std::string> ticks = legendTicksOf(log);
    REQUIRE(ticks.size() >= 4);  // the powers of ten across 4 decades
    CHECK(std::stod(ticks.back()) / std::stod(ticks.front()) >= 999.0);
}
