// hemirad-gui driven by mouse and keyboard under Xvfb (issue 38): the file browser's double-click,
// the Run estimate after opening another scene, frames after every input. Needs xvfb-run and
// xdotool (scripts/install-deps.sh).
#include "ui/gui_run.hpp"

#include <cstdlib>

using namespace hemirad::test;

TEST_CASE("hemirad-gui's file browser: a double-click on a folder enters it and opens nothing (issue 38 #1)") {
    // The folder's second click landed on the new listing's row under the pointer, a file, and opened it.
    const auto dir = tempDir("gui-double-click");
    REQUIRE(setenv("XDG_CONFIG_HOME", (dir / "config").c_str(), 1) == 0);  // no recent folders: a fixed layout
    const auto browse = dir / "browse";
    std::filesystem::create_directories(browse / "sub");
    writeFile(browse / "sub/m.mtl", "newmtl white\nKd 0.5 0.5 0.5\n");
    for (const char* name : {"b.obj", "c.obj"})
        writeFile(browse / "sub" / name, "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl white\nf 1 2 3\n");
    // The browser lists "..", "sub/" in the folder the GUI starts in, then "..", b.obj, c.obj in sub:
    // sub's row is b.obj's. Where the rows are: a first run opens the browser and prints them.
    const std::string log = (dir / "gui.log").string();
    runKeyboardScript("keyboard_keys.sh", log + " 12 '' ctrl+o", browse.string());
    const Panel row = panelOf(readText(log), "FilesRow1");
    const std::string at = std::to_string(int(row.x + 40)) + "," + std::to_string(int(row.y + row.h / 2));
    // Double-click sub/, then type c.obj and Enter: only c.obj is opened, from sub.
    runKeyboardScript("keyboard_keys.sh", log + " 25 '' ctrl+o dblclick:" + at + " type:c.obj Return", browse.string());
    const std::string output = readText(log);
    INFO(output);
    CHECK(output.find("b.obj") == std::string::npos);
    CHECK(output.find("loaded " + (browse / "sub/c.obj").string()) != std::string::npos);
}

TEST_CASE("hemirad-gui times Run from a run on the same mesh only: after another scene it says nothing yet (issue 38 #5)") {
    // After the 20-patch Cornell box, a 315-patch mesh was announced at "about 14.22 s" and took 0.11 s.
    const auto dir = tempDir("gui-estimate");
    const std::string log = (dir / "gui.log").string();
    runKeyboardScript("keyboard_keys.sh", log + " 30 '" + sourcePath("scenes/cornell_box.obj") + " --run' ctrl+o type:" +
                                              sourcePath("scenes/cornell_mirror.obj") + " Return");
    const std::string output = readText(log);
    INFO(output);
    REQUIRE(output.find("loaded " + sourcePath("scenes/cornell_mirror.obj")) != std::string::npos);
    const std::size_t at = output.find("hemirad-gui: Run: ");
    REQUIRE(at != std::string::npos);
    const std::string line = output.substr(at, output.find('\n', at) - at);
    CHECK(line.find("time known after a first run on this mesh") != std::string::npos);
    CHECK(line.find("about") == std::string::npos);
}

TEST_CASE("hemirad-gui keeps drawing after every input, also one that comes while it settles (issue 38 #15)") {
    // Popups appeared only after another mouse move: a click's release taken by the last of the
    // frames after its press left the popup it opened undrawn until the next event.
    const auto dir = tempDir("gui-pacing");
    const std::string log = (dir / "gui.log").string();
    // Clicks held 10 to 80 ms on the Log panel: the releases come while the frames after the press run.
    runKeyboardScript("keyboard_keys.sh", log + " 28 '" + sourcePath("scenes/cornell_box.obj") +
                                              "' hold:600,700,0.01 hold:600,700,0.02 hold:600,700,0.04 hold:600,700,0.08");
    const std::string output = readText(log);
    INFO(output);
    int frames = -1;
    const std::size_t at = output.find("hemirad-gui: after input, at least ");
    REQUIRE(at != std::string::npos);
    REQUIRE(std::sscanf(output.c_str() + at, "hemirad-gui: after input, at least %d frames", &frames) == 1);
    CHECK(frames >= 3);  // the frame that took it, one for ImGui to act, one for a new popup to show
}
