// One hour's solar irradiance: first arrivals, one radiosity band, the decomposition and balance.
#include "environment/irradiance.hpp"

#include "engine/error.hpp"
#include "thermal/solar_band.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

IrradianceResult solarIrradiance(const Scene& scene, const FormFactors& F, const IrradianceInputs& in, double metresPerUnit,
                                 const SolverOptions& options) {
    const std::size_t n = scene.size();
    const auto sized = [n](const std::vector<double>& v) { return v.empty() || v.size() == n; };
    if (in.directSun.size() != n || F.size() != n || !sized(in.reflectedSun) || !sized(in.directSky) || !sized(in.reflectedSky) ||
        (in.directSky.empty() && in.skyView.size() != n))
        throw Error("irradiance: the direct sun, the sky (view factors or irradiance), the reflected sun and sky and F need one entry per patch");
    if (!(std::isfinite(in.dhi) && in.dhi >= 0.0)) throw Error("irradiance: the diffuse-horizontal irradiance must be >= 0");
    // The first arrivals inter-reflected as the thermal model's solar band is (thermal/solar_band.hpp):
    // broadband reflectance the mean of Kd, absorptance what neither reflection takes.
    thermal::SolarBand band;
    band.surface.resize(n);
    band.incident.resize(n);
    IrradianceResult out;
    out.directSun = in.directSun;
    out.reflectedSun = in.reflectedSun.empty() ? std::vector<double>(n, 0.0) : in.reflectedSun;
    out.reflectedSky = in.reflectedSky.empty() ? std::vector<double>(n, 0.0) : in.reflectedSky;
    out.directSky.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double s = scene.patches[i].specular, rho = std::clamp(scene.patches[i].rho.mean(), 0.0, 1.0 - s);
        band.surface[i] = {1.0 - rho - s, s};
        out.directSky[i] = in.directSky.empty() ? in.dhi * in.skyView[i] : in.directSky[i];
        band.incident[i] = out.directSun[i] + out.directSky[i] + out.reflectedSun[i] + out.reflectedSky[i];
    }
    thermal::SolarSolution solar = thermal::solveSolar(scene, F, band, metresPerUnit, options);
    out.reflected = std::move(solar.H);
    out.radiosity = std::move(solar.J);
    out.absorbed = std::move(solar.absorbed);
    out.total.resize(n);
    for (std::size_t i = 0; i < n; ++i) out.total[i] = band.incident[i] + out.reflected[i];
    // The reflected sun (and sky) is the mirrors' specular reflection of their direct sun (and sky)
    // landing: counted once as it comes in (on the mirrors), and not as leaving.
    double landed = 0.0;
    const double m2 = metresPerUnit * metresPerUnit;
    for (std::size_t i = 0; i < n; ++i) landed += scene.patches[i].area * m2 * (out.reflectedSun[i] + out.reflectedSky[i]);
    out.incidentPower = solar.incidentPower - landed;
    out.absorbedPower = solar.absorbedPower;
    out.escapedPower = solar.escapedPower - landed;
    out.balance = out.incidentPower > 0.0
                      ? std::abs(out.incidentPower - out.absorbedPower - out.escapedPower) / out.incidentPower
                      : solar.balance;
    out.report = solar.report;
    return out;
}

}  // namespace hemirad
