// The thermal model of a scene: gray IR properties per patch (emissivity, specular and diffuse
// reflectance), a boundary condition per patch (temperature or net heat flux) and the environment
// node that receives what leaves an open scene. Read from files by thermal_files.hpp.
#pragma once

#include "engine/scene.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hemirad::thermal {

/// Stefan-Boltzmann constant, W m^-2 K^-4 (CODATA 2018).
constexpr double kStefanBoltzmann = 5.670374419e-8;
/// 0 degrees Celsius in kelvin.
constexpr double kCelsiusZero = 273.15;

/// Opaque gray surface: emissivity eps (= absorptance), specular reflectance s, diffuse reflectance
/// rho_d = 1 - eps - s (Siegel & Howell).
struct SurfaceProperties {
    double emissivity = 0.0;
    double specular = 0.0;
    double diffuse() const { return 1.0 - emissivity - specular; }
};

/// A surface's total hemispherical emissivity against its temperature, as handbooks tabulate it:
/// piecewise linear through the points (temperatures increasing, K), constant beyond the first and
/// the last.
struct EmissivityCurve {
    std::vector<double> temperatureK, emissivity;
    double at(double T) const;
};

/// What is known of a patch: its temperature (K), the net heat flux leaving it (W/m^2; 0 is
/// adiabatic: each patch reradiates at its own temperature), or that it belongs to an isothermal
/// node whose patches share one unknown temperature and together give off a known net power (a
/// conductive plate, a thin radiation shield: 0 W).
struct Condition {
    enum class Kind : std::uint8_t { Temperature, Flux, Isothermal };
    Kind kind = Kind::Flux;
    double value = 0.0;      ///< K or W/m^2; unused for Isothermal
    std::uint32_t node = 0;  ///< Isothermal: index into ThermalModel::isothermal
};

/// An isothermal node: one temperature for all its patches, net power leaving them (W).
struct IsothermalNode {
    std::string name;
    double power = 0.0;
};

/// Everything the gray solve needs besides F. Per-patch vectors have one entry per scene patch.
struct ThermalModel {
    std::vector<SurfaceProperties> surface;
    std::vector<Condition> condition;
    /// Non-gray IR: interior band limits (um, increasing; N limits make N + 1 bands from 0 to
    /// infinity) and each band's emissivity per patch (bandEmissivity[k][i]); emission in band k is
    /// eps_k F(lambda_k -> lambda_k+1, T) sigma T^4. Empty: gray. Then surface[i].emissivity is the
    /// emissivity weighted by the blackbody fractions at referenceTemperature (the start of the
    /// iteration, and what the conductors use).
    std::vector<double> bandLimitsUm;
    std::vector<std::vector<double>> bandEmissivity;
    /// Each band's specular reflectance per patch (bandSpecular[k][i]; with bandEmissivity). Empty:
    /// surface[i].specular in every band. A band whose reflectances differ from the scene's needs its
    /// own extended F (solveThermal's bandF). surface[i].specular, the scene's and F's, is then the
    /// reflectances weighted at referenceTemperature, as the gray emissivity.
    std::vector<std::vector<double>> bandSpecular;
    double referenceTemperature = 300.0;
    /// Temperature-dependent emissivity (gray model only): curveOf[i] indexes emissivityCurves, -1
    /// where patch i's emissivity is constant; empty: none. Where a curve is given, the solve uses
    /// the curve (its value at the known temperature; the iteration starts from its value at
    /// referenceTemperature) whatever surface[i].emissivity holds (the properties file puts the
    /// value at referenceTemperature there); solveThermal iterates on the unknown temperatures
    /// (band_solver.hpp).
    std::vector<EmissivityCurve> emissivityCurves;
    std::vector<std::int32_t> curveOf;
    std::vector<IsothermalNode> isothermal;
    /// The environment's temperature (K): deep space (3 K), sky or ambient. It takes each patch's
    /// escape (what F does not absorb) and irradiates each patch by its own. None: a closed scene, or
    /// an environment at 0 K.
    std::optional<double> environment;
    double metresPerUnit = 1.0;  ///< scene length unit in metres (areas in m^2 = area * this^2)
    /// Heat absorbed per patch from outside the IR band (W/m^2; the solar band's absorbed flux), a
    /// source in each patch's balance: the net heat leaving is q = eps (sigma T^4 - H) - this. Empty: 0.
    std::vector<double> absorbedExternal;
    /// Where each object's properties and condition came from, for the report (per scene object).
    std::vector<std::string> propertySource, conditionSource;
};

/// Patch i's specular reflectance in band k (its gray one without per-band reflectances).
inline double specularIn(const ThermalModel& model, std::size_t k, std::size_t i) {
    return model.bandSpecular.empty() ? model.surface[i].specular : model.bandSpecular[k][i];
}

/// Whether band k's specular reflectances differ from the scene's (then F does not serve it).
bool bandNeedsOwnFormFactors(const Scene& scene, const ThermalModel& model, std::size_t k);

/// Whether some patch's emissivity depends on its temperature.
inline bool hasEmissivityCurves(const ThermalModel& model) {
    for (const std::int32_t c : model.curveOf)
        if (c >= 0) return true;
    return false;
}

/// Patch i's largest emissivity at any temperature (its constant one without a curve).
double largestEmissivity(const ThermalModel& model, std::size_t i);

/// Patch i's emissivity at temperature T: its curve's value, or its constant one.
double emissivityAt(const ThermalModel& model, std::size_t i, double T);

/// Sets surface[i].emissivity of every patch with a curve to the curve's value at `T[i]` (the
/// solved temperatures: what the conductors of a solution use).
void setEmissivitiesAt(ThermalModel& model, const std::vector<double>& T);

/// The properties a scene has without a properties file: eps = 1 - mean(Kd) - s, i.e. the MTL's
/// diffuse reflectance taken as the IR one (an assumption the report states), s from the scene.
std::vector<SurfaceProperties> propertiesFromMaterials(const Scene& scene);

/// Throws hemirad::Error naming the object and value unless the model is physical and solvable:
/// one entry per patch, 0 <= eps, 0 <= s, eps + s <= 1, s equal to the scene's (F depends on it),
/// temperatures finite and >= 0 K, fluxes finite, an environment temperature >= 0 K and a flux only
/// where eps > 0 or the flux is 0 (a surface that neither emits nor absorbs has no net flux).
void checkModel(const Scene& scene, const ThermalModel& model);

}  // namespace hemirad::thermal
