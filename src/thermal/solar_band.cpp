// Semi-gray solar band: a radiosity band whose only source is the prescribed external irradiance.
#include "thermal/solar_band.hpp"

#include "engine/error.hpp"
#include "thermal/thermal_solver.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hemirad::thermal {

bool SolarBand::active() const {
    return std::any_of(incident.begin(), incident.end(), [](double e) { return e != 0.0; });
}

bool SolarBand::needsOwnFormFactors(const Scene& scene) const {
    for (PatchId i = 0; i < scene.size() && i < surface.size(); ++i)
        if (surface[i].specular != scene.patches[i].specular) return true;
    return false;
}

SolarSolution solveSolar(const Scene& scene, const FormFactors& F, const SolarBand& band, double metresPerUnit,
                         const SolverOptions& options) {
    return solveSolar(scene, LocalRows(F), band, metresPerUnit, options);
}

SolarSolution solveSolar(const Scene& scene, const ExchangeRows& F, const SolarBand& band, double metresPerUnit,
                         const SolverOptions& given) {
    const SolverOptions options = F.solverOptions(given, scene.size());
    const std::size_t n = scene.size();
    if (band.surface.size() != n || band.incident.size() != n || F.size() != n)
        throw Error("thermal: the solar band needs one value per patch and F of the scene");
    for (std::size_t i = 0; i < n; ++i) {
        const SurfaceProperties& sp = band.surface[i];
        std::ostringstream msg;
        if (!(sp.emissivity >= 0.0 && sp.emissivity <= 1.0 && sp.specular >= 0.0 && sp.emissivity + sp.specular <= 1.0 + 1e-12))
            msg << "thermal: patch " << i << ": solar absorptance " << sp.emissivity << " and specular " << sp.specular
                << " must be in [0, 1] with a sum of at most 1";
        else if (!(std::isfinite(band.incident[i]) && band.incident[i] >= 0.0))
            msg << "thermal: patch " << i << ": solar irradiance " << band.incident[i] << " W/m^2 must be finite and >= 0";
        else if (!F.rowComputed(i))
            msg << "thermal: row " << i << " of the solar band's F was not computed";
        else
            continue;
        throw Error(msg.str());
    }
    Band b;
    b.name = "solar";
    b.rho.resize(n);
    b.source.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        b.rho[i] = std::max(0.0, band.surface[i].diffuse());
        b.source[i] = b.rho[i] * band.incident[i];
    }
    BandSolution solved = F.solve(scene, {b}, options);
    SolarSolution out;
    out.report = solved.reports.at(0);
    out.J = std::move(solved.X.at(0));
    out.H = F.rowProducts(out.J);
    out.absorbed.assign(n, 0.0);
    const double m2 = metresPerUnit * metresPerUnit;
    std::vector<double> absorbing(n);
    for (std::size_t i = 0; i < n; ++i) absorbing[i] = scene.patches[i].area * m2 * (1.0 - band.surface[i].specular);
    const std::vector<double> absorbedFrom = F.columnSums(absorbing);  // per column j: sum_i A_i F_ij (1 - s_i)
    for (std::size_t i = 0; i < n; ++i) out.absorbed[i] = band.surface[i].emissivity * (band.incident[i] + out.H[i]);
    for (std::size_t i = 0; i < n; ++i) {
        const double A = scene.patches[i].area * m2;
        out.incidentPower += A * band.incident[i];
        out.absorbedPower += A * out.absorbed[i];
        out.escapedPower += A * band.surface[i].specular * band.incident[i] + out.J[i] * (A - absorbedFrom[i]);
    }
    out.balance = out.incidentPower > 0.0
                      ? std::abs(out.incidentPower - out.absorbedPower - out.escapedPower) / out.incidentPower
                      : 0.0;
    return out;
}

}  // namespace hemirad::thermal
