// ImGui panels of hemirad-gui.
#include "ui/panels.hpp"
#include "ui/panel_tip.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"
#include "engine/form_factor_notes.hpp"
#include "preprocess/backend_registry.hpp"
#include "rays/ray_scene.hpp"
#include "solve/solver_registry.hpp"
#include "ui/run_estimate.hpp"
#include "ui/units.hpp"

#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace hemirad::ui {
namespace {

const char* kLayerNames[] = {"Radiosity", "Patch id", "Emission", "Diffuse reflectance", "Specular", "F row of selection",
                             "False colour"};
constexpr int kLayerCount = int(sizeof kLayerNames / sizeof kLayerNames[0]);

/// The help window's table: what to press, what it does.
const std::pair<const char*, const char*> kMouseAndKeys[] = {
    {"left drag", "orbit around the target"},
    {"right or middle drag, Shift + left drag", "pan"},
    {"wheel", "zoom"},
    {"click", "select the patch (or, with Pick: object, its object)"},
    {"Ctrl/Shift + click", "add to the selection"},
    {"hover", "the status bar reads the patch out: B, H, E, rho, s, F from the selected patch"},
    {"F", "frame the scene (from its camera's or its open side, upright about its up axis)"},
    {"S", "frame the selection"},
    {"C", "the scene's camera"},
    {"Esc", "close this window or a dialog, else select none"},
    {"Ctrl+O", "open an OBJ"},
    {"Ctrl+S / Ctrl+Shift+S", "save the scene (OBJ + MTL) / save it as"},
    {"Ctrl+Z / Ctrl+Y", "undo / redo a material edit or a meshing"},
    {"Ctrl+Q", "quit (asks when edits are unsaved)"},
    {"F1", "this window"},
    {"Ctrl + click on a field", "type a value into a slider"},
};

std::string formatBytes(std::uintmax_t bytes) {
    char text[32];
    if (bytes < 1024) std::snprintf(text, sizeof text, "%ju B", bytes);
    else if (bytes < 1024 * 1024) std::snprintf(text, sizeof text, "%.1f KiB", double(bytes) / 1024.0);
    else std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / 1048576.0);
    return text;
}

bool isObjPath(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".obj";
}

}  // namespace

Panels::Panels(std::string recentFilesPath) : m_recentPath(std::move(recentFilesPath)) {
    std::ifstream in(m_recentPath);
    std::string line;
    while (std::getline(in, line))
        if (!line.empty() && m_recent.size() < 10) m_recent.push_back(line);
}

void Panels::remember(const std::string& path) {
    const std::string absolute = std::filesystem::absolute(path).string();
    m_recent.erase(std::remove(m_recent.begin(), m_recent.end(), absolute), m_recent.end());
    m_recent.push_front(absolute);
    while (m_recent.size() > 10) m_recent.pop_back();
    if (m_recentPath.empty()) return;
    try {
        std::filesystem::create_directories(std::filesystem::path(m_recentPath).parent_path());
        AtomicFile file(m_recentPath, false);
        for (const std::string& p : m_recent) file.stream() << p << '\n';
        file.commit();
    } catch (const std::exception&) {
        // Recent files are a convenience: a read-only home must not stop the program.
    }
}

void Panels::guarded(AppState& app, const std::string& what, std::function<void()> action) {
    if (!app.dirty()) {
        action();
        return;
    }
    m_confirmWhat = what;
    m_confirmAction = std::move(action);
    m_openConfirm = true;
    m_showHelp = false;
}

void Panels::open(AppState& app, OrbitCamera& camera, const std::string& path) {
    guarded(app, "open " + path, [this, &app, &camera, path] {
        if (app.loadScene(path)) {
            remember(path);
            camera.useSceneCamera(app.scene());
        }
    });
}

void Panels::browse(const std::string& purpose, const std::string& initial) {
    static const std::map<std::string, std::pair<std::vector<std::string>, bool>> kinds = {
        {"Open OBJ", {{".obj", ".stl"}, true}},        {"Save scene", {{".obj"}, false}},
        {"Import F", {{".hff", ".mtx"}, true}}, {"Export F", {{".hff", ".mtx"}, false}},
        {"Export PNG", {{".png"}, false}},      {"Export PLY", {{".ply"}, false}},
        {"Export object table", {{".csv"}, false}},
        {"Thermal properties", {{".toml"}, true}}, {"Boundary conditions", {{".toml"}, true}},
        {"Export exchange table", {{".csv"}, false}},
        {"Export conductors", {{".csv", ".mtx", ".esatan", ".cnd", ".sinda", ".inp"}, false}}};
    const auto kind = kinds.at(purpose);
    // One dialog at a time: the help window would stand over the browser (issue 38 #11).
    m_showHelp = false;
    m_browser.start(purpose, kind.first, initial, kind.second);
    std::snprintf(m_pathBuffer, sizeof m_pathBuffer, "%s", m_browser.typed.c_str());
    m_openPathPrompt = true;
}

void Panels::save(AppState& app) {
    if (!app.hasScene()) return;
    if (isObjPath(app.scenePath())) app.saveScene(app.scenePath());
    else browse("Save scene", "scene.obj");
}

Panels::Layout Panels::layout(float width, float height) {
    // A column on each side of the view: Scene (and the material editor) left over the Log; Pipeline
    // over Selection on the right. Everything inside the window; panels scroll what does not fit.
    // The status bar runs along the bottom edge.
    constexpr float kMargin = 8.0f, kTop = 28.0f, kStatus = 24.0f;
    Layout l;
    const float side = std::clamp(width * 0.27f, 260.0f, 420.0f);
    const float logHeight = std::clamp(height * 0.2f, 100.0f, 220.0f);
    const float right = width - side - kMargin;
    const float bottom = height - kStatus;
    const float column = bottom - kTop - kMargin;
    l.status = {0.0f, bottom, width, kStatus};
    l.scene = {kMargin, kTop, side, std::min(column - logHeight - kMargin, 340.0f)};  // the editor fits
    l.log = {kMargin, bottom - logHeight - kMargin, std::max(right - 2 * kMargin, side), logHeight};
    l.pipeline = {right, kTop, side, std::floor(column * 0.5f) - kMargin / 2};
    l.selection = {right, kTop + std::floor(column * 0.5f) + kMargin / 2, side, column - std::floor(column * 0.5f) - kMargin / 2};
    l.legend = {2 * kMargin + side, kTop, 210.0f, std::min(column - logHeight - kMargin, 420.0f)};
    return l;
}

bool Panels::beginPanel(const char* name, const Rect& rect, bool relayout) {
    const ImGuiCond when = relayout ? ImGuiCond_Always : ImGuiCond_FirstUseEver;
    ImGui::SetNextWindowPos(ImVec2(rect.x, rect.y), when);
    ImGui::SetNextWindowSize(ImVec2(rect.width, rect.height), when);
    const bool open = ImGui::Begin(name);
    const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    m_panelRects[name] = {pos.x, pos.y, size.x, size.y};
    return open;
}

void Panels::draw(AppState& app, OrbitCamera& camera, Inspector& inspector, double viewExposure, LoopRequests& requests,
                  std::optional<PatchId> hovered) {
    m_panelRects.clear();
    m_itemRects.clear();
    menuBar(app, camera, requests);
    const float width = ImGui::GetIO().DisplaySize.x, height = ImGui::GetIO().DisplaySize.y;
    // The layout is applied at start and whenever the window's size changes; in between the user
    // may move and resize panels.
    const bool relayout = width != m_layoutWidth || height != m_layoutHeight;
    m_layoutWidth = width;
    m_layoutHeight = height;
    const Layout l = layout(width, height);
    const ThermalPanel::Browse browseFile = [this](const std::string& purpose, const std::string& initial) { browse(purpose, initial); };
    if (beginPanel("Scene", l.scene, relayout)) {
        scenePanel(app, camera);
        materialPanel(app);
        m_thermal.section(app, browseFile);
        m_sunSky.section(app);
    }
    ImGui::End();
    if (app.hasScene()) m_sunSky.drawSun(app, camera, width, height);
    if (beginPanel("Pipeline", l.pipeline, relayout)) pipelinePanel(app);
    ImGui::End();
    if (!app.selection().empty()) {
        if (beginPanel("Selection", l.selection, relayout || m_selectionHidden)) selectionPanel(app, inspector, viewExposure);
        ImGui::End();
    }
    m_selectionHidden = app.selection().empty();
    if (beginPanel("Log", l.log, relayout)) logPanel(app);
    ImGui::End();
    // The false colour's legend, or the F-row layer's scale.
    const bool legend = app.hasScene() && (app.layer == Layer::FalseColour || app.layer == Layer::FormFactorRow);
    m_legendTicks.clear();
    if (legend) {
        if (beginPanel("Legend", l.legend, relayout || m_legendHidden)) {
            if (app.layer == Layer::FalseColour) legendPanel(app);
            else rowLegendPanel(app);
        }
        ImGui::End();
    }
    m_legendHidden = !legend;
    if (app.layer != Layer::FalseColour || !app.hasScene()) m_legend = {};
    m_thermal.exchangeWindow(app, browseFile, width, height);
    if (const auto& r = m_thermal.exchangeRect()) m_panelRects["Thermal exchange"] = {(*r)[0], (*r)[1], (*r)[2], (*r)[3]};
    if (!m_showObjects || !app.hasScene()) m_objectTable.clear();
    if (m_showObjects && app.hasScene()) {
        ImGui::SetNextWindowSize(ImVec2(620, 260), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowPos(ImVec2(width * 0.5f - 310, height * 0.3f), ImGuiCond_FirstUseEver);
        if (ImGui::Begin("Objects", &m_showObjects)) objectsPanel(app);
        ImGui::End();
    }
    if (m_showHelp) {
        ImGui::SetNextWindowSize(ImVec2(560, 0), ImGuiCond_Appearing);
        ImGui::SetNextWindowPos(ImVec2(width * 0.5f, height * 0.45f), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
        if (ImGui::Begin("Help", &m_showHelp, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings)) {
            helpPanel();
            const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
            m_panelRects["Help"] = {pos.x, pos.y, size.x, size.y};
        }
        ImGui::End();
    }
    statusBar(app, l.status, hovered, viewExposure);
    modals(app, camera, requests);
}

std::string Panels::statusText(const AppState& app, std::optional<PatchId> hovered, double viewExposure) {
    if (!app.hasScene()) return "no scene";
    const auto rgb = formatRgb;
    std::string text;
    // The patch under the cursor, else the (first) selected one.
    const std::optional<PatchId> shown = hovered ? hovered : app.selection().empty() ? std::nullopt
                                                                                      : std::optional<PatchId>(app.selection().front());
    if (const auto r = shown ? app.readout(*shown) : std::nullopt) {
        text += "patch " + std::to_string(r->patch) + " '" + r->object + "'";
        text += " | B " + rgb(r->B) + " W/m^2 | H " + rgb(r->H) + " W/m^2 | E " + rgb(r->emission) + " W/m^2";
        text += " | rho " + rgb(r->rho) + " s " + formatNumber(r->specular);
        if (r->fromSelected)
            text += " | F " + std::to_string(*r->selected) + "->" + std::to_string(r->patch) + " " + formatNumber(*r->fromSelected);
        // The last thermal run's values of the patch (the Thermal section's Run thermal).
        if (const ThermalResult* t = app.thermalResult())
            text += " | T " + formatNumber(t->solution.T[r->patch]) + " K, q " + formatNumber(t->solution.q[r->patch]) + " W/m^2";
        // The last Sky and sun run's values of the patch.
        if (const SunSkyResult* e = app.sunSkyResult())
            text += " | sunlit " + formatNumber(e->sunlit[r->patch]) + ", solar " + formatNumber(e->irradiance.total[r->patch]) + " W/m^2";
    } else {
        text += "hover a patch for its values";
    }
    char tail[96];
    std::snprintf(tail, sizeof tail, " | exposure %+.1f EV", std::log2(std::max(viewExposure, 1e-300)));
    text += tail;
    if (const FormFactors* F = app.formFactors()) {
        std::snprintf(tail, sizeof tail, " | F %.1f MiB", double(F->memoryBytes()) / 1048576.0);
        text += tail;
    }
    return text;
}

void Panels::statusBar(AppState& app, const Rect& rect, std::optional<PatchId> hovered, double viewExposure) {
    ImGui::SetNextWindowPos(ImVec2(rect.x, rect.y));
    ImGui::SetNextWindowSize(ImVec2(rect.width, rect.height));
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoBringToFrontOnFocus;
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(8.0f, 4.0f));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowMinSize, ImVec2(1.0f, 1.0f));  // one line high, not ImGui's 32 px minimum
    if (ImGui::Begin("Status", nullptr, flags)) {
        m_status = statusText(app, hovered, viewExposure);
        ImGui::TextUnformatted(m_status.c_str());
        const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
        m_panelRects["Status"] = {pos.x, pos.y, size.x, size.y};
    }
    ImGui::End();
    ImGui::PopStyleVar(2);
}

void Panels::menuBar(AppState& app, OrbitCamera& camera, LoopRequests& requests) {
    if (!ImGui::BeginMainMenuBar()) return;
    auto prompt = [this](const char* purpose, const std::string& initial) { browse(purpose, initial); };
    const std::string stem = app.hasScene() ? std::filesystem::path(app.scenePath()).replace_extension().string() : "scene";
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("Open OBJ...", "Ctrl+O")) prompt("Open OBJ", app.scenePath());
        if (ImGui::BeginMenu("Recent files", !m_recent.empty())) {
            for (const std::string& path : std::deque<std::string>(m_recent))
                if (ImGui::MenuItem(path.c_str())) open(app, camera, path);
            ImGui::EndMenu();
        }
        ImGui::Separator();
        if (ImGui::MenuItem("Save", "Ctrl+S", false, app.hasScene())) save(app);
        if (ImGui::MenuItem("Save scene as OBJ + MTL...", "Ctrl+Shift+S", false, app.hasScene())) prompt("Save scene", stem + "_edited.obj");
        if (ImGui::MenuItem("Import F (.hff, .mtx)...", nullptr, false, app.hasScene())) prompt("Import F", stem + ".hff");
        if (ImGui::MenuItem("Export F (.hff, .mtx)...", nullptr, false, app.formFactors() != nullptr)) prompt("Export F", stem + ".hff");
        if (ImGui::MenuItem("Export PNG...", nullptr, false, app.hasScene())) prompt("Export PNG", stem + ".png");
        if (ImGui::MenuItem("Export PLY...", nullptr, false, app.hasScene())) prompt("Export PLY", stem + ".ply");
        if (ImGui::MenuItem("Export object table (CSV)...", nullptr, false, app.hasScene()))
            prompt("Export object table", stem + "_objects.csv");
        if (ImGui::MenuItem("Export thermal exchange (CSV)...", nullptr, false, app.thermalResult() != nullptr))
            prompt("Export exchange table", stem + "_exchange.csv");
        if (ImGui::MenuItem("Export radiative conductors (ESATAN, SINDA, CSV)...", nullptr, false, app.thermalResult() != nullptr))
            prompt("Export conductors", stem + "_GR.esatan");
        ImGui::Separator();
        if (ImGui::MenuItem("Quit", "Ctrl+Q")) guarded(app, "quit", [&requests] { requests.quit = true; });
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Edit")) {
        if (ImGui::MenuItem("Undo (material, thermal edit, meshing)", "Ctrl+Z", false, app.canUndo())) app.undo();
        if (ImGui::MenuItem("Redo", "Ctrl+Y", false, app.canRedo())) app.redo();
        if (ImGui::MenuItem("Select none", "Esc", false, !app.selection().empty())) app.clearSelection();
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("View")) {
        for (int k = 0; k < kLayerCount; ++k)
            if (ImGui::MenuItem(kLayerNames[k], nullptr, int(app.layer) == k)) app.layer = Layer(k);
        ImGui::Separator();
        ImGui::MenuItem("Object table", nullptr, &m_showObjects, app.hasScene());
        ImGui::MenuItem("Thermal exchange table", nullptr, &m_thermal.showExchange, app.thermalResult() != nullptr);
        ImGui::Separator();
        ImGui::MenuItem("Gouraud shading", nullptr, &app.gouraud);
        ImGui::MenuItem("Mirrors show reflections", nullptr, &app.showReflections);
        ImGui::MenuItem("Automatic exposure", nullptr, &app.autoExposure);
        ImGui::Separator();
        if (ImGui::MenuItem("Frame scene", "F", false, app.hasScene())) camera.frame(app.scene());
        if (ImGui::MenuItem("Frame selection", "S", false, app.hasScene() && !app.selection().empty()))
            camera.frameSelection(app.scene(), app.selection());
        if (ImGui::BeginMenu("Look from", app.hasScene())) {
            // Top and bottom along the scene's up axis, then the other two axes.
            const int up = app.upAxis(), side = 3 - up;
            const struct {
                std::string label;
                int axis;
                bool positive;
            } views[] = {{std::string("Top (+") + upAxisName(up) + ")", up, true}, {std::string("Bottom (-") + upAxisName(up) + ")", up, false},
                         {"+x", 0, true}, {"-x", 0, false}, {std::string("+") + "xyz"[side], side, true},
                         {std::string("-") + "xyz"[side], side, false}};
            for (const auto& v : views)
                if (ImGui::MenuItem(v.label.c_str())) camera.lookAlong(app.scene(), v.axis, v.positive);
            ImGui::EndMenu();
        }
        if (ImGui::MenuItem("Scene camera", "C", false, app.hasScene())) camera.useSceneCamera(app.scene());
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Help")) {
        ImGui::MenuItem("Keyboard and mouse", "F1", &m_showHelp);
        ImGui::EndMenu();
    }
    const JobStatus job = app.job();
    if (job.running) {
        ImGui::Text("   %s %.0f%%  (%.1f s)", job.stage.c_str(), 100.0 * job.progress, job.elapsed);
        // Cancel where it is always in sight (the Pipeline panel's may be scrolled away).
        ImGui::BeginDisabled(job.cancelling);
        if (ImGui::SmallButton(job.cancelling ? "cancelling" : "Cancel")) app.cancel();
        ImGui::EndDisabled();
        tip("Stop the running job (between rows, or solver sweeps); the scene and the last results stay");
        const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
        m_itemRects["CancelButton"] = {lo.x, lo.y, hi.x - lo.x, hi.y - lo.y};
    } else if (app.formFactorsStale()) ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "   F is stale: press Run");
    else if (app.radiosityStale() && app.formFactors()) ImGui::TextColored(ImVec4(1, 0.9f, 0.3f, 1), "   radiosity out of date");
    ImGui::EndMainMenuBar();
}

void Panels::scenePanel(AppState& app, OrbitCamera& camera) {
    if (!app.hasScene()) {
        ImGui::TextWrapped("No scene. File > Open OBJ, or drop an .obj file on the window.");
        return;
    }
    const Scene& s = app.scene();
    ImGui::TextWrapped("%s%s", app.scenePath().c_str(), app.dirty() ? "  (edited)" : "");
    ImGui::TextUnformatted(sceneCounts(s).c_str());
    const std::string unitShown = s.unit.empty() ? "not stated" : s.unit;
    const bool unitOpen = ImGui::BeginCombo("Unit", unitShown.c_str());
    tip("The scene's length unit (OBJ: '# hemirad unit mm'): labels lengths and areas, gives a selection's\n"
        "power in W; saved with the scene. Radiosity, irradiance and emission are W/m^2 whatever the unit.");
    if (unitOpen) {
        if (ImGui::Selectable("not stated", s.unit.empty())) app.setUnit("");
        tip("Lengths and areas in scene units; power as W/m^2 x scene units^2");
        for (const std::string& u : lengthUnits()) {
            if (ImGui::Selectable(u.c_str(), s.unit == u)) app.setUnit(u);
            tip(("The scene's coordinates are in " + u).c_str());
        }
        ImGui::EndCombo();
    }
    int up = app.upAxis();
    ImGui::Text("Up:");
    ImGui::SameLine();
    const bool upY = ImGui::RadioButton("y##up", &up, 1);
    tip("The scene's up axis is y (the OBJ convention): F frames it, the view orbits about it");
    ImGui::SameLine();
    const bool upZ = ImGui::RadioButton("z##up", &up, 2);
    tip("The scene's up axis is z (sites, CAD data): F frames it, the view orbits about it");
    if (upY || upZ) {
        app.setUpAxis(up);
        camera.frame(s);
    }
    ImGui::SameLine();
    ImGui::TextDisabled("(%s)", upAxisSourceText(app.upAxisSource()));
    int mode = int(app.selectionMode);
    ImGui::Text("Pick:");
    ImGui::SameLine();
    ImGui::RadioButton("patch", &mode, 0);
    tip("A click in the view selects one patch (Ctrl/Shift + click adds)");
    ImGui::SameLine();
    ImGui::RadioButton("object", &mode, 1);
    tip("A click in the view selects the whole object under the cursor");
    app.selectionMode = SelectionMode(mode);
    int layer = int(app.layer);
    ImGui::Combo("Layer", &layer, kLayerNames, kLayerCount);
    tip("What the view shows: radiance (tone-mapped), patch ids, emission, reflectances,\n"
        "F of the selected patch to every other (log colours), or false colour with a legend");
    app.layer = Layer(layer);
    ImGui::Checkbox("Gouraud", &app.gouraud);
    tip("Smooth shading: radiosity interpolated from the vertices (creases at edges, emission and\n"
        "material boundaries); off: each patch flat, its own value");
    ImGui::SameLine();
    ImGui::Checkbox("Reflections", &app.showReflections);
    tip("Mirrors show what they reflect, mirrors in mirrors to the Pipeline's mirror depth");
    ImGui::Checkbox("Auto exposure", &app.autoExposure);
    tip("Scale the view so that 95% of the lit patches are below 80% white; off: set it by hand");
    if (!app.autoExposure) {
        float ev = float(std::log2(std::max(app.exposure, 1e-30)));
        if (ImGui::SliderFloat("Exposure (EV)", &ev, -20.0f, 20.0f, "%.1f")) app.exposure = std::exp2(double(ev));
        tip("Display scale in stops (EV): +1 doubles the brightness; Ctrl+click to type");
    }
    if (ImGui::Button("Frame scene")) camera.frame(s);
    tip("Look at the whole scene from its camera's side, or its open side (key F)");
    ImGui::SameLine();
    if (ImGui::Button("Scene camera")) camera.useSceneCamera(s);
    tip("The camera of the OBJ's '# hemirad camera' line (key C)");
}

void Panels::materialPanel(AppState& app) {
    if (!app.hasScene() || app.selection().empty()) return;
    ImGui::Separator();
    ImGui::Text("Material of %zu selected patch%s", app.selection().size(), app.selection().size() == 1 ? "" : "es");
    // The first selected patch's values, again after every edit, undo, redo and refused edit (never stale).
    m_material.sync(app);
    // Numeric fields in double: a value is stored as typed, and untouched channels keep theirs.
    const auto swatch = [](const char* id, const double c[3], double scale, const char* what) {
        const float k = float(scale > 0 ? 1.0 / scale : 0.0);
        ImGui::ColorButton(id, ImVec4(float(c[0]) * k, float(c[1]) * k, float(c[2]) * k, 1.0f), ImGuiColorEditFlags_NoTooltip);
        tip(what);
        ImGui::SameLine();
    };
    // The fields fill the panel's width up to their labels.
    ImGui::PushItemWidth(-ImGui::CalcTextSize("Diffuse reflectance").x - ImGui::GetStyle().ItemInnerSpacing.x);
    MaterialEdit edit;
    swatch("##emission", m_material.emission, std::max({m_material.emission[0], m_material.emission[1], m_material.emission[2]}),
           "The emission's colour (scaled to its largest channel)");
    ImGui::InputScalarN("Emission W/m^2", ImGuiDataType_Double, m_material.emission, 3, nullptr, nullptr, "%.6g");
    if (ImGui::IsItemDeactivatedAfterEdit()) edit.emission = Rgb(m_material.emission[0], m_material.emission[1], m_material.emission[2]);
    tip("Emitted radiosity E (W/m^2) per channel (MTL Ke) of the selected patches; re-solves at once");
    swatch("##rho", m_material.rho, 1.0, "The diffuse reflectance's colour");
    ImGui::InputScalarN("Diffuse reflectance", ImGuiDataType_Double, m_material.rho, 3, nullptr, nullptr, "%.6g");
    if (ImGui::IsItemDeactivatedAfterEdit()) edit.rho = Rgb(m_material.rho[0], m_material.rho[1], m_material.rho[2]);
    tip("Diffuse reflectance rho in [0, 1] per channel (MTL Kd); rho + s <= 1; re-solves at once");
    const double zero = 0.0, one = 1.0;
    ImGui::SliderScalar("Mirror reflectance", ImGuiDataType_Double, &m_material.specular, &zero, &one, "%.3f");
    if (ImGui::IsItemDeactivatedAfterEdit()) edit.specular = m_material.specular;
    tip("Specular (mirror) reflectance s (MTL Ks, illum 3); changes F: Run computes it again.\n"
        "Ctrl+click to type an exact value");
    ImGui::PopItemWidth();
    if (edit.emission || edit.rho || edit.specular) m_material.apply(app, edit);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("emission/diffuse edits re-solve with the current F; mirror edits need a new F");
    ImGui::PopTextWrapPos();
}

void Panels::selectionPanel(AppState& app, Inspector& inspector, double viewExposure) {
    const PatchId id = app.selection().front();
    const auto rgb = formatRgb;
    if (app.selection().size() > 1) {
        // The whole selection first: count, total area, area-weighted means, the power leaving it.
        const SelectionSummary sum = app.selectionSummary();
        const std::string& unit = app.scene().unit;
        ImGui::TextWrapped("%zu patches in %zu object%s, total area %s", sum.patches, sum.objects, sum.objects == 1 ? "" : "s",
                           formatArea(sum.area, unit).c_str());
        ImGui::Text("area-weighted means:");
        ImGui::Text("  E   %s W/m^2", rgb(sum.emission).c_str());
        ImGui::Text("  rho %s   s %s", rgb(sum.rho).c_str(), formatNumber(sum.specular).c_str());
        ImGui::Text("  B   %s W/m^2", rgb(sum.radiosity).c_str());
        ImGui::TextWrapped("power leaving (sum A B) %s", formatPower(sum.power, unit).c_str());
        ImGui::Separator();
        ImGui::TextDisabled("first selected patch:");
    }
    const PatchReadout r = *app.readout(id);
    ImGui::Text("patch %u, object '%s', line %d", id, r.object.c_str(), r.sourceLine);
    ImGui::Text("area %s", formatArea(r.area, app.scene().unit).c_str());
    ImGui::Text("E   %s W/m^2", rgb(r.emission).c_str());
    ImGui::Text("rho %s   s %s", rgb(r.rho).c_str(), formatNumber(r.specular).c_str());
    ImGui::Text("B   %s W/m^2", rgb(r.B).c_str());
    ImGui::Text("H   %s W/m^2", rgb(r.H).c_str());
    if (const FormFactors* F = app.formFactors(); F && F->rowComputed(id))
        ImGui::Text("F row sum %s, %zu nonzeros", formatNumber(F->rowSum(id)).c_str(), std::size_t(F->rowEnd(id) - F->rowBegin(id)));
    else
        ImGui::TextDisabled("F row not computed (black patch, or no F yet)");
    if (ImGui::Button("Colour by F of this patch")) app.layer = Layer::FormFactorRow;
    tip("The view's F-row layer: every patch coloured by F from this patch to it (4 decades, log)");
    if (!rayCastingNotBuilt().empty()) {
        // The inspector's pictures are ray-cast; a build without Embree says so instead.
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("Inspector: ray casting (Embree) is %s", rayCastingNotBuilt().c_str());
        ImGui::PopTextWrapPos();
        return;
    }
    ImGui::SameLine();
    ImGui::Checkbox("Inspector", &m_showInspector);
    tip("What this patch sees: its Nusselt disk (hemisphere, equal areas = equal F) or its hemicube");
    if (m_showInspector) {
        try {
            inspector.update(app, id, viewExposure);
            if (inspector.texture()) {
                ImGui::PushTextWrapPos(0.0f);
                ImGui::TextDisabled("%s", inspector.caption().c_str());
                ImGui::PopTextWrapPos();
                const float scale = std::min(300.0f, ImGui::GetContentRegionAvail().x) / float(std::max(inspector.width(), 1));
                ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(inspector.texture())),
                             ImVec2(inspector.width() * scale, inspector.height() * scale));
            }
        } catch (const std::exception& e) {
            app.error(e.what());
            m_showInspector = false;
        }
    }
}

void Panels::meshingSection(AppState& app) {
    const Scene& source = app.sourceScene();
    if (m_meshSceneId != app.sceneId()) {
        // A new scene: a first suggestion of about 20 steps along its bounds' diagonal, rounded to 1-2-5.
        m_meshSceneId = app.sceneId();
        const double raw = source.extent() / 20.0;
        const double decade = std::pow(10.0, std::floor(std::log10(raw)));
        m_meshEdge = raw >= 5 * decade ? 5 * decade : raw >= 2 * decade ? 2 * decade : decade;
    }
    const auto& edges = app.meshEdges();
    if (edges != m_meshEdgesSeen) {
        // Meshed elsewhere (undo, redo, --mesh): the fields show the mesh's edge length and target.
        m_meshEdgesSeen = edges;
        const auto finest = std::max_element(edges.begin(), edges.end());
        if (finest != edges.end() && *finest > 0) {
            m_meshEdge = *finest;
            m_meshSelected = std::count(edges.begin(), edges.end(), *finest) != std::ptrdiff_t(edges.size());
        }
    }
    const std::size_t meshed = std::size_t(std::count_if(edges.begin(), edges.end(), [](double e) { return e > 0; }));
    ImGui::Text("Mesh: %zu patches", app.scene().size());
    if (meshed == 0) ImGui::TextDisabled("as loaded");
    else ImGui::TextDisabled("%s (%zu patches as loaded)", meshedCounts(source, edges).c_str(), source.size());
    const std::string edgeLabel = "Max edge (" + lengthUnitLabel(app.scene().unit) + ")###maxedge";
    ImGui::InputDouble(edgeLabel.c_str(), &m_meshEdge, 0.0, 0.0, "%.6g");
    tip("Longest patch edge after meshing, in the scene's unit (like --subdivide): quads become grids,\n"
        "triangles n x n triangles, always from the patches as loaded. 0: back to those.");
    int target = m_meshSelected ? 1 : 0;
    ImGui::RadioButton("whole scene", &target, 0);
    tip("Mesh every object to this edge length");
    ImGui::SameLine();
    ImGui::RadioButton("selected objects", &target, 1);
    tip("The objects of the selection (pick one patch of each); the rest keep their mesh");
    m_meshSelected = target == 1;
    const MeshTarget meshTarget = m_meshSelected ? MeshTarget::SelectedObjects : MeshTarget::Scene;
    const MeshingPreview preview = app.meshingPreview(m_meshEdge, meshTarget);
    ImGui::PushTextWrapPos(0.0f);
    if (!preview.error.empty()) {
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", preview.error.c_str());
    } else if (preview.objects == 0) {
        ImGui::TextDisabled("the mesh already has these edges (%zu patches)", preview.patches);
    } else {
        ImGui::BeginDisabled(app.job().running);
        if (ImGui::Button("Apply")) app.mesh(m_meshEdge, meshTarget);
        ImGui::EndDisabled();
        tip("Mesh now (undoable, Ctrl+Z); materials and edits are kept, F must be recomputed");
        ImGui::SameLine();
        ImGui::TextDisabled("-> %zu patches (now %zu)", preview.patches, app.scene().size());
    }
    ImGui::PopTextWrapPos();
    ImGui::Separator();
}

void Panels::pipelinePanel(AppState& app) {
    if (app.hasScene()) meshingSection(app);
    PipelineSettings& st = app.settings;
    // The fields fill the panel's width up to their labels.
    ImGui::PushItemWidth(-ImGui::CalcTextSize("log10 tolerance").x - ImGui::GetStyle().ItemInnerSpacing.x);
    // The back ends and their options come from the registry: a widget per option kind.
    const auto& backends = formFactorBackends();
    const bool methodOpen = ImGui::BeginCombo("Method", st.formFactors.method.c_str());
    tip("--method: the form-factor back end (hemisphere: Embree rays or exact factors; hemicube: OpenGL)");
    if (methodOpen) {
        for (const BackendDescriptor* d : backends)
            if (d->notBuilt.empty() && ImGui::Selectable(d->name.c_str(), d->name == st.formFactors.method) &&
                d->name != st.formFactors.method) {
                const CommonOptions common = st.formFactors.common;
                st.formFactors = defaultSettings(d->name);
                st.formFactors.common = common;
            }
        ImGui::EndCombo();
    }
    const BackendDescriptor& backend = findBackend(st.formFactors.method);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("%s", backend.summary.c_str());
    ImGui::PopTextWrapPos();
    for (const BackendOption& option : backend.options) {
        const std::string current = option.get(st.formFactors);
        try {
            if (option.kind == OptionKind::Switch) {
                bool on = current == "yes";
                if (ImGui::Checkbox(option.label.c_str(), &on)) option.set(st.formFactors, on ? "yes" : "no");
            } else if (option.kind == OptionKind::Choice) {
                if (ImGui::BeginCombo(option.label.c_str(), current.c_str())) {
                    for (const std::string& choice : option.choices)
                        if (ImGui::Selectable(choice.c_str(), choice == current)) option.set(st.formFactors, choice);
                    ImGui::EndCombo();
                }
            } else {
                long long v = std::stoll(current);
                const long long step = option.even ? 2 : 1, fast = 16 * step;
                if (ImGui::InputScalar(option.label.c_str(), ImGuiDataType_S64, &v, &step, &fast)) {
                    long long clamped = std::clamp<long long>(v, option.min, option.max);
                    if (option.even) clamped = clamped / 2 * 2;
                    option.set(st.formFactors, std::to_string(clamped));
                }
            }
        } catch (const std::exception& e) {
            app.error(e.what());
        }
        // An option this run does not use says so (e.g. directions the analytic estimator never casts).
        const std::string unused = option.unusedBecause && app.hasScene() ? option.unusedBecause(app.scene(), st.formFactors) : "";
        tip((option.flag + ": " + option.help + (unused.empty() ? "" : "\n" + unused)).c_str());
        if (!unused.empty()) {
            ImGui::PushTextWrapPos(0.0f);
            ImGui::TextDisabled("%s", unused.c_str());
            ImGui::PopTextWrapPos();
        }
    }
    int depth = int(st.formFactors.common.maxDepth);
    if (ImGui::InputInt("Mirror depth", &depth)) st.formFactors.common.maxDepth = std::uint32_t(std::clamp(depth, 0, 254));
    tip("--max-depth: mirror reflections followed by F, and shown by the view (0 to 254)");
    int threads = st.formFactors.common.threads;
    if (ImGui::InputInt("Threads", &threads)) st.formFactors.common.threads = std::clamp(threads, 0, 4096);
    tip("--threads: worker threads (GL contexts for the hemicube); 0 = all cores");
    if (app.hasScene()) {
        // What Run will do, before it is pressed: the back end's description (what auto picks),
        // rows and work, the memory bound, and the time at the last run's rate.
        const FormFactorEstimate e = app.formFactorEstimate();
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("%s", e.description.c_str());
        ImGui::TextDisabled("%s", runEstimateText(e).c_str());
        ImGui::PopTextWrapPos();
    }
    const bool solverOpen = ImGui::BeginCombo("Solver", st.solver.solver.c_str());
    tip("--solver: per RGB channel; auto picks a direct factorisation for small scenes, else an iteration");
    if (solverOpen) {
        if (ImGui::Selectable("auto", st.solver.solver == "auto")) st.solver.solver = "auto";
        tip("The solver hemirad picks for the scene's size and F");
        for (const SolverDescriptor* d : solverRegistry()) {
            if (ImGui::Selectable(d->name.c_str(), st.solver.solver == d->name)) st.solver.solver = d->name;
            tip(d->summary.c_str());
        }
        ImGui::EndCombo();
    }
    // A factorisation does not iterate: its tolerance control is shown disabled.
    const bool iterates = st.solver.solver == "auto" || !findSolver(st.solver.solver).flags.empty();
    ImGui::BeginDisabled(!iterates);
    float exponent = float(std::log10(st.solver.tolerance));
    if (ImGui::SliderFloat("log10 tolerance", &exponent, -12.0f, -2.0f, "%.0f")) st.solver.tolerance = std::pow(10.0, double(exponent));
    ImGui::EndDisabled();
    tip(iterates ? "--tolerance: an iterative solver stops when the relative residual is below 10^this"
                 : "A factorisation solves exactly: no tolerance");
    ImGui::Checkbox("Re-solve after edits", &app.autoResolve);
    tip("Emission and diffuse edits solve again at once with the current F (warm start)");
    ImGui::PopItemWidth();

    // The buttons keep their places whether a job runs or not, Cancel on its own row: a click meant
    // for Cancel that lands after the job ended finds Cancel disabled, never Run (issue 38 #4).
    const JobStatus job = app.job();
    ImGui::BeginDisabled(job.running);
    if (ImGui::Button("Run", ImVec2(100, 0))) app.runPipeline();
    tip("Compute F where it is missing, stale or made with other settings, then solve");
    ImGui::SameLine();
    if (ImGui::Button("Re-solve", ImVec2(100, 0))) app.resolve();
    tip("Solve again with the current F (after edits or a solver change)");
    ImGui::SameLine();
    if (ImGui::Button("Recompute F")) app.recomputeFormFactors();
    tip("Compute the whole F again with the settings above, even when it is current, then solve");
    ImGui::EndDisabled();
    ImGui::ProgressBar(job.running ? float(job.progress) : 0.0f, ImVec2(-108.0f, 0),
                       job.running ? job.stage.c_str() : "no job running");
    ImGui::SameLine();
    ImGui::BeginDisabled(!job.running || job.cancelling);
    if (ImGui::Button(job.cancelling ? "cancelling###cancel" : "Cancel###cancel", ImVec2(100, 0))) app.cancel();
    ImGui::EndDisabled();
    const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    m_itemRects["PipelineCancel"] = {lo.x, lo.y, hi.x - lo.x, hi.y - lo.y};  // for scripted clicks
    tip("Stop the running job (between rows, or solver sweeps); the scene and the last results stay");
    if (app.formFactors() && !app.formFactorsStale() && !app.formFactorsMatchSettings()) {
        // Wrapped: a line wider than the panel was clipped (issue 38 #15).
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.6f, 0.2f, 1));
        ImGui::TextWrapped("F was made with other settings: Run computes it again");
        ImGui::PopStyleColor();
    }
    ImGui::Separator();
    if (!app.formFactors()) {
        ImGui::TextDisabled("no form factors yet");
    } else {
        const FormFactors& F = *app.formFactors();
        ImGui::Text("F: %zu of %zu rows, %zu nonzeros, %.1f MiB%s", F.computedRows(), F.size(), F.nonZeros(),
                    F.memoryBytes() / 1048576.0, app.formFactorsStale() ? "  STALE" : "");
        if (const auto& stats = app.formFactorStats()) {
            ImGui::TextWrapped("row sums %.4f / %.4f / %.4f (min/mean/max)", stats->rowSumMin, stats->rowSumMean, stats->rowSumMax);
            ImGui::TextWrapped("reciprocity: mean %.4f, max %.4f", stats->reciprocityMean, stats->reciprocityMax);
            // What a row sum of 0 or a reciprocity max near 1 means, as the CLI says it.
            ImGui::PushTextWrapPos(0.0f);
            for (const std::string& note : formFactorStatsNotes(*stats)) ImGui::TextDisabled("%s", note.c_str());
            ImGui::PopTextWrapPos();
        }
    }
    for (const auto& [stage, seconds] : app.timings()) ImGui::Text("%-26s %8.3f s", stage.c_str(), seconds);
    for (const SolveReport& r : app.solveReports())
        ImGui::Text("%s (%s): %s, %d it, residual %.2e", r.solver.c_str(), r.channels.c_str(),
                    r.converged ? "converged" : "NOT converged", r.iterations, r.residual);
    // The content never shrinks: ImGui pulls a panel scrolled to its end down by what went (fewer
    // timing lines after a run), which moved Run under a pointer aimed at Cancel (issue 38 #4).
    const float end = ImGui::GetCursorPosY();
    if (end < m_pipelineEnd) ImGui::Dummy(ImVec2(1.0f, m_pipelineEnd - end));
    m_pipelineEnd = std::max(m_pipelineEnd, end);
}

void Panels::objectsPanel(AppState& app) {
    // Per object: B and H as luminance Y (W/m^2), area-weighted means and extremes (File > Export
    // object table writes the same as CSV). The table as drawn is kept for scripted runs to print.
    ImGui::TextDisabled("B, H: luminance Y in W/m^2; mean = area-weighted; H = (B - E)/rho");
    const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY | ImGuiTableFlags_Resizable;
    const std::string area = "area (" + lengthUnitLabel(app.scene().unit) + "^2)";
    const std::vector<std::string> headings = {"object", "patches", area, "B mean", "B min", "B max", "H mean", "H min", "H max"};
    m_objectTable.clear();
    if (!ImGui::BeginTable("objects", int(headings.size()), flags)) return;
    ImGui::TableSetupScrollFreeze(0, 1);
    for (const std::string& h : headings) ImGui::TableSetupColumn(h.c_str());
    ImGui::TableHeadersRow();
    m_objectTable.push_back(headings);
    for (const ObjectSummary& o : app.objectTable()) {
        std::vector<std::string> row = {o.name, std::to_string(o.patches)};
        for (double v : {o.area, o.bMean, o.bMin, o.bMax, o.hMean, o.hMin, o.hMax})
            row.push_back(std::isnan(v) ? "no data" : formatNumber(v));
        ImGui::TableNextRow();
        for (std::size_t k = 0; k < row.size(); ++k) {
            ImGui::TableNextColumn();
            if (k >= 2 && row[k] == "no data") ImGui::TextDisabled("no data");
            else ImGui::TextUnformatted(row[k].c_str());
        }
        m_objectTable.push_back(std::move(row));
    }
    ImGui::EndTable();
}

void Panels::helpPanel() {
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
        for (const auto& [keys, action] : kMouseAndKeys) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(keys);
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(action);
        }
        ImGui::EndTable();
    }
    ImGui::Separator();
    ImGui::PushTextWrapPos(540.0f);
    ImGui::TextUnformatted("A session: File > Open OBJ; mesh it finer in the Pipeline panel (Max edge, Apply); choose the "
                           "method and press Run (F, then the solve); look at the result in View > False colour with its "
                           "legend, hover patches for their values, View > Object table for means per object; edit "
                           "materials of a selection (the solve follows); File > Save, Export.");
    ImGui::TextDisabled("Radiosity B, irradiance H and emission E are in W/m^2; rho and s are fractions; lengths and "
                        "areas are in scene units (Scene panel: Unit).");
    ImGui::TextDisabled("Every control explains itself in a tooltip. The same computations from the command line: "
                        "hemirad help.");
    ImGui::PopTextWrapPos();
}

void Panels::logPanel(AppState& app) {
    for (const LogEntry& e : app.log()) {
        // Errors wrap like every other line, in red.
        if (e.error) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.4f, 1.0f));
        ImGui::TextWrapped("[%8.2f] %s", e.seconds, e.text.c_str());
        if (e.error) ImGui::PopStyleColor();
    }
    if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY() - 20) ImGui::SetScrollHereY(1.0f);
}

void Panels::modals(AppState& app, OrbitCamera& camera, LoopRequests& requests) {
    if (m_openPathPrompt) {
        ImGui::OpenPopup("Files");
        m_openPathPrompt = false;
        m_focusPath = true;
    }
    ImGui::SetNextWindowSize(ImVec2(620, 0), ImGuiCond_Appearing);
    if (ImGui::BeginPopupModal("Files", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        std::optional<std::string> chosen;
        const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
        m_panelRects["Files"] = {pos.x, pos.y, size.x, size.y};
        ImGui::Text("%s", m_browser.purpose().c_str());
        ImGui::SameLine();
        std::string filter;
        for (const std::string& e : m_browser.extensions()) filter += (filter.empty() ? "*" : ", *") + e;
        ImGui::TextDisabled("(%s)", filter.empty() ? "all files" : filter.c_str());
        ImGui::TextWrapped("in %s", m_browser.directory().c_str());
        const std::vector<std::string> folders = FileBrowser::recentFolders(m_recent);
        const bool foldersOpen = !folders.empty() && ImGui::BeginCombo("Recent folders", folders.front().c_str());
        if (!folders.empty()) tip("The folders of the recent files");
        if (foldersOpen) {
            for (const std::string& folder : folders)
                if (ImGui::Selectable(folder.c_str())) m_browser.changeDirectory(folder);
            ImGui::EndCombo();
        }
        ImGui::BeginChild("listing", ImVec2(600, 260), true);
        std::optional<FileBrowser::Entry> picked;
        bool doubleClicked = false;
        for (const FileBrowser::Entry& e : m_browser.entries()) {
            const std::string label = e.directory ? e.name + "/" : e.name;
            if (ImGui::Selectable(label.c_str(), !e.directory && e.name == m_pathBuffer, ImGuiSelectableFlags_AllowDoubleClick)) {
                picked = e;
                doubleClicked = ImGui::IsMouseDoubleClicked(0);
            }
            // The first rows' places, for scripted clicks.
            if (const std::size_t row = std::size_t(&e - m_browser.entries().data()); row < 3) {
                const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
                m_itemRects["FilesRow" + std::to_string(row)] = {lo.x, lo.y, hi.x - lo.x, hi.y - lo.y};
            }
            if (!e.directory) {
                ImGui::SameLine(480);
                ImGui::TextDisabled("%s", formatBytes(e.size).c_str());
            }
        }
        ImGui::EndChild();
        if (picked) {
            // A double-click on a folder enters it once (issue 38 #1): click() ignores its second click.
            chosen = m_browser.click(*picked, doubleClicked);
            std::snprintf(m_pathBuffer, sizeof m_pathBuffer, "%s", m_browser.typed.c_str());
            m_focusPath = true;
        }
        if (!m_browser.error().empty()) {
            ImGui::PushTextWrapPos(600);
            ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", m_browser.error().c_str());
            ImGui::PopTextWrapPos();
        }
        // Typed paths (absolute, or relative to the folder shown); Enter confirms, a folder is entered.
        if (m_focusPath) {
            ImGui::SetKeyboardFocusHere();
            m_focusPath = false;
        }
        ImGui::SetNextItemWidth(600);
        const bool enter = ImGui::InputText("##path", m_pathBuffer, sizeof m_pathBuffer,
                                            ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
        tip("A file name or path (absolute, or relative to the folder shown); Enter confirms, a folder is entered");
        const bool ok = ImGui::Button("OK", ImVec2(100, 0));
        tip("Use the file typed (Enter does the same)");
        if (ok || enter) {
            chosen = m_browser.confirm(m_pathBuffer);
            if (!chosen) {
                std::snprintf(m_pathBuffer, sizeof m_pathBuffer, "%s", m_browser.typed.c_str());
                m_focusPath = true;
            }
        }
        ImGui::SameLine();
        const bool cancel = ImGui::Button("Cancel", ImVec2(100, 0));
        tip("Close the browser (Esc)");
        if (cancel || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) ImGui::CloseCurrentPopup();
        if (chosen) {
            ImGui::CloseCurrentPopup();
            const std::string& path = *chosen;
            const std::string& purpose = m_browser.purpose();
            if (purpose == "Open OBJ") open(app, camera, path);
            else if (purpose == "Save scene") {
                if (app.saveScene(path)) remember(path);
            } else if (purpose == "Import F") app.importFormFactors(path);
            else if (purpose == "Export F") app.exportFormFactors(path);
            else if (purpose == "Export PNG") requests.exportImage = path;
            else if (purpose == "Export PLY") app.exportPly(path);
            else if (purpose == "Export object table") app.exportObjectTable(path);
            else if (purpose == "Thermal properties") app.loadThermalProperties(path);
            else if (purpose == "Boundary conditions") app.loadThermalConditions(path);
            else if (purpose == "Export exchange table") app.exportThermalExchange(path);
            else if (purpose == "Export conductors") app.exportThermalConductors(path);
        }
        ImGui::EndPopup();
    }
    if (m_openConfirm) {
        ImGui::OpenPopup("Unsaved edits");
        m_openConfirm = false;
    }
    if (ImGui::BeginPopupModal("Unsaved edits", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("The scene has unsaved edits. Save or discard them and %s?", m_confirmWhat.c_str());
        const bool canSave = isObjPath(app.scenePath());
        ImGui::BeginDisabled(!canSave);
        if (ImGui::Button("Save", ImVec2(120, 0)) && app.saveScene(app.scenePath())) {
            ImGui::CloseCurrentPopup();
            auto action = std::move(m_confirmAction);
            m_confirmAction = nullptr;
            if (action) action();
        }
        ImGui::EndDisabled();
        tip(canSave ? "Save the scene over its .obj and .mtl, then go on"
                    : "The scene has no .obj file to save to: use File > Save scene as");
        ImGui::SameLine();
        const bool discard = ImGui::Button("Discard", ImVec2(120, 0));
        tip("Drop the edits and go on");
        if (discard) {
            ImGui::CloseCurrentPopup();
            auto action = std::move(m_confirmAction);
            m_confirmAction = nullptr;
            if (action) action();
        }
        ImGui::SameLine();
        const bool keep = ImGui::Button("Keep editing", ImVec2(120, 0));
        tip("Go back to the scene; nothing happens");
        if (keep) {
            m_confirmAction = nullptr;
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
}

}  // namespace hemirad::ui
