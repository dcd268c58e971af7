// One hour's solar irradiance: first arrivals, one radiosity band, the decomposition and balance.
#include "environment/irradiance.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

IrradianceResult solarIrradiance(const Scene& scene, const FormFactors& F, const IrradianceInputs& in, double metresPerUnit,
                                 const SolverOptions& options) {
    const std::size_t n = scene.size();
    if (in.directSun.size() != n || in.skyView.size() != n || F.size() != n)
        throw Error("irradiance: the direct sun, the sky view factors and F need one entry per patch");
    if (!(std::isfinite(in.dhi) && in.dhi >= 0.0)) throw Error("irradiance: the diffuse-horizontal irradiance must be >= 0");
    for (std::size_t i = 0; i < n; ++i)
        if (!F.rowComputed(i)) throw Error("irradiance: row " + std::to_string(i) + " of F was not computed (compute every row)");
    IrradianceResult out;
    out.directSun = in.directSun;
    out.directSky.resize(n);
    Band band;
    band.name = "solar";
    band.rho.resize(n);
    band.source.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        out.directSky[i] = in.dhi * in.skyView[i];
        band.rho[i] = std::clamp(scene.patches[i].rho.mean(), 0.0, 1.0 - scene.patches[i].specular);
        band.source[i] = band.rho[i] * (out.directSun[i] + out.directSky[i]);
    }
    BandSolution solved = solveBands(scene, F, {band}, options);
    out.report = solved.reports.at(0);
    const std::vector<double>& J = solved.X.at(0);
    out.reflected.assign(n, 0.0);
    out.total.assign(n, 0.0);
    out.absorbed.assign(n, 0.0);
    const double m2 = metresPerUnit * metresPerUnit;
    std::vector<double> landedFrom(n, 0.0);  // per column j: sum_i A_i F_ij (1 - s_i)
    for (std::size_t i = 0; i < n; ++i) {
        double h = 0.0;
        const double w = scene.patches[i].area * m2 * (1.0 - scene.patches[i].specular);
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            h += double(F.values()[k]) * J[F.columns()[k]];
            landedFrom[F.columns()[k]] += w * double(F.values()[k]);
        }
        out.reflected[i] = h;
        const double first = out.directSun[i] + out.directSky[i];
        out.total[i] = first + h;
        out.absorbed[i] = std::max(0.0, 1.0 - band.rho[i] - scene.patches[i].specular) * out.total[i];
    }
    for (std::size_t i = 0; i < n; ++i) {
        const double A = scene.patches[i].area * m2, first = out.directSun[i] + out.directSky[i];
        out.incidentPower += A * first;
        out.absorbedPower += A * out.absorbed[i];
        out.escapedPower += A * scene.patches[i].specular * first + J[i] * (A - landedFrom[i]);
    }
    out.balance = out.incidentPower > 0.0 ? std::abs(out.incidentPower - out.absorbedPower - out.escapedPower) / out.incidentPower : 0.0;
    return out;
}

}  // namespace hemirad
