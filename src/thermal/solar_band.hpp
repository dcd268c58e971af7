// The solar band of a semi-gray model: prescribed solar irradiance on objects (W/m^2, from outside
// the scene), inter-reflected diffusely through the solar band's extended F, absorbed per patch.
// What each patch absorbs is a heat source for the IR solve (ThermalModel::absorbedExternal). The
// surfaces emit nothing in this band (their temperatures are far below the sun's).
#pragma once

#include "engine/form_factors.hpp"
#include "solve/solver.hpp"
#include "thermal/exchange_rows.hpp"
#include "thermal/thermal_model.hpp"

#include <vector>

namespace hemirad::thermal {

struct SolarBand {
    /// Per patch: solar absorptance (in `emissivity`: Kirchhoff, absorptance = emissivity per band)
    /// and solar specular reflectance; diffuse reflectance 1 - alpha - s.
    std::vector<SurfaceProperties> surface;
    /// Per patch: irradiance arriving from outside the scene (W/m^2 on the patch's front). Its
    /// specular part leaves the scene (a prescribed flux has no direction to reflect it along).
    std::vector<double> incident;
    /// Whether any patch receives some: else there is no solar band to solve.
    bool active() const;
    /// Whether its specular reflectances differ from the IR ones (then it needs its own F).
    bool needsOwnFormFactors(const Scene& scene) const;
};

struct SolarSolution {
    std::vector<double> J, H;       ///< diffuse radiosity and irradiance from the scene, W/m^2
    std::vector<double> absorbed;   ///< W/m^2: alpha (incident + H)
    double incidentPower = 0.0;     ///< sum A incident, W
    double absorbedPower = 0.0;     ///< sum A absorbed, W
    double escapedPower = 0.0;      ///< W: the direct specular part, and what F's columns do not absorb
    double balance = 0.0;           ///< |incident - absorbed - escaped| / incident
    SolveReport report;
};

/// Solves (I - R_d F) J = R_d incident on `F` (the extended factors for the solar band's specular
/// reflectances, every row computed); areas in m^2 by `metresPerUnit`. Throws hemirad::Error for
/// values out of range (alpha + s > 1) or a solve that does not converge.
SolarSolution solveSolar(const Scene& scene, const FormFactors& F, const SolarBand& band, double metresPerUnit,
                         const SolverOptions& options);
/// The same on F as `F` holds it (one process, or rows across MPI ranks).
SolarSolution solveSolar(const Scene& scene, const ExchangeRows& F, const SolarBand& band, double metresPerUnit,
                         const SolverOptions& options);

}  // namespace hemirad::thermal
