// Daylight coefficients from the sun's machinery: each sky direction is a parallel beam.
#include "environment/sky_coefficients.hpp"

#include "engine/error.hpp"
#include "environment/reflected_sun.hpp"
#include "environment/sunlit.hpp"

#include <algorithm>

namespace hemirad {

SkyCoefficients skyCoefficients(const Scene& scene, int subdivision, int samples, const Vec3& up, const Vec3& north) {
    if (samples < 1 || samples > 16) throw Error("sky: " + std::to_string(samples) + " samples per cell side is outside 1..16");
    if (!up.allFinite() || !north.allFinite() || up.norm() == 0.0 || (north - north.dot(up.normalized()) * up.normalized()).norm() == 0.0)
        throw Error("sky: up and north must be finite, not zero and not parallel");
    SkyCoefficients out;
    out.grid = skyGrid(subdivision);
    out.samples = samples;
    out.horizontal = horizontalWeights(out.grid, samples);
    const std::size_t n = scene.size(), cells = out.grid.size();
    const bool mirrors = scene.hasMirrors();
    out.direct = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(cells));
    if (mirrors) out.mirrored = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(cells));
    const BeamShadows shadows(scene);
    for (std::size_t k = 0; k < cells; ++k) {
        const double weight = out.grid.cells[k].solidAngle() / double(samples * samples);
        for (const Vec3& local : cellSamples(out.grid.cells[k], samples)) {
            const Vec3 d = skyToScene(local, up, north);
            const std::vector<double> lit = shadows.sunlitFractions(d);
            for (std::size_t i = 0; i < n; ++i)
                out.direct(Eigen::Index(i), Eigen::Index(k)) += weight * std::max(0.0, scene.patches[i].normal.dot(d)) * lit[i];
            if (!mirrors) continue;
            const ReflectedSun reflected = reflectedSun(shadows, d, 1.0);
            for (std::size_t i = 0; i < n; ++i) out.mirrored(Eigen::Index(i), Eigen::Index(k)) += weight * reflected.irradiance[i];
        }
    }
    return out;
}

std::vector<double> skyIrradiance(const Eigen::MatrixXd& coefficients, const std::vector<double>& radiance) {
    if (std::size_t(coefficients.cols()) != radiance.size())
        throw Error("sky: " + std::to_string(radiance.size()) + " cell radiances for " + std::to_string(coefficients.cols()) + " cells");
    const Eigen::VectorXd E = coefficients * Eigen::Map<const Eigen::VectorXd>(radiance.data(), Eigen::Index(radiance.size()));
    return std::vector<double>(E.data(), E.data() + E.size());
}

SkyHour skyHour(const SkyCoefficients& c, const SkyModel& model, const SkyConditions& conditions) {
    SkyHour hour;
    const std::vector<double> L = skyRadiance(c.grid, c.samples, model, conditions, &hour.uniformFallback);
    hour.direct = skyIrradiance(c.direct, L);
    if (c.mirrored.size() > 0) hour.mirrored = skyIrradiance(c.mirrored, L);
    return hour;
}

}  // namespace hemirad
