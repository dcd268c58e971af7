// The thermal input files, TOML (toml++): surface properties by material and object, boundary
// conditions by object and the environment. Every mistake names the file and line. Formats:
// docs/thermal.md.
#pragma once

#include "thermal/thermal_model.hpp"

#include <optional>
#include <string>
#include <vector>

namespace hemirad::thermal {

/// Reads a properties file (path "" = none: every patch from its MTL, propertiesFromMaterials) and
/// applies it to `scene`: a specular reflectance given there becomes the patches' s (F depends on
/// it, so call this before computing F). Per patch the object's entry wins over its material's, that
/// over [default], that over the MTL. `sources` gets one line per object saying where its
/// properties came from. Throws hemirad::Error naming file:line for a syntax error, an unknown key
/// or name, a value out of range or eps + s > 1.
/// Non-gray IR from a properties file's [bands] table: interior limits (um), the emissivity per
/// band and patch (a list per entry, or its one value in every band), the reference temperature
/// at which the gray emissivity (SurfaceProperties) weights them by the blackbody fractions.
/// Or, in the gray model, emissivities against temperature (emissivity = [[T_K, eps], ...]): the
/// distinct curves and each patch's (-1: none; curveOf empty when no table gives one), the gray
/// emissivity then being the curve's value at the reference temperature.
struct BandProperties {
    std::vector<double> limitsUm;
    std::vector<std::vector<double>> emissivity;  ///< [band][patch]; empty without [bands]
    /// [band][patch] where some entry gives specular = [...] (one per band; entries with one value
    /// keep it in every band); empty otherwise. The scene's specular is then the bands' weighted at
    /// the reference temperature.
    std::vector<std::vector<double>> specular;
    double referenceTemperature = 300.0;
    std::vector<EmissivityCurve> emissivityCurves;
    std::vector<std::int32_t> curveOf;
};

/// Moves the band limits and emissivities, the reference temperature and the emissivity curves
/// into `model`.
void takeBandProperties(ThermalModel& model, BandProperties&& bands);

/// `solar`, if given, gets the solar band's properties per patch: solar_absorptance (in emissivity)
/// and solar_specular, the same layers deciding, by default 1 - mean(Kd) - s and the IR specular.
/// `bands`, if given, gets the [bands] model (empty without one).
std::vector<SurfaceProperties> applyProperties(const std::string& path, Scene& scene, std::vector<std::string>& sources,
                                               std::vector<SurfaceProperties>* solar = nullptr, BandProperties* bands = nullptr);
/// The same from text (`name` names it in messages).
std::vector<SurfaceProperties> applyPropertiesText(const std::string& text, const std::string& name, Scene& scene,
                                                   std::vector<std::string>& sources,
                                                   std::vector<SurfaceProperties>* solar = nullptr,
                                                   BandProperties* bands = nullptr);

/// Boundary conditions and the environment read from a file.
struct Conditions {
    std::vector<Condition> perPatch;
    std::vector<IsothermalNode> isothermal;  ///< one per object given power_W
    std::optional<double> environment;  ///< K
    std::vector<std::string> sources;   ///< one line per object: its condition
    /// W/m^2 of solar irradiance arriving from outside on each patch (solar_W_m2; 0 where none).
    std::vector<double> solarIncident;
};

/// Reads a boundary-condition file for `scene`. power_W makes its object an isothermal node.
/// Every object with patches needs a condition, from its own table or [default]. Throws
/// hemirad::Error naming file:line for a syntax error, an unknown key or object, a table with none
/// or two of the conditions, a temperature below 0 K, a non-finite value, or objects left without
/// a condition (named).
Conditions readConditions(const std::string& path, const Scene& scene, double metresPerUnit);
Conditions readConditionsText(const std::string& text, const std::string& name, const Scene& scene, double metresPerUnit);

}  // namespace hemirad::thermal
