// The Scene panel's thermal fields: the values they show (per object emissivity, condition and its
// value, the environment, temperatures in K or C) and when they are loaded from AppState, so that a
// value AppState refused never stays in a field. No ImGui: the tests drive it headless.
#pragma once

#include "ui/app_state.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hemirad::ui {

class ThermalFields {
public:
    /// One object's fields; `value` as shown: K or C for a temperature, W/m^2, W.
    struct Row {
        ObjectThermalRow object;
        double emissivity = 0.0;
        ObjectCondition::Kind kind = ObjectCondition::Kind::Adiabatic;
        double value = 0.0;
    };

    /// Loads the fields after every thermal load or edit (accepted or refused), material edit, new
    /// scene or mesh, and when `celsius` changed; else leaves them as typed.
    void sync(const AppState& app);
    /// Applies row k's typed emissivity, condition kind (with a start value: 293.15 K, 0 W/m^2, 0 W)
    /// or value, or the environment; the fields are loaded again at once, so a refused value is
    /// replaced by the one in effect. Return whether AppState accepted it.
    bool applyEmissivity(AppState& app, std::size_t k);
    bool applyKind(AppState& app, std::size_t k);
    bool applyValue(AppState& app, std::size_t k);
    bool applyEnvironment(AppState& app);

    std::vector<Row> rows;
    std::string error;         ///< why there are no rows (a file that no longer fits the scene)
    bool closed = true;        ///< no environment: a closed scene
    double environment = 3.0;  ///< as shown: K or C
    bool celsius = false;      ///< temperatures shown and typed in degrees Celsius

private:
    /// K for a temperature typed in the shown unit.
    double kelvin(double shown) const;
    void reload(const AppState& app);
    std::uint64_t m_thermalRevision = ~std::uint64_t(0), m_materialsRevision = 0, m_sceneId = 0;
    std::size_t m_patches = 0;
    bool m_shownCelsius = false;
};

}  // namespace hemirad::ui
