// A year of hours against one F: each hour's sun (position, exact sunlit fractions) and isotropic
// sky (DHI x sky view factor) inter-reflected through the same F, the hours' right-hand sides solved
// in batches (one factorisation or one set of sweeps' set-up per batch), annual sums per patch, and
// the hourly totals as a NumPy .npy array. Radiosity is linear in its sources: the sky's radiosity
// is solved once per unit of sky (the isotropic sky's DHI, or each of a model's cells: daylight
// coefficients carried through the inter-reflection) and summed by the hour, so an hour solves for
// its sun alone and an overcast hour (no sun) solves nothing.
#pragma once

#include "engine/atomic_file.hpp"
#include "engine/form_factors.hpp"
#include "engine/scene.hpp"
#include "environment/sensor_sky.hpp"
#include "environment/sensors.hpp"
#include "environment/sky_coefficients.hpp"
#include "environment/weather.hpp"
#include "solve/solver.hpp"

#include <functional>
#include <string>
#include <vector>

namespace hemirad {

struct YearOptions {
    Vec3 up = Vec3(0, 0, 1), north = Vec3(0, 1, 0);
    double metresPerUnit = 1.0;
    std::size_t batch = 168;  ///< hours solved together
    /// Sensor points and their factors (sensorFactors of the same scene), or none: each hour's
    /// irradiance at them as sensorIrradiance gives it, from that hour's patch radiosity.
    const Sensors* sensors = nullptr;
    const SensorFactors* sensorFactors = nullptr;
    /// A sky model's daylight coefficients (of the same scene, oriented by up and north), or none for
    /// the isotropic sky (DHI x the sky view factors). Each hour's cells then take the model's
    /// radiance for that hour's sun, DNI and DHI (at sensors too, with sensorSky).
    const SkyCoefficients* sky = nullptr;
    SkyModel skyModel;
    /// With a sky model and sensors: the sensors' daylight coefficients for the same cells
    /// (sensorSkyCoefficients), each hour's sky at them one product with its cells' radiance.
    const SensorSkyCoefficients* sensorSky = nullptr;
    /// Called for each solved hour in order with its total irradiance per patch and per sensor
    /// (W/m^2; the sensors' pointer null without sensors), to be written as it comes: a year of a
    /// large scene need not be held whole. When set, YearResult::total and sensorTotal stay empty.
    std::function<void(const double* patches, const double* sensors)> hourly;
};

struct YearResult {
    std::vector<std::size_t> hours;       ///< the weather rows solved (sun or sky above 0)
    std::vector<double> total;            ///< per solved hour, per patch (row-major: hours x patches), W/m^2 (none with `hourly`)
    /// Per patch over the year, Wh/m^2: direct sun, direct sky, reflected, total and absorbed.
    std::vector<double> directSun, directSky, reflected, sum, absorbed;
    std::vector<double> reflectedSun;     ///< per patch over the year, Wh/m^2: the sun reflected onto it by mirrors (in sum)
    std::vector<double> reflectedSky;     ///< per patch over the year, Wh/m^2: a sky model's sky seen through mirrors (in sum)
    double worstBalance = 0.0;            ///< the largest hourly |incident - absorbed - escaped| / incident
    std::size_t skyClampedHours = 0;      ///< Perez's sky: hours whose clearness or brightness was kept in the model's range
    std::size_t skyUniformHours = 0;      ///< Perez's sky: hours dark everywhere even so, given a uniform sky (skyRadiance)
    double incidentWh = 0.0, absorbedWh = 0.0;  ///< over the year (W h; scene units^2 x W/m^2 h without a unit)
    /// Wall seconds of the hours' stages: the sun (sunlit fractions, its reflections, the sensors'
    /// sun), the sky (a model's radiance and coefficients), the inter-reflection solves, and the
    /// tallies (each hour's totals, sums and energy balance).
    double sunSeconds = 0.0, skySeconds = 0.0, solveSeconds = 0.0, tallySeconds = 0.0;
    /// With sensors: per solved hour, per sensor (hours x sensors), W/m^2, and per sensor over the
    /// year, Wh/m^2: direct sun, direct sky, reflected, total, and the sun and sky seen in mirrors
    /// (in the total; zeros without mirrors followed).
    std::vector<double> sensorTotal;
    std::vector<double> sensorDirectSun, sensorDirectSky, sensorReflected, sensorSum, sensorReflectedSun, sensorReflectedSky;
};

/// Solves every hour of `weather` with sun or sky on `F` (every row computed) with the direct sky
/// view factors `skyView` (or the sky model's coefficients in `options`, when `skyView` may be
/// empty). Throws hemirad::Error as solarIrradiance does.
YearResult solveYear(const Scene& scene, const FormFactors& F, const std::vector<double>& skyView, const Weather& weather,
                     const YearOptions& options, const SolverOptions& solver);

/// The weather rows a year solves: those with sun or sky (DNI or DHI above 0).
std::vector<std::size_t> solvedHours(const Weather& weather);

/// A NumPy .npy file (format 1.0, little-endian float64, C order) of rows x columns written a row at
/// a time, atomically: the header first, each append() a row, commit() once all rows are in.
class NpyWriter {
public:
    NpyWriter(const std::string& path, std::size_t rows, std::size_t columns);
    void append(const double* row);
    /// Throws hemirad::Error when fewer rows than declared were appended.
    void commit();

private:
    AtomicFile m_file;
    std::size_t m_rows, m_columns, m_written = 0;
};

/// Writes rows x columns doubles as a NumPy .npy file at once (NpyWriter).
void writeNpy(const std::string& path, const std::vector<double>& values, std::size_t rows, std::size_t columns);

}  // namespace hemirad
