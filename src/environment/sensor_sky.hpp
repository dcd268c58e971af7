// A sky model at sensor points: daylight coefficients per sensor and sky cell, by the patches'
// quadrature (skyCoefficients) with each direction's parallel beam tested at the point, so that any
// hour of a sky model (CIE, Perez) gives every sensor's direct sky, and the sky its mirrors show it,
// as one product with the cells' radiance.
#pragma once

#include "environment/sensors.hpp"
#include "environment/sky_model.hpp"

#include <Eigen/Core>

#include <vector>

namespace hemirad {

struct SensorSkyCoefficients {
    /// sensors x cells, sr: sum over the cell's directions d of (its solid angle) x cos(theta_s(d))
    /// where a beam from d reaches the sensor past every patch (sensorSunlit).
    Eigen::MatrixXd direct;
    /// sensors x cells, sr: the same for the cell seen by way of one mirror (SensorReflections::sun
    /// for a unit DNI: s cos where the reflected beam reaches the sensor); 0 x 0 where the scene has no
    /// mirror or they cannot be followed.
    Eigen::MatrixXd mirrored;
};

/// The coefficients of `sensors` in `scene` for the cells of `grid`, `samples` x `samples` directions
/// per cell (as skyCoefficients: cellSamples, oriented by `up` and `north`). Below the horizon
/// nothing comes. The sensors run on `threads` threads (0: every core). Throws hemirad::Error for
/// samples outside 1..16 or up and north that orient nothing.
SensorSkyCoefficients sensorSkyCoefficients(const Scene& scene, const Sensors& sensors, const SkyGrid& grid, int samples,
                                            const Vec3& up, const Vec3& north, int threads = 0);

/// One hour at the sensors, W/m^2: the coefficients times the cells' radiance (skyRadiance).
SensorSky sensorSkyHour(const SensorSkyCoefficients& coefficients, const std::vector<double>& radiance);

}  // namespace hemirad
