// Solar irradiance of an open scene for one hour: the direct sun (sunlit fraction x DNI cos), the
// direct isotropic sky (diffuse-horizontal irradiance x sky view factor) and what the surfaces
// reflect to each other (a radiosity band through F), decomposed per patch, with the power balance.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/scene.hpp"
#include "solve/solver.hpp"

#include <vector>

namespace hemirad {

struct IrradianceInputs {
    std::vector<double> directSun;  ///< W/m^2 per patch: DNI cos(theta) x sunlit fraction
    std::vector<double> skyView;    ///< per patch: the direct sky view factor (environment/sky_view.hpp)
    double dhi = 0.0;               ///< diffuse-horizontal irradiance of an isotropic sky, W/m^2
};

struct IrradianceResult {
    std::vector<double> directSun, directSky, reflected, total, absorbed;  ///< W/m^2 per patch
    std::vector<double> radiosity;  ///< W/m^2 per patch: the diffuse radiosity J leaving it (what sensors see of it)
    double incidentPower = 0.0;   ///< W (scene units^2 x W/m^2 when the scene has no unit): the first arrivals
    double absorbedPower = 0.0;
    double escapedPower = 0.0;    ///< what leaves to the sky: diffuse reflections F does not land, specular first reflections
    double balance = 0.0;         ///< |incident - absorbed - escaped| / incident
    SolveReport report;
};

/// Inter-reflects the first arrivals (direct sun + direct sky) through F (every row computed) with
/// each patch's broadband diffuse reflectance (the mean of its Kd) and mirror reflectance s: the
/// diffuse radiosity J = rho (E + F J); reflected irradiance F J; absorbed (1 - rho - s) x total.
/// The specular part of the first arrivals leaves the scene (the sun's and sky's images through
/// mirrors are not yet followed). Throws hemirad::Error for inputs of the wrong size or an
/// unconverged solve.
IrradianceResult solarIrradiance(const Scene& scene, const FormFactors& F, const IrradianceInputs& inputs,
                                 double metresPerUnit, const SolverOptions& options);

}  // namespace hemirad
