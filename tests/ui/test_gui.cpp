// hemirad-gui under Xvfb: load, compute, solve, draw, screenshot, quit, and the picture is checked.
// Needs xvfb-run (installed by scripts/install-deps.sh); without it the test fails, never skips.
#include "engine/obj_loader.hpp"
#include "engine/subdivide.hpp"
#include "render/false_colour.hpp"
#include "ui/gui_run.hpp"

#include <algorithm>
#include <sstream>

using namespace hemirad::test;

TEST_CASE("hemirad-gui renders the Cornell box under Xvfb: walls in their halves, the UI drawn") {
    const std::string log = runGuiAndCheckPicture("gui", "--samples 768");
    CHECK(log.find("form factors: hemisphere") != std::string::npos);
}

TEST_CASE("hemirad-gui computes hemicube form factors in its EGL context next to the GLFW window") {
    // The GUI's GLFW context and the hemicube workers' EGL contexts share one GL entry-point table.
    const std::string log = runGuiAndCheckPicture("gui-hemicube", "--method hemicube --resolution 32");
    CHECK(log.find("form factors: hemicube") != std::string::npos);
}

TEST_CASE("hemirad-gui takes the back ends' flags from the registry and refuses those its back end ignores") {
    // Parsing happens before any window opens: no display is needed.
    const auto dir = tempDir("gui-flags");
    const std::string log = (dir / "out.txt").string();
    auto run = [&](const std::string& flags) {
        const int s = std::system((std::string(HEMIRAD_GUI_BINARY) + " " + flags + " > " + log + " 2>&1").c_str());
        return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
    };
    CHECK(run("--samples 3072 --method hemicube") == 2);
    CHECK(readText(log).find("option '--samples' does not apply to --method hemicube") != std::string::npos);
    CHECK(run("--method hemisphere --resolution 64") == 2);
    CHECK(readText(log).find("option '--resolution' does not apply to --method hemisphere") != std::string::npos);
    CHECK(run("--method cube") == 2);
    CHECK(readText(log).find("unknown --method 'cube' (hemisphere, hemicube)") != std::string::npos);
    // Sky and sun's inputs are checked as they are read.
    CHECK(run("--sun-sky --sun-direction 0,0,0") == 2);
    CHECK(readText(log).find("--sun-direction expects x,y,z (not all 0), got '0,0,0'") != std::string::npos);
    CHECK(run("--sun-sky --dni -5") == 2);
    CHECK(readText(log).find("--dni expects a number in 0") != std::string::npos);
}

TEST_CASE("hemirad-gui sleeps while idle: a few frames, not one per refresh") {
    // Issue 14, defect 9: the GUI redrew every frame and used a full core while nothing changed.
    REQUIRE_MESSAGE(std::system("command -v xvfb-run > /dev/null") == 0, "xvfb-run is missing (scripts/install-deps.sh)");
    const auto dir = tempDir("gui-idle");
    const std::string log = (dir / "log.txt").string();
    const std::string command = "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 "
                                "xvfb-run -a -s '-screen 0 1400x900x24' " + std::string(HEMIRAD_GUI_BINARY) + " " +
                                sourcePath("scenes/cornell_box.obj") + " --quit-after 3 > " + log + " 2>&1";
    const int status = std::system(command.c_str());
    const std::string output = readText(log);
    INFO(output);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
    long frames = -1;
    double seconds = 0.0;
    const std::size_t at = output.find("hemirad-gui: ");
    REQUIRE(at != std::string::npos);
    const std::size_t line = output.find(" frames drawn in ");
    REQUIRE(line != std::string::npos);
    REQUIRE(std::sscanf(output.c_str() + output.rfind('\n', line) + 1, "hemirad-gui: %ld frames drawn in %lf s", &frames, &seconds) == 2);
    CHECK(seconds >= 3.0);
    // It did draw. Not ">= 3": under the sanitizers on a loaded 2-core machine the first frames
    // (llvmpipe compiling shaders) took 3.4 s for 2 (CI, 2026-11-24).
    CHECK(frames >= 1);
    CHECK(frames <= 20);  // 3 settling frames, then about 3 per 2 s of waiting (a busy loop draws hundreds)
}

TEST_CASE("hemirad-gui's panels stay inside a 1280x800 window and apart, the Selection panel included") {
    // Issue 14: at the default size the Pipeline and Selection panels ran past the window's edge and
    // over each other, hiding the F diagnostics and the inspector.
    const std::string log = runGuiAndCheckPicture("gui-layout", "--estimator rays --samples 256 --select 0", false);
    const std::vector<Panel> panels = panelsOf(log);
    REQUIRE(panels.size() == 5);  // Scene, Pipeline, Selection, Log, Status
    for (const Panel& p : panels) {
        CAPTURE(p.name);
        CHECK(p.x >= 0);
        CHECK(p.y >= 20);  // below the menu bar
        CHECK(p.x + p.w <= 1280);
        CHECK(p.y + p.h <= 800);
        CHECK(p.w >= 200);
        if (p.name == "Status") {
            CHECK(p.w == 1280);     // the status bar: the window's width, one line along the bottom edge
            CHECK(p.y + p.h == 800);
        } else {
            CHECK(p.h >= 100);
        }
    }
    for (std::size_t a = 0; a < panels.size(); ++a)
        for (std::size_t b = a + 1; b < panels.size(); ++b) {
            const Panel &p = panels[a], &q = panels[b];
            CAPTURE(p.name);
            CAPTURE(q.name);
            CHECK((p.x + p.w <= q.x || q.x + q.w <= p.x || p.y + p.h <= q.y || q.y + q.h <= p.y));
        }
}

TEST_CASE("hemirad-gui's false-colour view: patches in the map's colours, a legend whose bar and range come from the data") {
    Image image;
    const std::string log = runGuiAndCheckPicture("gui-false-colour", "--estimator rays --samples 256 --false-color irradiance", false, &image);
    // The range equals hemirad render's for the same scene and settings.
    double guiMin = 0, guiMax = 0;
    const std::size_t at = log.find("hemirad-gui: false colour: irradiance H, linear scale ");
    REQUIRE(at != std::string::npos);
    REQUIRE(std::sscanf(log.c_str() + at, "hemirad-gui: false colour: irradiance H, linear scale %lf .. %lf", &guiMin, &guiMax) == 2);
    const auto dir = tempDir("gui-false-colour-cli");
    const CommandResult cli = runCommand(std::string(HEMIRAD_BINARY) + " render " + sourcePath("scenes/cornell_box.obj") +
                                         " --subdivide 60 --estimator rays --samples 256 --false-color irradiance --size 64x64 -o " +
                                         (dir / "H.png").string() + " 2>&1");
    REQUIRE(cli.status == 0);
    double cliMin = 0, cliMax = 0;
    const std::size_t scale = cli.output.find("linear scale ");
    REQUIRE(scale != std::string::npos);
    REQUIRE(std::sscanf(cli.output.c_str() + scale, "linear scale %lf .. %lf", &cliMin, &cliMax) == 2);
    CHECK(guiMin == doctest::Approx(cliMin).epsilon(1e-6));
    CHECK(guiMax == doctest::Approx(cliMax).epsilon(1e-6));
    CHECK(guiMax > guiMin);
    // The legend's bar: the map's top colour at its top row, its bottom colour at its bottom row.
    const std::vector<Panel> panels = panelsOf(log);
    const auto bar = std::find_if(panels.begin(), panels.end(), [](const Panel& p) { return p.name == "LegendBar"; });
    REQUIRE(bar != panels.end());
    const int x = int(bar->x + bar->w / 2), top = int(bar->y), bottom = int(bar->y + bar->h) - 1;
    const auto colour = [&](int px, int py) { return std::array<int, 3>{image.at(px, py)[0], image.at(px, py)[1], image.at(px, py)[2]}; };
    const auto map = [](double t) {
        const auto c = hemirad::viridis(t);
        return std::array<int, 3>{c[0], c[1], c[2]};
    };
    CHECK(colour(x, top) == map(1.0));
    CHECK(colour(x, bottom) == map(0.0));
    // The view shows map colours: the back wall's middle is one of them, not a shaded radiance.
    const int vx = image.width / 2 + 60, vy = image.height / 2 - 120;
    bool inMap = false;
    for (int k = 0; k < 256; ++k) inMap |= colour(vx, vy) == map(k / 255.0);
    CHECK(inMap);
}

TEST_CASE("hemirad-gui's log false colour: the automatic range spans at most 4 decades below the maximum") {
    // The mesh: at 30 mm floor patches lie under a block (irradiance near 0: 1.0e-5 here,
    // 1.8e-19 in the issue), which set the minimum before the floor.
    std::string log;
    const Image image = runGui("gui-false-colour-log",
                               sourcePath("scenes/cornell_box.obj") + " --subdivide 30 --false-color irradiance --scale log --run", log);
    INFO(log);
    double lo = 0, hi = 0;
    const std::size_t at = log.find("hemirad-gui: false colour: irradiance H, log scale ");
    REQUIRE(at != std::string::npos);
    REQUIRE(std::sscanf(log.c_str() + at, "hemirad-gui: false colour: irradiance H, log scale %lf .. %lf", &lo, &hi) == 2);
    CHECK(hi > 0.1);
    CHECK(lo == doctest::Approx(hi * 1e-4).epsilon(1e-6));  // not the round-off on the floor under a block
    // The view spreads over the map: a tenth of the map-coloured pixels of the window's middle or more
    // in the map's lower three quarters (the blocks).
    std::size_t coloured = 0, low = 0;
    for (int y = image.height * 3 / 10; y < image.height * 7 / 10; ++y)
        for (int x = image.width * 3 / 10; x < image.width * 7 / 10; ++x)
            for (int k = 0; k < 256; ++k)
                if (hemirad::viridis(k / 255.0) == std::array<std::uint8_t, 3>{image.at(x, y)[0], image.at(x, y)[1], image.at(x, y)[2]}) {
                    ++coloured;
                    low += k < 192;
                    break;
                }
    CHECK(coloured > 10000);
    CHECK(double(low) > 0.1 * double(coloured));
}

TEST_CASE("hemirad-gui's false colour of a scene where nothing emits says so, every patch in the no-data grey") {
    // The Cornell box with its light switched off.
    const auto dir = tempDir("gui-no-emitter");
    std::string mtl = readText(sourcePath("scenes/cornell_box.mtl"));
    const std::size_t light = mtl.find("Ke 17 11.8 4");
    REQUIRE(light != std::string::npos);
    mtl.replace(light, 12, "Ke 0 0 0");
    writeFile(dir / "cornell_box.obj", readText(sourcePath("scenes/cornell_box.obj")));
    writeFile(dir / "cornell_box.mtl", mtl);
    std::string log;
    const Image image = runGui("gui-no-emitter-run", (dir / "cornell_box.obj").string() + " --subdivide 60 --estimator rays --samples 64 --false-color irradiance --run", log);
    INFO(log);
    CHECK(log.find("hemirad-gui: false colour: nothing emits") != std::string::npos);
    CHECK(log.find("scale -1 .. 1") == std::string::npos);
    // The back wall's middle is the no-data grey.
    const unsigned char* c = image.at(image.width / 2 + 60, image.height / 2 - 120);
    CHECK(std::array<int, 3>{c[0], c[1], c[2]} == std::array<int, 3>{128, 128, 128});
}

TEST_CASE("hemirad-gui meshes a selected object as the Pipeline panel's Apply does: the patch count it previews, and F made for it") {
    // --mesh-selected is the panel's Apply for the objects of --select (patch 17 of the 60 mm mesh
    // lies on the tall block); Run then computes every row of the new mesh.
    hemirad::Warnings quiet = quietWarnings();
    const hemirad::Scene source = hemirad::loadObj(sourcePath("scenes/cornell_box.obj"), quiet);
    const hemirad::Scene loaded = hemirad::subdivide(source, 60.0);
    std::vector<double> edges(source.objects.size(), 60.0);
    edges[loaded.patches[17].object] = 25.0;
    const std::size_t expected = hemirad::subdividedSize(source, edges);
    REQUIRE(expected > loaded.size());
    Image image;
    const std::string log = runGuiAndCheckPicture("gui-mesh", "--estimator rays --samples 256 --select 17 --mesh-selected 25 --layer patch-id", false, &image);
    CHECK(log.find("meshed 1 object(s) to edges <= 25: " + std::to_string(loaded.size()) + " -> " + std::to_string(expected) +
                   " patches") != std::string::npos);
    CHECK(log.find(", " + std::to_string(expected) + " rows in ") != std::string::npos);  // F for the new mesh
    // The patch-id view shows the finer mesh: the tall block's face (left of centre) has many more
    // distinct colours than a 60 mm face of the same size.
    const auto distinct = [&](int x0, int y0, int x1, int y1) {
        std::vector<int> seen;
        for (int y = y0; y < y1; y += 2)
            for (int x = x0; x < x1; x += 2) {
                const unsigned char* c = image.at(x, y);
                seen.push_back(c[0] << 16 | c[1] << 8 | c[2]);
            }
        std::sort(seen.begin(), seen.end());
        return std::unique(seen.begin(), seen.end()) - seen.begin();
    };
    MESSAGE("distinct patch colours: tall block ", distinct(470, 350, 640, 600), ", short block ", distinct(640, 540, 820, 620));
    CHECK(distinct(470, 350, 640, 600) > 2 * distinct(640, 540, 820, 620));
}

TEST_CASE("hemirad-gui reports the lost power area-weighted, as the CLI: meshing one block finer leaves it where it was") {
    // The case: the 20-patch Cornell box (the mean over rows: 18.1 %), then its tall block
    // meshed to 30 mm from the Pipeline panel (11.45 %).
    hemirad::Warnings quiet = quietWarnings();
    const hemirad::Scene source = hemirad::loadObj(sourcePath("scenes/cornell_box.obj"), quiet);
    hemirad::PatchId tall = 0;
    while (tall < source.size() && source.objects[source.patches[tall].object] != "tall_block") ++tall;
    REQUIRE(tall < source.size());
    const auto lostPercent = [](const std::string& name, const std::string& arguments) {
        std::string log;
        runGui(name, sourcePath("scenes/cornell_box.obj") + " " + arguments + " --run", log);
        INFO(log);
        const std::size_t at = log.find("% of the power");
        REQUIRE(at != std::string::npos);
        CHECK(log.find("area-weighted", at) < log.find('\n', at));
        const std::size_t start = log.find_last_of(" ;", at) + 1;
        return std::stod(log.substr(start, at - start));
    };
    const double whole = lostPercent("gui-lost-whole", "");
    const double meshed = lostPercent("gui-lost-meshed", "--select " + std::to_string(tall) + " --mesh-selected 30");
    CHECK(whole > 10.0);  // the open front
    CHECK(std::abs(meshed - whole) < 1.0);
}

TEST_CASE("hemirad-gui's status bar reads out a known patch: B, H, E, rho, s as the CLI's CSV, and F_ij from the selected patch") {
    // Patch 200 of the 60 mm Cornell box is on the light; patch 0 (the floor) is selected.
    const std::string log = runGuiAndCheckPicture("gui-readout", "--samples 256 --pair-digits 1 --select 0 --hover 200", false);
    const std::size_t at = log.find("hemirad-gui: status: patch 200 'light' | B ");
    REQUIRE(at != std::string::npos);
    double B[3], H[3], E[3], rho[3], s = -1, F = -1;
    REQUIRE(std::sscanf(log.c_str() + at,
                        "hemirad-gui: status: patch 200 'light' | B %lf %lf %lf W/m^2 | H %lf %lf %lf W/m^2 | E %lf %lf %lf W/m^2 | "
                        "rho %lf %lf %lf s %lf | F 0->200 %lf",
                        &B[0], &B[1], &B[2], &H[0], &H[1], &H[2], &E[0], &E[1], &E[2], &rho[0], &rho[1], &rho[2], &s, &F) == 14);
    // The CLI's per-patch CSV and F for the same scene and settings.
    const auto dir = tempDir("gui-readout-cli");
    const std::string csv = (dir / "B.csv").string(), mtx = (dir / "F.mtx").string();
    const std::string scene = sourcePath("scenes/cornell_box.obj") + " --subdivide 60 --samples 256 --pair-digits 1 ";
    REQUIRE(runCommand(std::string(HEMIRAD_BINARY) + " solve " + scene + "-o " + csv + " 2>&1").status == 0);
    REQUIRE(runCommand(std::string(HEMIRAD_BINARY) + " formfactors " + scene + "-o " + mtx + " 2>&1").status == 0);
    std::istringstream rows(readText(csv));
    std::string line;
    bool found = false;
    while (std::getline(rows, line))
        if (line.rfind("200,", 0) == 0) {
            double area, e[3], r[3], spec, b[3];
            REQUIRE(std::sscanf(line.c_str(), "200,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &area, &e[0], &e[1], &e[2], &r[0],
                                &r[1], &r[2], &spec, &b[0], &b[1], &b[2]) == 11);
            for (int c = 0; c < 3; ++c) {
                // The status bar prints 4 significant digits.
                CHECK(B[c] == doctest::Approx(b[c]).epsilon(1e-3));
                CHECK(E[c] == doctest::Approx(e[c]).epsilon(1e-3));
                CHECK(rho[c] == doctest::Approx(r[c]).epsilon(1e-3));
                CHECK(H[c] == doctest::Approx((b[c] - e[c]) / r[c]).epsilon(2e-3));
            }
            CHECK(s == spec);
            found = true;
        }
    CHECK(found);
    std::istringstream entries(readText(mtx));
    double F02 = 0.0;  // Matrix Market: 1-based "row column value"
    while (std::getline(entries, line)) {
        long i = 0, j = 0;
        double v = 0;
        if (line[0] != '%' && std::sscanf(line.c_str(), "%ld %ld %lf", &i, &j, &v) == 3 && i == 1 && j == 201) F02 = v;
    }
    CHECK(F02 > 0.0);
    CHECK(F == doctest::Approx(F02).epsilon(1e-3));
}

TEST_CASE("hemirad-gui opens a file through the file browser by keyboard: Ctrl+O, a folder typed and entered, a file name typed and entered") {
    const auto dir = tempDir("gui-keyboard");
    const std::string log = (dir / "gui.log").string();
    // The folder is typed first (the browser enters it), then the file name relative to it.
    const std::string run = runKeyboardScript("keyboard_open.sh", sourcePath("scenes") + " cornell_box.obj " + log);
    const std::string output = readText(log);
    INFO(run);
    INFO(output);
    CHECK(output.find("loaded " + sourcePath("scenes/cornell_box.obj") + ": 20 patches") != std::string::npos);
    CHECK(run.find("title: Hemirad - cornell_box.obj") != std::string::npos);
}

TEST_CASE("hemirad-gui shows mirrors in mirrors to --max-depth, pixel for pixel as hemirad render") {
    // A corridor between two facing mirrors (s = 0.9, no diffuse part), a red far wall and a lit
    // ceiling. The scene camera looks down it past the right mirror, which shows the red wall again
    // and again: once through the left or the right mirror, then through both, and so on.
    const auto dir = tempDir("gui-mirrors");
    writeFile(dir / "corridor.mtl", "newmtl white\nKd 0.7 0.7 0.7\nnewmtl red\nKd 0.7 0.1 0.1\n"
                                    "newmtl mirror\nKd 0 0 0\nKs 0.9 0.9 0.9\nillum 3\n"
                                    "newmtl light\nKd 0.5 0.5 0.5\nKe 10 10 10\n");
    const std::string scene = writeFile(dir / "corridor.obj",
                                        "# hemirad camera 3 1.5 -4 1.2 1.2 6 50\nmtllib corridor.mtl\n"
                                        "v 0 0 0\nv 4 0 0\nv 4 0 20\nv 0 0 20\nv 0 3 0\nv 4 3 0\nv 4 3 20\nv 0 3 20\n"
                                        "o floor\nusemtl white\nf 1 4 3 2\no ceiling_light\nusemtl light\nf 5 6 7 8\n"
                                        "o mirror_left\nusemtl mirror\nf 1 5 8 4\no mirror_right\nusemtl mirror\nf 2 3 7 6\n"
                                        "o back\nusemtl red\nf 4 8 7 3\n");
    struct Region {
        const char* name;
        int x0, y0, x1, y1;
    };
    // Rectangles clear of the panels at 1280x800.
    const Region direct{"the red wall, direct", 470, 335, 570, 415};
    const Region left1{"the red wall in the left mirror", 380, 335, 440, 415};
    const Region right1{"the red wall in the right mirror", 600, 335, 720, 415};
    const Region right2{"the red wall in the right mirror through both", 760, 335, 900, 415};
    const Region floor{"the floor in the right mirror", 950, 450, 1050, 580};
    for (const int depth : {0, 1, 8}) {
        CAPTURE(depth);
        const std::string flags = " --subdivide 1 --max-depth " + std::to_string(depth) + " --exposure 0.2";
        std::string log;
        const Image gui = runGui("gui-mirrors-" + std::to_string(depth), scene + flags + " --run", log);
        const std::string png = (dir / ("cli" + std::to_string(depth) + ".png")).string();
        const CommandResult cli =
            runCommand(std::string(HEMIRAD_BINARY) + " render " + scene + flags + " --size 1280x800 -o " + png + " 2>&1");
        INFO(cli.output);
        REQUIRE(cli.status == 0);
        const Image reference = loadImage(png);
        REQUIRE(reference.width == gui.width);
        REQUIRE(reference.height == gui.height);
        for (const Region& r : {direct, left1, right1, right2, floor}) {
            INFO(r.name);
            const auto shown = gui.mean(r.x0, r.y0, r.x1, r.y1), expected = reference.mean(r.x0, r.y0, r.x1, r.y1);
            // Same camera, exposure and sRGB mapping; the CLI averages 4 rays per pixel.
            for (int c = 0; c < 3; ++c) CHECK(shown[c] == doctest::Approx(expected[c]).epsilon(0.004).scale(255.0));
        }
        // What each depth must show (red channel): mirrors without a diffuse part are black past the depth.
        const auto red = [&gui](const Region& r) { return gui.mean(r.x0, r.y0, r.x1, r.y1)[0]; };
        CHECK(red(direct) > 100.0);
        CHECK((red(left1) > 100.0) == (depth >= 1));
        CHECK((red(right1) > 100.0) == (depth >= 1));
        CHECK((red(right2) > 100.0) == (depth >= 2));
    }
}

TEST_CASE("hemirad-gui: every control of every panel shows a tooltip, above it (the mouse swept over each panel, page by page)") {
    // --check-tooltips moves the mouse over a grid in every panel, scrolling down their content, and
    // lists each control (ImGui's hovered item) that drew no tooltip. Two set-ups show most controls:
    // the hemisphere with a selection (material editor, inspector) and the false-colour legend; the
    // hemicube's options on the mirror box; the thermal section and exchange table on the radiator.
    const std::vector<std::string> setups = {
        sourcePath("scenes/cornell_box.obj") + " --subdivide 60 --samples 256 --pair-digits 1 --select 0 --false-color irradiance --exposure 2",
        sourcePath("scenes/cornell_mirror.obj") + " --method hemicube --resolution 32 --select 4",
        // The Scene panel's Thermal section (opened by its files) with a result, T in false colour and
        // the exchange table.
        sourcePath("examples/thermal/radiator.obj") + " --properties " + sourcePath("examples/thermal/radiator_properties.toml") +
            " --bc " + sourcePath("examples/thermal/radiator_bc.toml") + " --thermal --false-color temperature --thermal-window"};
    for (const std::string& setup : setups) {
        CAPTURE(setup);
        std::string log;
        runGui("gui-tooltips", setup + " --run --check-tooltips", log);
        INFO(log);
        const std::size_t at = log.find("hemirad-gui: tooltips: ");
        REQUIRE(at != std::string::npos);
        std::size_t points = 0, controls = 0, missing = 1, below = 1;
        REQUIRE(std::sscanf(log.c_str() + at, "hemirad-gui: tooltips: %zu points, %zu controls hovered, %zu without a tooltip, %zu below",
                            &points, &controls, &missing, &below) == 4);
        CHECK(points > 5000);
        CHECK(controls >= 40);  // the sweep reaches the controls (the Pipeline panel alone has over 25)
        CHECK(missing == 0);
        CHECK(log.find("no tooltip:") == std::string::npos);
        // Each tooltip stands above its control: none covers the controls below (issue 38 #15: the
        // tolerance's covered the Run buttons).
        CHECK(below == 0);
    }
}

TEST_CASE("hemirad-gui's help window lists the mouse and the keys, inside the window (Help menu, F1, --help-window)") {
    std::string log;
    const Image image = runGui("gui-help", sourcePath("scenes/cornell_box.obj") + " --help-window", log);
    const std::vector<Panel> panels = panelsOf(log);
    const auto help = std::find_if(panels.begin(), panels.end(), [](const Panel& p) { return p.name == "Help"; });
    REQUIRE(help != panels.end());
    CHECK(help->x >= 0);
    CHECK(help->y >= 20);
    CHECK(help->x + help->w <= image.width);
    CHECK(help->y + help->h <= image.height);
    CHECK(help->h >= 300);  // a row per key or gesture, then the session's steps
    // Without the flag it stays closed.
    runGui("gui-help-closed", sourcePath("scenes/cornell_box.obj"), log);
    CHECK(log.find("hemirad-gui: panel Help") == std::string::npos);
}

TEST_CASE("hemirad-gui's Scene panel counts the objects that hold patches, singular for one (issue 38 #9)") {
    // The Cornell box's 8 groups read "9 objects": the loader's empty "default" object was counted.
    std::string log;
    runGui("gui-counts", sourcePath("scenes/cornell_box.obj"), log);
    CHECK(log.find("hemirad-gui: scene: 20 patches, 8 objects\n") != std::string::npos);
    const auto dir = tempDir("gui-counts-one");
    writeFile(dir / "one.mtl", "newmtl white\nKd 0.5 0.5 0.5\n");
    const std::string one = writeFile(dir / "one.obj", "mtllib one.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\no plate\nusemtl white\nf 1 2 3\n");
    runGui("gui-counts-1", one, log);
    CHECK(log.find("hemirad-gui: scene: 1 patch, 1 object\n") != std::string::npos);
}

TEST_CASE("hemirad-gui's object table has H min between H mean and H max, as the CLI's --objects CSV (issue 38 #8)") {
    std::string log;
    runGui("gui-object-table", sourcePath("scenes/cornell_box.obj") + " --subdivide 60 --estimator rays --samples 256 --run --objects-window", log);
    CHECK(log.find("hemirad-gui: object table: object | patches | area (mm^2) | B mean | B min | B max | "
                   "H mean | H min | H max\n") != std::string::npos);
    // The floor's row against `hemirad solve --objects` for the same scene and settings.
    const auto dir = tempDir("gui-object-table-cli");
    const std::string csv = (dir / "objects.csv").string();
    REQUIRE(runCommand(std::string(HEMIRAD_BINARY) + " solve " + sourcePath("scenes/cornell_box.obj") +
                       " --subdivide 60 --estimator rays --samples 256 --objects " + csv + " -o " + (dir / "B.csv").string() + " 2>&1").status == 0);
    std::istringstream rows(readText(csv));
    std::string line;
    double f[9] = {};
    bool found = false;
    while (std::getline(rows, line))
        if (line.rfind("floor,", 0) == 0)
            found = std::sscanf(line.c_str(), "floor,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &f[0], &f[1], &f[2], &f[3], &f[4], &f[5],
                                &f[6], &f[7], &f[8]) == 9;
    REQUIRE(found);
    // On screen: patches, area, B mean/min/max, H mean/min/max, 4 significant digits.
    const std::size_t at = log.find("hemirad-gui: object table: floor | ");
    REQUIRE(at != std::string::npos);
    double g[8] = {};
    REQUIRE(std::sscanf(log.c_str() + at, "hemirad-gui: object table: floor | %lf | %lf | %lf | %lf | %lf | %lf | %lf | %lf", &g[0],
                        &g[1], &g[2], &g[3], &g[4], &g[5], &g[6], &g[7]) == 8);
    const double cli[8] = {f[0], f[1], f[2], f[3], f[4], f[6], f[7], f[8]};  // H_patches (f[5]) is not shown
    for (int k = 0; k < 8; ++k) {
        CAPTURE(k);
        CHECK(g[k] == doctest::Approx(cli[k]).epsilon(1e-3));
    }
    CHECK(g[6] < g[5]);  // H min below H mean: the floor is lit unevenly
}

TEST_CASE("hemirad-gui: Esc closes the help window, and a file browser opened over it is the one dialog shown (issue 38 #11)") {
    // Keys tapped into the GUI started with the help window open; the log ends with the panels of
    // the last frame.
    const auto taps = [](const std::string& name, const std::string& keys) {
        const std::string log = (tempDir(name) / "gui.log").string();
        runKeyboardScript("keyboard_keys.sh", log + " 20 '" + sourcePath("scenes/cornell_box.obj") + " --select 0 --help-window' " + keys);
        const std::string output = readText(log);
        INFO(output);
        CHECK(output.find("hemirad-gui: panel Help") == std::string::npos);
        return output;
    };
    // Esc closes the help window (Help: "Esc: close this window or a dialog, else select none") and
    // keeps the selection: the Selection panel is still drawn.
    std::string log = taps("gui-esc-help", "Escape");
    CHECK(log.find("hemirad-gui: panel Selection") != std::string::npos);
    // Ctrl+O with the help window open: the browser, and no help window standing over it.
    log = taps("gui-help-browser", "ctrl+o");
    CHECK(log.find("hemirad-gui: panel Files") != std::string::npos);
}
