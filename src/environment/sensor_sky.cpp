// Sensors' daylight coefficients: each sky direction a parallel beam, tested at every sensor (one
// shadow-polygon ray each) and through the mirrors (the reflected beam's ray from each sensor).
#include "environment/sensor_sky.hpp"

#include "engine/error.hpp"
#include "environment/sensor_mirrors.hpp"
#include "environment/sunlit.hpp"

#include <algorithm>

namespace hemirad {

SensorSkyCoefficients sensorSkyCoefficients(const Scene& scene, const Sensors& sensors, const SkyGrid& grid, int samples,
                                            const Vec3& up, const Vec3& north, int threads) {
    if (samples < 1 || samples > 16) throw Error("sky: " + std::to_string(samples) + " samples per cell side is outside 1..16");
    if (!up.allFinite() || !north.allFinite() || up.norm() == 0.0 || (north - north.dot(up.normalized()) * up.normalized()).norm() == 0.0)
        throw Error("sky: up and north must be finite, not zero and not parallel");
    const std::size_t count = sensors.size(), cells = grid.size();
    SensorSkyCoefficients out;
    out.direct = Eigen::MatrixXd::Zero(Eigen::Index(count), Eigen::Index(cells));
    const BeamShadows beams(scene);
    const SensorReflections mirrors(scene, threads);
    if (mirrors.active()) out.mirrored = Eigen::MatrixXd::Zero(Eigen::Index(count), Eigen::Index(cells));
    for (std::size_t k = 0; k < cells; ++k) {
        const double weight = grid.cells[k].solidAngle() / double(samples * samples);
        for (const Vec3& local : cellSamples(grid.cells[k], samples)) {
            const Vec3 d = skyToScene(local, up, north);
            const std::vector<double> lit = sensorSunlit(beams, sensors, d);
            for (std::size_t s = 0; s < count; ++s)
                out.direct(Eigen::Index(s), Eigen::Index(k)) += weight * std::max(0.0, sensors.normal[s].dot(d)) * lit[s];
            if (!mirrors.active()) continue;
            const std::vector<double> reflected = mirrors.sun(beams, sensors, d, 1.0);
            for (std::size_t s = 0; s < count; ++s) out.mirrored(Eigen::Index(s), Eigen::Index(k)) += weight * reflected[s];
        }
    }
    return out;
}

SensorSky sensorSkyHour(const SensorSkyCoefficients& c, const std::vector<double>& radiance) {
    if (std::size_t(c.direct.cols()) != radiance.size())
        throw Error("sky: " + std::to_string(radiance.size()) + " cell radiances for " + std::to_string(c.direct.cols()) + " cells");
    const Eigen::Map<const Eigen::VectorXd> L(radiance.data(), Eigen::Index(radiance.size()));
    SensorSky out;
    const Eigen::VectorXd direct = c.direct * L;
    out.direct.assign(direct.data(), direct.data() + direct.size());
    if (c.mirrored.size() > 0) {
        const Eigen::VectorXd mirrored = c.mirrored * L;
        out.mirrored.assign(mirrored.data(), mirrored.data() + mirrored.size());
    }
    return out;
}

}  // namespace hemirad
