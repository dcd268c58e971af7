// Sensor points as the command line gives them, shared by `sensors` and `year`.
#pragma once

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "environment/sensor_sky.hpp"
#include "environment/sensors.hpp"

namespace hemirad {

/// The sensors of --sensors FILE.csv, or of --grid OBJECT --spacing D --height H over `scene`;
/// reports how many. Throws hemirad::Error.
Sensors sensorsFromOptions(const Scene& scene, const Options& options, const Reporter& reporter);

/// Their factors by --sensor-estimator (and --sensor-rays, --threads); reports the estimator, why
/// it was chosen, the work and the sky view factors' range. Throws hemirad::Error.
SensorFactors sensorFactorsFromOptions(const Scene& scene, const Sensors& sensors, const Options& options,
                                       const Reporter& reporter);

/// --sky MODEL's daylight coefficients at the sensors (the cells and directions of --sky-subdivision
/// and --sky-samples, oriented by --up and --north), timed and reported. Throws hemirad::Error.
SensorSkyCoefficients sensorSkyFromOptions(const Scene& scene, const Sensors& sensors, const Options& options, Timings& timings,
                                           const Reporter& reporter);

}  // namespace hemirad
