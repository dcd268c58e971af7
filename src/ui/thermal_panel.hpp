// hemirad-gui's thermal controls: the Scene panel's section (the properties and boundary-condition
// files, the environment, each object's emissivity and condition, Run thermal and its report) and
// the object exchange table's window. They present AppState and call its actions, nothing else.
#pragma once

#include "ui/app_state.hpp"
#include "ui/thermal_fields.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hemirad::ui {

class ThermalPanel {
public:
    /// Opens the file browser for a purpose ("Thermal properties", "Boundary conditions", "Export
    /// exchange table") at an initial path.
    using Browse = std::function<void(const std::string& purpose, const std::string& initial)>;

    /// The Scene panel's Thermal section.
    void section(AppState& app, const Browse& browse);
    /// The exchange table's window, when `showExchange`.
    void exchangeWindow(AppState& app, const Browse& browse, float width, float height);
    bool showExchange = false;

    /// The result lines the section drew in the last frame (balance, each isothermal node's T) and
    /// the exchange table as drawn (headings, then a row per object): scripted runs print them.
    const std::vector<std::string>& resultLines() const { return m_resultLines; }
    const std::vector<std::vector<std::string>>& exchangeTable() const { return m_exchangeTable; }
    /// Where the exchange window was in the last frame (x, y, width, height; none when not drawn).
    const std::optional<std::array<float, 4>>& exchangeRect() const { return m_exchangeRect; }

private:
    /// The path fields follow the files loaded.
    void syncPaths(const AppState& app);
    void fileRow(AppState& app, const Browse& browse, bool properties);
    void objectTable(AppState& app);
    void results(AppState& app);

    ThermalFields m_fields;
    bool m_openedForFiles = false;  ///< the section was opened for the thermal files loaded
    char m_propertiesPath[1024] = {}, m_conditionsPath[1024] = {};
    std::string m_propertiesSeen, m_conditionsSeen;  ///< the setup's paths the fields were set from
    std::vector<std::string> m_resultLines;
    std::vector<std::vector<std::string>> m_exchangeTable;
    std::optional<std::array<float, 4>> m_exchangeRect;
};

}  // namespace hemirad::ui
