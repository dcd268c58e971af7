// hemirad-gui's thermal inputs: the properties and boundary-condition files as loaded (their text)
// and the per-object edits made in the Scene panel over them, turned into the library's
// ThermalModel and solar band for the current scene (src/thermal does the reading and checking).
#pragma once

#include "engine/scene.hpp"
#include "thermal/gebhart.hpp"
#include "thermal/solar_band.hpp"
#include "thermal/thermal_model.hpp"
#include "thermal/thermal_solver.hpp"

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hemirad::ui {

/// An object's boundary condition as the panel edits it. Temperatures are kept in K (the panel shows
/// K or C); a power makes the object an isothermal node (0 W: a thin shield).
struct ObjectCondition {
    enum class Kind : std::uint8_t { Temperature, Flux, Power, Adiabatic };
    Kind kind = Kind::Adiabatic;
    double value = 0.0;  ///< K, W/m^2 or W; unused for Adiabatic
    bool operator==(const ObjectCondition& o) const { return kind == o.kind && value == o.value; }
};

/// "temperature", "flux", "power", "adiabatic".
const char* conditionKindName(ObjectCondition::Kind kind);

/// What the user gave: the files (path and text; "" = none) and the edits over them.
struct ThermalSetup {
    std::string propertiesPath, propertiesText;
    std::string conditionsPath, conditionsText;
    std::map<std::uint32_t, double> emissivity;          ///< per object index: overrides the files
    std::map<std::uint32_t, ObjectCondition> condition;  ///< per object index: overrides the BC file
    /// Overrides the BC file's [environment]: a temperature (K), or none for a closed scene.
    std::optional<std::optional<double>> environment;
};

/// The library's inputs for one solve: the IR model and the solar band (inactive without solar_W_m2).
struct ThermalInputs {
    thermal::ThermalModel model;
    thermal::SolarBand solar;
};

/// Metres per scene unit: the scene's stated unit, else 1 (lengths taken as metres).
double thermalMetresPerUnit(const Scene& scene);

/// The model for `scene`: the properties file (or the MTL) per patch with the scene's own specular
/// reflectances (the Material editor's), the edits' emissivities, the BC file's conditions by
/// object with the edits over them, the environment; checked by thermal::checkModel. Throws
/// hemirad::Error (file:line for a file that no longer fits the scene, the objects without a
/// condition named).
ThermalInputs buildThermalInputs(const Scene& scene, const ThermalSetup& setup);

/// Throws hemirad::Error unless `setup` is valid for `scene` as far as it goes: objects without a
/// condition are allowed (taken as adiabatic for the check), everything else as buildThermalInputs.
void checkThermalSetup(const Scene& scene, const ThermalSetup& setup);

/// What a thermal run gives: per patch T, q, ... for the scene it was solved on, per object the net
/// power exchanged (W; the last column the environment), and the lines it reported.
struct ThermalResult {
    thermal::ThermalModel model;  ///< as solved (absorbedExternal: the solar band's)
    thermal::ThermalSolution solution;
    std::optional<thermal::SolarSolution> solar;
    std::vector<std::string> objects;             ///< exchange-matrix rows: objects with patches
    std::vector<std::vector<double>> exchange;    ///< W, [object][object..., environment]
    /// Radiative conductors GR per object (lumped, isothermal nodes) and to the environment, as
    /// `hemirad thermal --conductors` computes them; exported in its formats.
    thermal::Conductors conductors;
    std::uint64_t geometryHash = 0;               ///< of the scene it was solved on
    std::uint64_t materialsRevision = 0, setupRevision = 0;
};

/// One row of the Scene panel's thermal table.
struct ObjectThermalRow {
    std::uint32_t object = 0;
    std::string name;
    std::size_t patches = 0;
    double emissivity = 0.0;  ///< area-weighted mean over the object's patches
    double specular = 0.0;    ///< area-weighted mean of the scene's s
    std::optional<ObjectCondition> condition;  ///< none: no file gives one and it was not set
    double solar = 0.0;       ///< solar_W_m2 from the BC file (0: none)
    bool emissivityEdited = false, conditionEdited = false;
    /// The properties file's emissivity against temperature for the object's patches, e.g.
    /// "eps(T) from the properties file: 0.3 at 300 K, 0.55 at 600 K, 0.8 at 1000 K" ("" when its
    /// emissivity is constant or edited here); `emissivity` is then the curve's value at the
    /// reference temperature, and typing a value replaces the curve with that constant.
    std::string emissivityCurve;
};

/// The table's rows (objects with patches, in scene order) and the environment in effect (K, none:
/// closed). Throws hemirad::Error as checkThermalSetup.
std::vector<ObjectThermalRow> objectThermalRows(const Scene& scene, const ThermalSetup& setup,
                                                std::optional<double>& environment);

}  // namespace hemirad::ui
