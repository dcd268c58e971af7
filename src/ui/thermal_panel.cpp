// hemirad-gui's thermal section and exchange table (ImGui).
#include "ui/thermal_panel.hpp"

#include "thermal/thermal_model.hpp"
#include "ui/units.hpp"

#include <imgui.h>

#include <cstdio>
#include <filesystem>
#include <sstream>

namespace hemirad::ui {
namespace {

void tip(const char* text) {
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("%s", text);
}

/// Six significant digits, as hemirad thermal reports.
std::string figure(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

const char* kKinds[] = {"temperature", "flux", "power (isothermal)", "adiabatic"};

}  // namespace

void ThermalPanel::syncPaths(const AppState& app) {
    // The path fields follow the files loaded (a typed path stays until another file is loaded).
    const ThermalSetup& setup = app.thermalSetup();
    if (setup.propertiesPath != m_propertiesSeen) {
        m_propertiesSeen = setup.propertiesPath;
        std::snprintf(m_propertiesPath, sizeof m_propertiesPath, "%s", setup.propertiesPath.c_str());
    }
    if (setup.conditionsPath != m_conditionsSeen) {
        m_conditionsSeen = setup.conditionsPath;
        std::snprintf(m_conditionsPath, sizeof m_conditionsPath, "%s", setup.conditionsPath.c_str());
    }
}

void ThermalPanel::fileRow(AppState& app, const Browse& browse, bool properties) {
    char* buffer = properties ? m_propertiesPath : m_conditionsPath;
    const char* purpose = properties ? "Thermal properties" : "Boundary conditions";
    ImGui::PushID(purpose);
    ImGui::SetNextItemWidth(-ImGui::CalcTextSize("Conditions  Load  ...").x - 3 * ImGui::GetStyle().ItemSpacing.x);
    const bool enter = ImGui::InputText(properties ? "Properties" : "Conditions", buffer, 1024, ImGuiInputTextFlags_EnterReturnsTrue);
    tip(properties ? "Properties TOML (docs/thermal.md): emissivity, specular, solar absorptance by material or object.\n"
                     "Enter or Load reads it; its specular reflectances become the scene's (F is recomputed)"
                   : "Boundary-condition TOML (docs/thermal.md): per object a temperature (K or C), flux (W/m^2),\n"
                     "power (W, isothermal) or adiabatic, and the [environment]. Enter or Load reads it");
    ImGui::SameLine();
    const bool load = ImGui::Button("Load");
    tip("Read the file typed; an error names its file and line and changes nothing");
    if ((enter || load) && buffer[0]) properties ? app.loadThermalProperties(buffer) : app.loadThermalConditions(buffer);
    ImGui::SameLine();
    const std::string folder = std::filesystem::path(app.scenePath()).parent_path().string() + "/";
    if (ImGui::Button("...")) browse(purpose, buffer[0] ? std::string(buffer) : folder);
    tip("Choose the file in the file browser");
    ImGui::PopID();
}

void ThermalPanel::section(AppState& app, const Browse& browse) {
    m_resultLines.clear();
    if (!app.hasScene()) return;
    // The section opens by itself the first time thermal files are loaded (the panel, --properties, --bc).
    const bool files = !app.thermalSetup().propertiesPath.empty() || !app.thermalSetup().conditionsPath.empty();
    if (files && !m_openedForFiles) ImGui::SetNextItemOpen(true);
    m_openedForFiles = files;
    const bool open = ImGui::CollapsingHeader("Thermal");
    tip("Radiative heat transfer on F (hemirad thermal): properties and conditions per object, T and q");
    if (!open) return;
    m_fields.sync(app);
    syncPaths(app);
    fileRow(app, browse, true);
    fileRow(app, browse, false);
    if (!app.thermalLoadError().empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", app.thermalLoadError().c_str());
        ImGui::PopTextWrapPos();
    }
    const char* unit = m_fields.celsius ? "C" : "K";
    bool environment = !m_fields.closed;
    if (ImGui::Checkbox("Environment", &environment)) {
        m_fields.closed = !environment;
        m_fields.applyEnvironment(app);
    }
    tip("The deep-space, sky or ambient temperature that takes what leaves an open scene; off: a closed scene");
    if (!m_fields.closed) {
        ImGui::SameLine();
        ImGui::SetNextItemWidth(90);
        ImGui::InputDouble(unit, &m_fields.environment, 0.0, 0.0, "%.6g");
        if (ImGui::IsItemDeactivatedAfterEdit()) m_fields.applyEnvironment(app);
        tip("The environment's temperature; below 0 K is refused");
    }
    ImGui::SameLine();
    ImGui::Checkbox("in C", &m_fields.celsius);
    tip("Show and type temperatures in degrees Celsius instead of kelvin");
    objectTable(app);
    const bool running = app.job().running;
    ImGui::BeginDisabled(running);
    if (ImGui::Button("Run thermal")) app.runThermal();
    ImGui::EndDisabled();
    tip("Solve T and q on the current F (every row computed first where some are missing), off the GUI thread");
    ImGui::SameLine();
    ImGui::BeginDisabled(!running);
    if (ImGui::Button("Cancel##thermal")) app.cancel();
    ImGui::EndDisabled();
    tip("Stop the running computation");
    ImGui::SameLine();
    ImGui::BeginDisabled(!app.thermalResult());
    if (ImGui::Button("Exchange table")) showExchange = true;
    ImGui::EndDisabled();
    tip("Net power between objects and to the environment (W), exportable as CSV");
    results(app);
}

void ThermalPanel::objectTable(AppState& app) {
    if (!m_fields.error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", m_fields.error.c_str());
        ImGui::PopTextWrapPos();
        return;
    }
    const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp;
    if (!ImGui::BeginTable("thermal objects", 5, flags)) return;
    static const std::pair<const char*, const char*> kHeadings[] = {
        {"object", "The OBJ object (o/g name) the files and edits address"},
        {"eps", "IR emissivity (= absorptance), 0..1"},
        {"s", "Specular (mirror) reflectance: F is made with it (read-only here)"},
        {"condition", "Boundary condition: temperature, flux, power of an isothermal node or adiabatic"},
        {"value", "The condition's value, with its unit: K or C, W/m^2 (net leaving), W"}};
    for (const auto& h : kHeadings) ImGui::TableSetupColumn(h.first);
    // The header row by hand: each heading explains its column.
    ImGui::TableNextRow(ImGuiTableRowFlags_Headers);
    for (int c = 0; c < 5; ++c) {
        ImGui::TableSetColumnIndex(c);
        ImGui::TableHeader(kHeadings[c].first);
        tip(kHeadings[c].second);
    }
    // An apply reloads the rows (this frame's references go): the row's widgets are drawn first, the
    // apply comes after them and ends this frame's table.
    enum class Apply { None, Emissivity, Kind, Value };
    for (std::size_t k = 0; k < m_fields.rows.size(); ++k) {
        ThermalFields::Row& f = m_fields.rows[k];
        const ObjectThermalRow& r = f.object;
        Apply apply = Apply::None;
        ImGui::PushID(int(k));
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(r.name.c_str());
        if (r.solar > 0) tip(("solar irradiance " + figure(r.solar) + " W/m^2 from the boundary-condition file").c_str());
        ImGui::TableNextColumn();
        ImGui::SetNextItemWidth(-1);
        ImGui::InputDouble("##eps", &f.emissivity, 0.0, 0.0, "%.4g");
        if (ImGui::IsItemDeactivatedAfterEdit()) apply = Apply::Emissivity;
        if (!r.emissivityCurve.empty())
            tip(("IR emissivity against temperature: " + r.emissivityCurve +
                 ".\nThe solve follows the curve; typing a value replaces it with that constant. eps + s <= 1")
                    .c_str());
        else
            tip(r.emissivityEdited ? "IR emissivity (edited here; area-weighted mean shown); eps + s <= 1"
                                   : "IR emissivity from the properties file (or 1 - mean(Kd) - s); eps + s <= 1");
        ImGui::TableNextColumn();
        ImGui::Text("%.4g", r.specular);
        tip("Specular reflectance s: F is made with it, so it is read-only here; change it in the Material\n"
            "editor (then Run thermal computes F again)");
        ImGui::TableNextColumn();
        ImGui::SetNextItemWidth(-1);
        int kind = int(f.kind);
        if (ImGui::Combo("##kind", &kind, kKinds, 4)) {
            f.kind = ObjectCondition::Kind(kind);
            apply = Apply::Kind;
        }
        tip("The object's boundary condition: temperature, net heat flux leaving (W/m^2), net power of an\n"
            "isothermal node (W, 0: a thin shield) or adiabatic (reradiating)");
        ImGui::TableNextColumn();
        if (!r.condition) {
            ImGui::TextDisabled("none");
        } else if (f.kind != ObjectCondition::Kind::Adiabatic) {
            // The unit follows the number in the field (ImGui reads the number back and drops it).
            const char* format = f.kind == ObjectCondition::Kind::Temperature ? (m_fields.celsius ? "%.6g C" : "%.6g K")
                                 : f.kind == ObjectCondition::Kind::Flux      ? "%.6g W/m^2"
                                                                              : "%.6g W";
            ImGui::SetNextItemWidth(-1);
            ImGui::InputDouble("##value", &f.value, 0.0, 0.0, format);
            if (ImGui::IsItemDeactivatedAfterEdit()) apply = Apply::Value;
            tip("The condition's value; one the library refuses (below 0 K, ...) is put back");
        }
        ImGui::PopID();
        if (apply == Apply::None) continue;
        if (apply == Apply::Emissivity) m_fields.applyEmissivity(app, k);
        else if (apply == Apply::Kind) m_fields.applyKind(app, k);
        else m_fields.applyValue(app, k);
        break;
    }
    ImGui::EndTable();
}

void ThermalPanel::results(AppState& app) {
    const ThermalResult* r = app.thermalResult();
    if (!r) {
        ImGui::TextDisabled("no thermal result yet");
        return;
    }
    const thermal::ThermalSolution& s = r->solution;
    m_resultLines.push_back("energy balance " + figure(s.balance) + " (|sum Q + Q_env| / max |Q|); environment gives " +
                            figure(s.environmentPower) + " W");
    if (r->solar)
        m_resultLines.push_back("solar band: " + figure(r->solar->absorbedPower) + " W absorbed of " +
                                figure(r->solar->incidentPower) + " W");
    for (std::size_t k = 0; k < r->model.isothermal.size(); ++k)
        m_resultLines.push_back("isothermal '" + r->model.isothermal[k].name + "': T = " + figure(s.isothermalT[k]) + " K (" +
                                figure(s.isothermalT[k] - thermal::kCelsiusZero) + " C)");
    ImGui::PushTextWrapPos(0.0f);
    for (const std::string& line : m_resultLines) ImGui::TextUnformatted(line.c_str());
    if (app.thermalStale()) ImGui::TextColored(ImVec4(1, 0.9f, 0.3f, 1), "out of date: the inputs changed since; Run thermal");
    ImGui::TextDisabled("View > False colour: temperature T, net heat flux q");
    ImGui::PopTextWrapPos();
}

void ThermalPanel::exchangeWindow(AppState& app, const Browse& browse, float width, float height) {
    m_exchangeTable.clear();
    m_exchangeRect.reset();
    const ThermalResult* r = app.thermalResult();
    if (!showExchange || !r) return;
    ImGui::SetNextWindowSize(ImVec2(560, 220), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowPos(ImVec2(width * 0.5f - 280, height * 0.55f), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Thermal exchange", &showExchange)) {
        const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
        m_exchangeRect = std::array<float, 4>{pos.x, pos.y, size.x, size.y};
        ImGui::TextDisabled("net IR power from row to column, W; a row sums to the object's net IR leaving (its Q plus the\n"
                            "sunlight it absorbs)");
        const std::string stem = std::filesystem::path(app.scenePath()).replace_extension().string();
        if (ImGui::Button("Export CSV...")) browse("Export exchange table", stem + "_exchange.csv");
        tip("Write the table as CSV, units in the header (as hemirad thermal --exchange)");
        ImGui::SameLine();
        if (ImGui::Button("Export conductors...")) browse("Export conductors", stem + "_GR.esatan");
        tip("Write the conductors GR (m^2) for a thermal network: .esatan, .sinda, .csv or .mtx");
        std::vector<std::string> headings = {"Q from \\ to (W)"};
        for (const std::string& o : r->objects) headings.push_back(o);
        headings.push_back("environment");
        headings.push_back("total");
        m_exchangeTable.push_back(headings);
        const ImGuiTableFlags flags =
            ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollX | ImGuiTableFlags_ScrollY;
        if (ImGui::BeginTable("exchange", int(headings.size()), flags)) {
            ImGui::TableSetupScrollFreeze(1, 1);
            for (const std::string& h : headings) ImGui::TableSetupColumn(h.c_str());
            ImGui::TableHeadersRow();
            for (std::size_t I = 0; I < r->objects.size(); ++I) {
                std::vector<std::string> row = {r->objects[I]};
                double total = 0.0;
                for (const double q : r->exchange[I]) {
                    row.push_back(formatNumber(q));
                    total += q;
                }
                row.push_back(formatNumber(total));
                ImGui::TableNextRow();
                for (const std::string& cell : row) {
                    ImGui::TableNextColumn();
                    ImGui::TextUnformatted(cell.c_str());
                }
                m_exchangeTable.push_back(std::move(row));
            }
            ImGui::EndTable();
        }
    }
    ImGui::End();
}

}  // namespace hemirad::ui
