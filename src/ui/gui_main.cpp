// hemirad-gui: the event loop. GLFW events become camera moves, picks and actions on AppState;
// ImGui panels present the state; the viewer draws the scene behind them.
#include "engine/crash_report.hpp"
#include "engine/error.hpp"
#include "engine/result_writer.hpp"
#include "engine/threads.hpp"
#include "gl/gl_api.hpp"
#include "ui/app_state.hpp"
#include "ui/frame_pacing.hpp"
#include "ui/inspector.hpp"
#include "ui/key_taps.hpp"
#include "ui/orbit_camera.hpp"
#include "ui/tooltip_check.hpp"
#include "ui/units.hpp"
#include "ui/panels.hpp"
#include "ui/run_estimate.hpp"
#include "ui/viewer.hpp"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <cerrno>
#include <climits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using namespace hemirad;
using namespace hemirad::ui;

namespace {

struct GuiOptions {
    std::string scene;
    bool run = false;
    bool exitAfter = false;
    double quitAfter = 0.0;  ///< --quit-after: seconds of interactive running, then quit as --exit
    std::optional<FalseColourQuantity> falseColour;  ///< --false-color: start in the false-colour view of it
    FalseColourSettings::Thermal falseColourThermal = FalseColourSettings::Thermal::None;  ///< --false-color temperature|heat-flux
    /// --properties, --bc (each may repeat): thermal files loaded in order, as the Scene panel's Load
    std::vector<std::string> properties, conditions;
    bool thermal = false;                ///< --thermal: Run thermal after loading
    bool thermalWindow = false;          ///< --thermal-window: the exchange table's window open
    std::optional<FalseColourSettings::Sun> falseColourSun;  ///< --false-color sunlit_fraction, total_solar, ...
    bool sunSky = false;                 ///< --sun-sky: Run sky and sun after loading
    SunSkySetup sunSkySetup;             ///< --sun-time, --latitude, --longitude, --sun-direction, --dni, --dhi, --sky
    FalseColourScale falseColourScale = FalseColourScale::Linear;
    std::string screenshot;
    double subdivide = 0.0;
    std::string materials;       ///< --materials FILE.mtl: materials by object name
    long hover = -1;             ///< --hover: the status bar reads this patch out (scripted runs)
    std::optional<Layer> layer;  ///< --layer: the view's layer at start
    double exposure = 0.0;       ///< --exposure X: a fixed display scale (0: automatic)
    bool checkTooltips = false;  ///< --check-tooltips: sweep the mouse over the panels, then exit
    bool help = false;           ///< --help-window: start with Help > Keyboard and mouse open
    bool objects = false;        ///< --objects-window: start with View > Object table open
    double mesh = 0.0;          ///< --mesh L: the meshing panel's Apply for the whole scene
    double meshSelected = 0.0;  ///< --mesh-selected L: the same for the objects of --select
    int up = 0;                 ///< --up y|z: the Scene panel's up-axis choice (0: none)
    int width = 1280, height = 800;
    PipelineSettings settings;
    long select = -1;  ///< patch to select after loading (scripted screenshots)
};

const char* kUsage =
    "usage: hemirad-gui [SCENE.obj|SCENE.stl] [--materials FILE.mtl] [--subdivide L] [--method NAME]\n"
    "                   [back-end options, see 'hemirad help']\n"
    "                   [--max-depth D] [--exposure X] [--check-tooltips] [--help-window] [--objects-window]\n"
    "                   [--mesh L | --select PATCH --mesh-selected L] [--up y|z]\n"
    "                   [--size WxH] [--select PATCH] [--hover PATCH] [--run] [--screenshot OUT.png] [--exit]\n"
    "                   [--quit-after S] [--false-color Q [--scale linear|log]] [--layer NAME]\n"
    "                   [--properties P.toml] [--bc BC.toml] [--thermal] [--thermal-window]\n"
    "                   [--sun-sky [--sun-time T --latitude LAT --longitude LON | --sun-direction x,y,z]\n"
    "                    [--dni W] [--dhi W] [--sky MODEL]]\n"
    "  --run          compute form factors and solve after loading\n"
    "  --materials FILE.mtl  materials by object name for every scene opened, as hemirad's\n"
    "  --max-depth D  mirror reflections followed by F and shown by the view (default 8, as hemirad)\n"
    "  --exposure X   display scale of the view, as hemirad render's (default automatic)\n"
    "  --mesh L       mesh the scene to edges <= L as the Pipeline panel's Apply does (undoable);\n"
    "                 --mesh-selected L only the objects of --select\n"
    "  --up y|z       the scene's up axis, as the Scene panel's choice (remembered for the file;\n"
    "                 else the OBJ's '# hemirad up z', else guessed from the bounding box)\n"
    "  --screenshot   once the view shows the results, save the window (with the UI) as a PNG\n"
    "  --exit         quit after the screenshot (or at once without one), print the log,\n"
    "                 exit 1 if it holds an error\n"
    "  --quit-after S run interactively for S seconds, then quit as --exit does\n"
    "  --check-tooltips  once the view is drawn, move the mouse over every panel and list the\n"
    "                 controls that show no tooltip; exit as --exit does (1 if any)\n"
    "  --false-color Q  start in the false-colour view of Q (radiosity, irradiance, emission, and after\n"
    "                 --thermal temperature, heat-flux; after --sun-sky sunlit_fraction, sky_view_factor,\n"
    "                 direct_sun, direct_sky, reflected_solar, total_solar, absorbed_solar);\n"
    "                 --scale linear|log its scale\n"
    "  --hover PATCH  read PATCH out in the status bar as if the cursor were on it (scripted runs)\n"
    "  --layer NAME   start in that view: radiosity, patch-id, emission, reflectance, specular, f-row\n"
    "  --help-window  start with Help > Keyboard and mouse open (F1)\n"
    "  --objects-window  start with View > Object table open (scripted runs print it)\n"
    "  --properties P.toml, --bc BC.toml  load thermal properties and boundary conditions, as the\n"
    "                 Scene panel's Thermal section does (docs/thermal.md); each may repeat (loaded in order)\n"
    "  --thermal      Run thermal after loading (every row of F, then T and q)\n"
    "  --thermal-window  open the thermal exchange table once there is a result (scripted runs print it)\n"
    "  --sun-sky      Run sky and sun after loading, as the Scene panel's Sky and sun section: the sun at\n"
    "                 --sun-time (default 2026-06-21T12:00Z) at --latitude, --longitude (default 48.14,\n"
    "                 11.58), or along --sun-direction; --dni, --dhi W/m^2 (default 800, 100); --sky\n"
    "                 isotropic (default), uniform, cie-overcast, cie:N or perez (hemirad help: --sky)\n"
    "mouse: left drag orbits, right/middle drag (or shift + left) pans, wheel zooms, click selects\n"
    "       (ctrl/shift + click adds); keys: F frame, S frame selection, C scene camera, Esc close help\n"
    "       (else select none), Ctrl+Z/Y undo/redo, Ctrl+O open, Ctrl+S save (Shift: save as), Ctrl+Q\n"
    "       quit, F1 help;\n"
    "       View > Look from: the standard views\n";

GuiOptions parse(int argc, char** argv) {
    GuiOptions o;
    std::string method = o.settings.formFactors.method;
    std::vector<std::pair<std::string, std::string>> backendFlags;  // applied once --method is known
    std::optional<std::uint32_t> maxDepth;
    auto value = [&](int& k, const char* flag) -> std::string {
        if (k + 1 >= argc) throw Error(std::string(flag) + " needs a value");
        return argv[++k];
    };
    auto number = [](const std::string& text, const char* flag) {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end || !(v > 0)) throw Error(std::string(flag) + " expects a positive number, got '" + text + "'");
        return v;
    };
    // A number in [lo, hi].
    auto real = [](const std::string& text, const char* flag, double lo, double hi) {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end || !(v >= lo && v <= hi))
            throw Error(std::string(flag) + " expects a number in " + std::to_string(lo) + " .. " + std::to_string(hi) + ", got '" + text + "'");
        return v;
    };
    // A whole number in [0, hi]; `expects` says what in the error.
    auto integer = [](const std::string& text, const char* flag, long hi, const char* expects) {
        char* end = nullptr;
        errno = 0;
        const long v = std::strtol(text.c_str(), &end, 10);
        if (text.empty() || *end || errno || v < 0 || v > hi)
            throw Error(std::string(flag) + " expects " + expects + ", got '" + text + "'");
        return v;
    };
    for (int k = 1; k < argc; ++k) {
        const std::string a = argv[k];
        if (a == "--help" || a == "-h") {
            std::cout << kUsage;
            std::exit(0);
        } else if (a == "--run") o.run = true;
        else if (a == "--exit") o.exitAfter = true;
        else if (a == "--check-tooltips") o.checkTooltips = o.exitAfter = true;
        else if (a == "--help-window") o.help = true;
        else if (a == "--objects-window") o.objects = true;
        else if (a == "--false-color") {
            const std::string q = value(k, "--false-color");
            if (q == "temperature") o.falseColourThermal = FalseColourSettings::Thermal::Temperature;
            else if (q == "heat-flux") o.falseColourThermal = FalseColourSettings::Thermal::HeatFlux;
            else if (const auto sun = parseSunQuantity(q)) o.falseColourSun = sun;
            else o.falseColour = parseFalseColourQuantity(q);
            if (!o.falseColour) o.falseColour = FalseColourQuantity::Irradiance;
        } else if (a == "--properties") o.properties.push_back(value(k, "--properties"));
        else if (a == "--bc") o.conditions.push_back(value(k, "--bc"));
        else if (a == "--thermal") o.thermal = true;
        else if (a == "--thermal-window") o.thermalWindow = true;
        else if (a == "--sun-sky") o.sunSky = true;
        else if (a == "--sun-time") {
            o.sunSkySetup.time = value(k, "--sun-time");
            o.sunSkySetup.byTime = true;
        } else if (a == "--latitude") o.sunSkySetup.latitude = real(value(k, "--latitude"), "--latitude", -90, 90);
        else if (a == "--longitude") o.sunSkySetup.longitude = real(value(k, "--longitude"), "--longitude", -180, 180);
        else if (a == "--dni") o.sunSkySetup.dni = real(value(k, "--dni"), "--dni", 0, 1e5);
        else if (a == "--dhi") o.sunSkySetup.dhi = real(value(k, "--dhi"), "--dhi", 0, 1e5);
        else if (a == "--sky") o.sunSkySetup.sky = value(k, "--sky");
        else if (a == "--sun-direction") {
            const std::string v = value(k, "--sun-direction");
            double x = 0, y = 0, z = 0;
            char tail = 0;
            if (std::sscanf(v.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &tail) != 3 || !Vec3(x, y, z).allFinite() || Vec3(x, y, z).norm() == 0.0)
                throw Error("--sun-direction expects x,y,z (not all 0), got '" + v + "'");
            o.sunSkySetup.direction = Vec3(x, y, z);
            o.sunSkySetup.byTime = false;
        }
        else if (a == "--scale") o.falseColourScale = parseFalseColourScale(value(k, "--scale"));
        else if (a == "--quit-after") o.quitAfter = number(value(k, "--quit-after"), "--quit-after");
        else if (a == "--screenshot") o.screenshot = value(k, "--screenshot");
        else if (a == "--subdivide") o.subdivide = number(value(k, "--subdivide"), "--subdivide");
        else if (a == "--materials") o.materials = value(k, "--materials");
        else if (a == "--exposure") o.exposure = number(value(k, "--exposure"), "--exposure");
        else if (a == "--layer") {
            const std::string v = value(k, "--layer");
            static const std::pair<const char*, Layer> layers[] = {
                {"radiosity", Layer::Radiosity}, {"patch-id", Layer::PatchId},       {"emission", Layer::Emission},
                {"reflectance", Layer::Reflectance}, {"specular", Layer::Specular}, {"f-row", Layer::FormFactorRow}};
            for (const auto& [name, layer] : layers)
                if (v == name) o.layer = layer;
            if (!o.layer) throw Error("--layer expects radiosity, patch-id, emission, reflectance, specular or f-row, got '" + v + "'");
        } else if (a == "--mesh") o.mesh = number(value(k, "--mesh"), "--mesh");
        else if (a == "--mesh-selected") o.meshSelected = number(value(k, "--mesh-selected"), "--mesh-selected");
        else if (a == "--up") {
            const std::string v = value(k, "--up");
            if (v != "y" && v != "z") throw Error("--up expects y or z, got '" + v + "'");
            o.up = v == "z" ? 2 : 1;
        } else if (a == "--method") method = value(k, "--method");
        else if (a == "--max-depth") maxDepth = std::uint32_t(integer(value(k, "--max-depth"), "--max-depth", 254, "0 to 254"));
        else if (const BackendOption* option = findBackendOption(a)) {
            backendFlags.emplace_back(a, option->kind == OptionKind::Switch ? "yes" : value(k, a.c_str()));
        } else if (a == "--select") o.select = integer(value(k, "--select"), "--select", LONG_MAX, "a patch id");
        else if (a == "--hover") o.hover = integer(value(k, "--hover"), "--hover", LONG_MAX, "a patch id");
        else if (a == "--size") {
            const std::string v = value(k, "--size");
            if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 64 || o.height < 64)
                throw Error("--size expects WxH (at least 64x64), got '" + v + "'");
        } else if (!a.empty() && a[0] == '-') throw Error("unknown option '" + a + "'");
        else if (o.scene.empty()) o.scene = a;
        else throw Error("more than one scene given: '" + a + "'");
    }
    o.settings.formFactors = defaultSettings(method);
    for (const auto& [flag, text] : backendFlags) setBackendOption(o.settings.formFactors, flag, text);
    if (maxDepth) o.settings.formFactors.common.maxDepth = *maxDepth;
    return o;
}

struct Input {
    bool pointerSeen = false;  // the pointer moved over the window at least once (no hover before)
    bool dragging = false, moved = false;
    double lastX = 0, lastY = 0, pressX = 0, pressY = 0;
    int button = -1;
    std::vector<std::string> dropped;
    /// Ctrl+key presses since the last frame, with their modifiers (GLFW_MOD_*): taken from GLFW's
    /// key events, whose modifiers are reliable where ImGui 1.86's key-state polling can miss a short
    /// press (synthetic input, a slow frame).
    std::vector<std::pair<int, int>> shortcuts;
    KeyTaps taps;                  // a tap shorter than a frame still reaches ImGui
    bool eventSeen = false;        // some input arrived since the last frame (FramePacing)
    bool typedTaps = false;        // KeyTaps holds changes that came while a text field had the keyboard
    // Where the pointer was at each button's last press and release event (the last motion event
    // before it): a frame sees a click late, when the hand may have moved on.
    double cursorX = 0, cursorY = 0;
    double downX[3] = {}, downY[3] = {}, upX[3] = {}, upY[3] = {};
    bool down[3] = {};  // as the button events say (ImGui reports a release a frame after the press)
    GLFWkeyfun imguiKey = nullptr;  // ImGui's key callback (which chains onKey)
};

void onKey(GLFWwindow* window, int key, int, int action, int mods) {
    auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window));
    if (input) input->eventSeen = true;
    if (input && action == GLFW_PRESS && (mods & GLFW_MOD_CONTROL)) input->shortcuts.emplace_back(key, mods);
}

/// Installed before ImGui's back end, which chains them: any input keeps frames coming (FramePacing).
void onButton(GLFWwindow* window, int button, int action, int) {
    auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window));
    if (!input) return;
    input->eventSeen = true;
    if (button < 0 || button > 2) return;
    if (!input->pointerSeen) glfwGetCursorPos(window, &input->cursorX, &input->cursorY);
    (action == GLFW_PRESS ? input->downX : input->upX)[button] = input->cursorX;
    (action == GLFW_PRESS ? input->downY : input->upY)[button] = input->cursorY;
    input->down[button] = action == GLFW_PRESS;
}
void onScroll(GLFWwindow* window, double, double) {
    if (auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window))) input->eventSeen = true;
}
void onChar(GLFWwindow* window, unsigned int) {
    if (auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window))) input->eventSeen = true;
}

/// Installed in front of ImGui's key callback: a key's second change before a frame has seen its first waits.
void onKeyTap(GLFWwindow* window, int key, int scancode, int action, int mods) {
    auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window));
    if (input && input->imguiKey && input->taps.pass({key, scancode, action, mods}))
        input->imguiKey(window, key, scancode, action, mods);
}

void onDrop(GLFWwindow* window, int count, const char** paths) {
    auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window));
    for (int k = 0; k < count; ++k) input->dropped.emplace_back(paths[k]);
    input->eventSeen = true;
}

void onCursor(GLFWwindow* window, double x, double y) {
    auto* input = static_cast<Input*>(glfwGetWindowUserPointer(window));
    input->pointerSeen = input->eventSeen = true;
    input->cursorX = x;
    input->cursorY = y;
}

void onGlfwError(int code, const char* text) { std::fprintf(stderr, "hemirad-gui: GLFW error %d: %s\n", code, text); }

/// Reads the window's back buffer (UI included) into a PNG, rows flipped to top-down.
void screenshot(const std::string& path, int width, int height, GLenum buffer) {
    std::vector<std::uint8_t> rgb(std::size_t(width) * height * 3), flipped(rgb.size());
    gl::BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl::ReadBuffer(buffer);
    gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl::ReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    for (int y = 0; y < height; ++y)
        std::memcpy(&flipped[std::size_t(y) * width * 3], &rgb[std::size_t(height - 1 - y) * width * 3], std::size_t(width) * 3);
    writePng(path, width, height, flipped);
}

/// A file of hemirad-gui's settings ("recent-files", "up-axes") in $XDG_CONFIG_HOME/hemirad (else
/// ~/.config/hemirad); "" without either.
std::string configPath(const std::string& name) {
    const char* config = std::getenv("XDG_CONFIG_HOME");
    const char* home = std::getenv("HOME");
    if (config && *config) return std::string(config) + "/hemirad/" + name;
    if (home && *home) return std::string(home) + "/.config/hemirad/" + name;
    return {};
}

}  // namespace

int main(int argc, char** argv) {
    reportFatalSignals("hemirad-gui");
    GuiOptions options;
    try {
        options = parse(argc, argv);
    } catch (const Error& e) {
        std::fprintf(stderr, "hemirad-gui: error: %s\n%s", e.what(), kUsage);
        return 2;
    }
    // Before any thread or GL context: the worker-thread default and llvmpipe's rasteriser threads.
    configureProcessThreads(options.settings.formFactors.common.threads);
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        std::fprintf(stderr, "hemirad-gui: error: cannot open a window (no display? try xvfb-run hemirad-gui ...)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow* window = glfwCreateWindow(options.width, options.height, "Hemirad", nullptr, nullptr);
    if (!window) {
        std::fprintf(stderr, "hemirad-gui: error: cannot create an OpenGL 4.5 core window\n");
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    int status = 0;
    try {
        gl::loadApi([](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }, "GLFW");
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // layouts are not persisted between runs
        ImGui::StyleColorsDark();
        glfwSetKeyCallback(window, onKey);  // before ImGui's back end, which chains them
        glfwSetMouseButtonCallback(window, onButton);
        glfwSetScrollCallback(window, onScroll);
        glfwSetCharCallback(window, onChar);
        ImGui_ImplGlfw_InitForOpenGL(window, true);
        ImGui_ImplOpenGL3_Init("#version 450");

        AppState app;
        app.settings = options.settings;
        app.loading.materials = options.materials;
        if (options.falseColour && !options.falseColourSun) {
            app.layer = Layer::FalseColour;
            app.falseColour.quantity = *options.falseColour;
            app.falseColour.thermal = options.falseColourThermal;
        }
        if (options.falseColourSun) {
            app.layer = Layer::FalseColour;
            app.falseColour.sun = *options.falseColourSun;
        }
        app.sunSky = options.sunSkySetup;
        app.falseColour.scale = options.falseColourScale;
        if (options.layer) app.layer = *options.layer;
        if (options.exposure > 0.0) {
            app.autoExposure = false;
            app.exposure = options.exposure;
        }
        OrbitCamera camera;
        app.upAxes = UpAxisMemory(configPath("up-axes"));
        Panels panels(configPath("recent-files"));
        if (options.help) panels.toggleHelp();
        if (options.objects) panels.showObjectTable();
        if (options.thermalWindow) panels.showThermalExchange();
        Input input;
        LoopRequests requests;
        glfwSetWindowUserPointer(window, &input);
        input.imguiKey = glfwSetKeyCallback(window, onKeyTap);
        glfwSetDropCallback(window, onDrop);
        glfwSetCursorPosCallback(window, onCursor);  // ImGui 1.86's GLFW back end polls the cursor itself
        if (!options.scene.empty()) {
            panels.open(app, camera, options.scene);
            // Part of loading: the meshing panel can still go back to the patches as loaded.
            if (app.hasScene() && options.subdivide > 0 && !app.mesh(options.subdivide, MeshTarget::Scene, true))
                throw Error("--subdivide " + std::to_string(options.subdivide) + ": " + app.log().back().text);
        }
        if (options.up && app.hasScene()) {
            app.setUpAxis(options.up);
            camera.frame(app.scene());
        }
        if (options.select >= 0 && app.hasScene()) {
            if (std::size_t(options.select) >= app.scene().size())
                throw Error("--select " + std::to_string(options.select) + ": the scene has " +
                            std::to_string(app.scene().size()) + " patches");
            app.select(PatchId(options.select), false);
        }
        if (options.hover >= 0 && (!app.hasScene() || std::size_t(options.hover) >= app.scene().size()))
            throw Error("--hover " + std::to_string(options.hover) + ": the scene has " +
                        std::to_string(app.hasScene() ? app.scene().size() : 0) + " patches");
        // Scripted meshing, as the panel's Apply (undoable): the whole scene, or the objects of --select.
        if (app.hasScene() && options.mesh > 0 && !app.mesh(options.mesh, MeshTarget::Scene))
            throw Error("--mesh: " + app.log().back().text);
        if (app.hasScene() && options.meshSelected > 0 && !app.mesh(options.meshSelected, MeshTarget::SelectedObjects))
            throw Error("--mesh-selected: " + app.log().back().text);
        if (options.run && app.hasScene()) app.runPipeline();
        // Scripted thermal input, as the Scene panel's Load buttons: an error is logged (--exit fails).
        for (const std::string& path : options.properties)
            if (app.hasScene()) app.loadThermalProperties(path);
        for (const std::string& path : options.conditions)
            if (app.hasScene()) app.loadThermalConditions(path);
        if (options.thermal && app.hasScene()) {
            app.wait();  // after --run's job
            app.poll();
            app.runThermal();
        }
        if (options.sunSky && app.hasScene()) {
            app.wait();  // after --run's or --thermal's job
            app.poll();
            app.runSunSky();
        }
        {
            Viewer viewer;
            Inspector inspector;
            std::optional<PatchId> hovered;
            int framesSinceDone = 0;
            // Frames are drawn while something changes, not all the time: a scripted run polls; a
            // running job redraws 30 times a second (progress, progressive solves); after an event a
            // few frames let ImGui settle; idle, the loop sleeps until an event (or 2 s pass).
            const auto started = std::chrono::steady_clock::now();
            const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(); };
            long frames = 0;
            std::string windowTitle = "Hemirad";
            FramePacing pacing;
            TooltipCheck tooltips;
            while (!glfwWindowShouldClose(window) && !requests.quit) {
                const bool scripted = !options.screenshot.empty() || options.exitAfter;
                switch (pacing.next(scripted, app.job().running, input.taps.pending())) {
                    case FramePacing::Wait::Poll: glfwPollEvents(); break;
                    case FramePacing::Wait::Job: glfwWaitEventsTimeout(1.0 / 30.0); break;
                    case FramePacing::Wait::Idle: {
                        const double limit = options.quitAfter > 0 ? std::max(options.quitAfter - seconds(), 1e-3) : 2.0;
                        glfwWaitEventsTimeout(std::min(2.0, limit));
                        break;
                    }
                }
                pacing.eventsProcessed(std::exchange(input.eventSeen, false));
                if (options.quitAfter > 0 && seconds() >= options.quitAfter) requests.quit = true;
                // The title names the scene and says when it has unsaved edits.
                const std::string title = app.hasScene() ? "Hemirad - " + std::filesystem::path(app.scenePath()).filename().string() +
                                                               (app.dirty() ? " (edited)" : "")
                                                         : std::string("Hemirad");
                if (title != windowTitle) {
                    windowTitle = title;
                    glfwSetWindowTitle(window, title.c_str());
                }
                ++frames;
                app.poll();
                ImGui_ImplOpenGL3_NewFrame();
                ImGui_ImplGlfw_NewFrame();
                if (tooltips.planned()) tooltips.placeMouse();
                ImGui::NewFrame();
                ImGuiIO& io = ImGui::GetIO();
                int width = 0, height = 0;
                glfwGetFramebufferSize(window, &width, &height);

                for (const std::string& path : input.dropped) panels.open(app, camera, path);
                input.dropped.clear();

                // Mouse on the view (not on a panel): orbit, pan, zoom, pick.
                double x = 0, y = 0;
                glfwGetCursorPos(window, &x, &y);
                if (!io.WantCaptureMouse) {
                    // No hover highlight in a scripted screenshot (Xvfb parks the pointer mid-window).
                    hovered = input.pointerSeen && options.screenshot.empty() ? viewer.pick(int(x), int(y)) : std::nullopt;
                    for (int b = 0; b < 3; ++b)
                        if (ImGui::IsMouseClicked(b)) {
                            input.dragging = true;
                            input.moved = false;
                            input.button = b;
                            input.pressX = input.lastX = input.downX[b];
                            input.pressY = input.lastY = input.downY[b];
                        }
                    if (io.MouseWheel != 0.0f) camera.zoom(io.MouseWheel);
                } else {
                    hovered.reset();
                }
                if (input.dragging) {
                    // A click or a drag is told by where the button went down and up (its events),
                    // not where the pointer is when a frame sees them: a quick click, the hand moving
                    // on at once, orbited instead of selecting (issue 38 #16).
                    const bool released = ImGui::IsMouseReleased(input.button);
                    // Up already (its release event came with the press, ImGui tells it next frame):
                    // the drag ended where the button went up.
                    const bool up = released || !input.down[input.button];
                    const double px = up ? input.upX[input.button] : x, py = up ? input.upY[input.button] : y;
                    const double dx = px - input.lastX, dy = py - input.lastY;
                    if (std::hypot(px - input.pressX, py - input.pressY) > io.MouseDragThreshold) input.moved = true;
                    if (input.moved) {
                        if (input.button == 0 && !io.KeyShift) camera.orbit(dx, dy);
                        else camera.pan(dx, dy, height);
                    }
                    input.lastX = px;
                    input.lastY = py;
                    if (released) {
                        if (!input.moved && input.button == 0) {
                            if (const auto id = viewer.pick(int(input.pressX), int(input.pressY)))
                                app.select(*id, io.KeyCtrl || io.KeyShift);
                            else app.clearSelection();
                        }
                        input.dragging = false;
                    }
                }
                // Ctrl shortcuts: Open, Save (Shift: Save as), Undo, Redo, Quit; not while typing in a field.
                for (const auto& [key, mods] : input.shortcuts) {
                    if (io.WantCaptureKeyboard) break;
                    if (key == GLFW_KEY_O) panels.browse("Open OBJ", app.hasScene() ? app.scenePath() : std::string());
                    else if (key == GLFW_KEY_Q) panels.guarded(app, "quit", [&] { requests.quit = true; });
                    else if (!app.hasScene()) continue;
                    else if (key == GLFW_KEY_S && (mods & GLFW_MOD_SHIFT)) panels.browse("Save scene", app.scenePath());
                    else if (key == GLFW_KEY_S) panels.save(app);
                    else if (key == GLFW_KEY_Z) app.undo();
                    else if (key == GLFW_KEY_Y) app.redo();
                }
                input.shortcuts.clear();
                // Key changes KeyTaps held back while a text field had the keyboard are still typing
                // when they reach ImGui after it closed: the last letters of "stuff.hff" typed fast,
                // then Enter, pressed F again a frame later and framed the view (issue 38 #16).
                if (io.WantCaptureKeyboard && input.taps.pending()) input.typedTaps = true;
                if (!input.taps.pending()) input.typedTaps = false;
                const bool viewKeys = !io.WantCaptureKeyboard && !input.typedTaps;
                if (viewKeys && ImGui::IsKeyPressed(GLFW_KEY_F1)) panels.toggleHelp();
                // Esc closes the help window, else selects none.
                const bool escape = viewKeys && !io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_ESCAPE);
                if (escape && !panels.closeHelp() && app.hasScene()) app.clearSelection();
                if (viewKeys && app.hasScene() && !io.KeyCtrl) {
                    if (ImGui::IsKeyPressed(GLFW_KEY_F)) camera.frame(app.scene());
                    if (ImGui::IsKeyPressed(GLFW_KEY_S) && !app.selection().empty()) camera.frameSelection(app.scene(), app.selection());
                    if (ImGui::IsKeyPressed(GLFW_KEY_C)) camera.useSceneCamera(app.scene());
                }
                if (glfwWindowShouldClose(window) && app.dirty()) {
                    glfwSetWindowShouldClose(window, GLFW_FALSE);
                    panels.guarded(app, "quit", [&] { requests.quit = true; });
                }

                // Scripted runs read out --hover's patch as if the cursor were on it.
                const std::optional<PatchId> readout =
                    hovered ? hovered : options.hover >= 0 ? std::optional<PatchId>(PatchId(options.hover)) : std::nullopt;
                panels.draw(app, camera, inspector, viewer.exposure(), requests, readout);
                ImGui::Render();
                // Held-back key releases, for the next frame (inside a frame they would change its modifiers).
                for (const KeyEvent& e : input.taps.frameEnded()) input.imguiKey(window, e.key, e.scancode, e.action, e.mods);
                if (tooltips.planned()) {
                    // The tooltip sweep looks at ImGui's state only: nothing is drawn meanwhile.
                    tooltips.observe();
                    if (tooltips.finished()) requests.quit = true;
                    continue;
                }
                gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
                gl::Viewport(0, 0, width, height);
                gl::ClearColor(0.08f, 0.08f, 0.09f, 1.0f);
                gl::Clear(GL_COLOR_BUFFER_BIT);
                try {
                    viewer.render(app, camera, width, height, hovered);
                } catch (const Error& e) {
                    app.error(e.what());
                }
                if (!requests.exportImage.empty()) {
                    try {
                        screenshot(requests.exportImage, width, height, GL_BACK);
                        app.info("exported " + requests.exportImage + " (the view, exposure " + std::to_string(viewer.exposure()) + ")");
                    } catch (const Error& e) {
                        app.error(e.what());
                    }
                    requests.exportImage.clear();
                }
                ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

                // --run --screenshot: once the results are in and drawn, save the window with its UI.
                const bool done = !app.job().running;
                framesSinceDone = done ? framesSinceDone + 1 : 0;
                if (framesSinceDone >= 3 && (!options.screenshot.empty() || options.exitAfter)) {
                    if (!options.screenshot.empty()) {
                        screenshot(options.screenshot, width, height, GL_BACK);
                        std::printf("hemirad-gui: wrote %s (%dx%d)\n", options.screenshot.c_str(), width, height);
                        options.screenshot.clear();
                    }
                    // --check-tooltips: the sweep starts from the panels as drawn now, and ends the run.
                    if (options.checkTooltips && !tooltips.planned()) tooltips.plan(panels.panelRects());
                    if (options.exitAfter && !options.checkTooltips) requests.quit = true;
                }
                glfwSwapBuffers(window);
            }
            // Scripted runs (--exit, --quit-after) print the whole log and fail if anything went wrong.
            const bool scriptedExit = options.exitAfter || options.quitAfter > 0;
            for (const LogEntry& e : app.log()) {
                if (e.error) {
                    std::fprintf(stderr, "hemirad-gui: error: %s\n", e.text.c_str());
                    if (scriptedExit) status = 1;
                } else if (scriptedExit) {
                    std::printf("hemirad-gui: %s\n", e.text.c_str());
                }
            }
            if (scriptedExit) {
                std::printf("hemirad-gui: %ld frames drawn in %.2f s\n", frames, seconds());
                if (pacing.leastFramesAfterInput() >= 0)
                    std::printf("hemirad-gui: after input, at least %d frames before sleeping\n", pacing.leastFramesAfterInput());
                if (app.layer == Layer::FalseColour) {
                    const FalseColourView view = app.falseColourView();
                    if (!view.error.empty()) std::printf("hemirad-gui: %s\n", view.error.c_str());
                    else std::printf("hemirad-gui: false colour: %s, %s scale %.9g .. %.9g\n", app.falseColourLegend().first.c_str(),
                                     falseColourScaleName(view.range.scale), view.range.min, view.range.max);
                }
                if (app.hasScene()) {
                    std::printf("hemirad-gui: scene: %s\n", sceneCounts(app.scene()).c_str());
                    const Vec3 from = (camera.eye() - camera.target).normalized();
                    std::printf("hemirad-gui: up axis %s, %s; view from %.3f %.3f %.3f\n", upAxisName(app.upAxis()),
                                upAxisSourceText(app.upAxisSource()), from.x(), from.y(), from.z());
                }
                std::printf("hemirad-gui: status: %s\n", panels.status().c_str());
                if (app.hasScene()) std::printf("hemirad-gui: %s\n", runEstimateText(app.formFactorEstimate()).c_str());
                if (!panels.legendTicks().empty()) {
                    std::string ticks;
                    for (const std::string& t : panels.legendTicks()) ticks += (ticks.empty() ? "" : " | ") + t;
                    std::printf("hemirad-gui: legend ticks: %s\n", ticks.c_str());
                }
                for (const std::vector<std::string>& row : panels.objectTable()) {
                    std::string line;
                    for (const std::string& cell : row) line += (line.empty() ? "" : " | ") + cell;
                    std::printf("hemirad-gui: object table: %s\n", line.c_str());
                }
                if (!panels.legend().first.empty())
                    std::printf("hemirad-gui: legend: %s | %s\n", panels.legend().first.c_str(), panels.legend().second.c_str());
                for (const std::string& line : panels.thermal().resultLines()) std::printf("hemirad-gui: thermal panel: %s\n", line.c_str());
                for (const std::string& line : panels.sunSky().resultLines())
                    std::printf("hemirad-gui: sky and sun panel: %s\n", line.c_str());
                if (!panels.sunSky().sunMark().empty())
                    std::printf("hemirad-gui: sun drawn at %.0f,%.0f\n", panels.sunSky().sunMark()[0], panels.sunSky().sunMark()[1]);
                for (const std::vector<std::string>& row : panels.thermal().exchangeTable()) {
                    std::string line;
                    for (const std::string& cell : row) line += (line.empty() ? "" : " | ") + cell;
                    std::printf("hemirad-gui: exchange table: %s\n", line.c_str());
                }
                if (options.checkTooltips) {
                    std::istringstream lines(tooltips.report());
                    for (std::string line; std::getline(lines, line);) std::printf("hemirad-gui: %s\n", line.c_str());
                    if (tooltips.missing() > 0) status = 1;
                }
                for (const auto& [name, r] : panels.panelRects())
                    std::printf("hemirad-gui: panel %s at %.0f,%.0f size %.0fx%.0f\n", name.c_str(), r.x, r.y, r.width, r.height);
                for (const auto& [name, r] : panels.itemRects())
                    std::printf("hemirad-gui: item %s at %.0f,%.0f size %.0fx%.0f\n", name.c_str(), r.x, r.y, r.width, r.height);
            }
        }
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "hemirad-gui: error: %s\n", e.what());
        status = 1;
    }
    glfwDestroyWindow(window);
    glfwTerminate();
    return status;
}
