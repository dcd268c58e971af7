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
    /// W/m^2 per patch: the direct sky of a sky model (environment/sky_coefficients.hpp), or empty
    /// for the isotropic sky dhi x skyView (skyView may then be empty).
    std::vector<double> directSky;
    /// W/m^2 per patch: the sky seen by way of mirrors (the daylight coefficients' mirrored part), or
    /// empty. Like the reflected sun, part of the mirrors' specular reflection of their direct sky.
    std::vector<double> reflectedSky;
    /// W/m^2 per patch: the sun reflected onto it by mirrors (environment/reflected_sun.hpp), or
    /// empty. Part of the mirrors' specular reflection of the direct sun: it lands instead of leaving.
    std::vector<double> reflectedSun;
};

struct IrradianceResult {
    std::vector<double> directSun, directSky, reflected, total, absorbed;  ///< W/m^2 per patch
    std::vector<double> reflectedSun;  ///< W/m^2 per patch: the mirrors' reflection of the sun (zeros without)
    std::vector<double> reflectedSky;  ///< W/m^2 per patch: the sky seen through mirrors (zeros without a sky model's)
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
/// The first arrivals are the direct sun, the direct sky and the sun (and a sky model's sky) reflected
/// by mirrors (given); the specular part that lands so does not leave, the rest of the first arrivals'
/// specular part does (the isotropic sky's images through mirrors are not followed). The
/// incident power counts what comes from outside: the direct sun and sky. Throws hemirad::Error for
/// inputs of the wrong size or an unconverged solve.
IrradianceResult solarIrradiance(const Scene& scene, const FormFactors& F, const IrradianceInputs& inputs,
                                 double metresPerUnit, const SolverOptions& options);

}  // namespace hemirad
