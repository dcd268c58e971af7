// `hemirad sensors SCENE --sensors S.csv | --grid OBJECT --spacing D -o OUT.csv`: each sensor point's
// sky view factor and factors to the patches (--factors F.mtx; exact, or by rays for large grids),
// and with --dni and the sun one hour's irradiance there: direct sun, direct sky and what the
// patches reflect (src/environment).
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "cli/sensor_command.hpp"
#include "cli/sun_command.hpp"
#include "environment/sensor_mirrors.hpp"
#include "environment/sensors.hpp"

#include <algorithm>
#include <iomanip>
#include <numeric>
#include <optional>
#include <sstream>

namespace hemirad {

Sensors sensorsFromOptions(const Scene& scene, const Options& options, const Reporter& reporter) {
    Sensors sensors = options.sensorsPath.empty()
                          ? sensorGrid(scene, options.gridObject, options.gridSpacing, options.gridHeight)
                          : readSensorsCsv(options.sensorsPath);
    reporter.line("sensors: " + std::to_string(sensors.size()) +
                  (options.sensorsPath.empty() ? " on a grid over '" + options.gridObject + "'" : " from " + options.sensorsPath));
    return sensors;
}

SensorFactors sensorFactorsFromOptions(const Scene& scene, const Sensors& sensors, const Options& options,
                                       const Reporter& reporter) {
    SensorOptions chosen = options.sensorFactors;
    chosen.threads = options.formFactors.common.threads;
    chosen.limits.maxDepth = options.formFactors.common.maxDepth;
    chosen.limits.minWeight = options.formFactors.common.minWeight;
    std::string why;
    const SensorFactors factors = sensorFactors(scene, sensors, chosen, &why);
    const double mean = std::accumulate(factors.skyView.begin(), factors.skyView.end(), 0.0) / double(sensors.size());
    std::ostringstream line;
    line << std::setprecision(4) << "sensor factors: ";
    if (factors.rays > 0)
        line << "rays (" << chosen.rays << " stratified directions per sensor, " << factors.rays << " rays)";
    else
        line << "exact (Lambert's factors to the visible parts, shadow polygons), " << factors.terms
             << " sensor-patch terms";
    line << ", " << factors.values.size() << " nonzeros; sky view factor mean " << mean << ", min "
         << *std::min_element(factors.skyView.begin(), factors.skyView.end()) << ", max "
         << *std::max_element(factors.skyView.begin(), factors.skyView.end()) << " [" << why << "]";
    if (!factors.mirrors.empty()) {
        line << "\n  mirrors: " << factors.mirrors;
        if (!factors.skyMirrored.empty())
            line << "; sky seen in them: mean "
                 << std::accumulate(factors.skyMirrored.begin(), factors.skyMirrored.end(), 0.0) / double(sensors.size()) << ", max "
                 << *std::max_element(factors.skyMirrored.begin(), factors.skyMirrored.end()) << "; cut off by --max-depth "
                 << chosen.limits.maxDepth << " / --min-weight " << chosen.limits.minWeight << ": "
                 << factors.cutoffWeight / double(sensors.size()) << " per sensor (counted as sky)";
    }
    reporter.line(line.str());
    return factors;
}

SensorSkyCoefficients sensorSkyFromOptions(const Scene& scene, const Sensors& sensors, const Options& options, Timings& timings,
                                           const Reporter& reporter) {
    timings.start("sensors' daylight coefficients");
    const SkyGrid grid = skyGrid(options.skySubdivision);
    SensorSkyCoefficients sky =
        sensorSkyCoefficients(scene, sensors, grid, options.skySamples, upFromOptions(options), northFromOptions(options),
                              options.formFactors.common.threads);
    timings.stop();
    std::ostringstream line;
    line << "sensors' sky: " << grid.size() << " cells x " << options.skySamples * options.skySamples
         << " direction(s), a ray from each sensor along each" << (sky.mirrored.size() > 0 ? ", and each mirror's reflected beam" : "");
    reporter.line(line.str());
    return sky;
}

int runSensors(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const Scene scene = loadScene(options, timings, reporter, warnings);

    timings.start("sensors");
    const Sensors sensors = sensorsFromOptions(scene, options, reporter);
    timings.start("sensor factors");
    const SensorFactors factors = sensorFactorsFromOptions(scene, sensors, options, reporter);
    timings.stop();
    if (factors.mirrors.rfind("not followed", 0) == 0) warnings.add("mirrors", "sensors: the scene's mirrors are " + factors.mirrors);

    SensorIrradiance irradiance;
    if (options.dni) {
        const double metres = metresFromOptions(scene, options, warnings);
        const Vec3 toSun = sunDirectionFromOptions(options, reporter);
        // The patches' hour as `irradiance` solves it: their radiosity is what the sensors see reflected.
        const IrradianceResult patches = patchHour(scene, options, toSun, metres, timings, reporter, warnings);
        timings.start("sensors in the sun");
        // A sun below the horizon (--sun-time at night) reaches no sensor (patchHour says so).
        std::vector<double> lit(sensors.size(), 0.0), glare;
        if (!sunBelowHorizon(options)) {
            const BeamShadows beams(scene);
            lit = sensorSunlit(beams, sensors, toSun);
            const SensorReflections reflections(scene, options.formFactors.common.threads);
            if (reflections.active()) glare = reflections.sun(beams, sensors, toSun, *options.dni);
            else if (scene.hasMirrors() && factors.mirrors.rfind("followed", 0) == 0)  // rays follow mirrors images cannot
                warnings.add("mirrors", "sensors: the sun reflected by mirrors is " + reflections.note());
        }
        // A sky model's hour at the sensors, as the patches have it.
        std::optional<SensorSky> modelSky;
        if (options.skyModel != "isotropic") {
            const SensorSkyCoefficients coefficients = sensorSkyFromOptions(scene, sensors, options, timings, reporter);
            const std::vector<double> L = skyRadiance(skyGrid(options.skySubdivision), options.skySamples, parseSkyModel(options.skyModel),
                                                      skyConditionsFromOptions(options, toSun));
            modelSky = sensorSkyHour(coefficients, L);
        }
        irradiance = sensorIrradiance(sensors, factors, lit, toSun, *options.dni, options.dhi, patches.radiosity, glare,
                                      modelSky ? &*modelSky : nullptr);
        timings.stop();
        std::ostringstream line;
        line << std::setprecision(6) << "sensors: the patches' hour balances to " << std::setprecision(3) << patches.balance
             << " (" << patches.report.solver << "); " << std::accumulate(lit.begin(), lit.end(), 0.0) << " of "
             << sensors.size() << " sensors in the sun";
        if (!glare.empty())
            line << ", " << std::count_if(glare.begin(), glare.end(), [](double g) { return g > 0.0; })
                 << " in the sun reflected by mirrors (up to " << *std::max_element(glare.begin(), glare.end()) << " W/m^2)";
        reporter.line(line.str());
    }

    timings.start("write CSV");
    writeSensorsCsv(options.output, sensors, factors, options.dni ? &irradiance : nullptr);
    if (!options.sensorFactorsPath.empty()) writeSensorFactorsMtx(options.sensorFactorsPath, factors);
    timings.stop();
    reporter.line("wrote " + outputName(options.output) + " (per sensor: position, normal, sky view factor" +
                  (factors.skyMirrored.empty() ? std::string() : std::string(", sky direct and through mirrors")) +
                  (options.dni ? std::string(", direct sun, direct sky") +
                                     (factors.skyMirrored.empty() ? "" : ", sun and sky reflected by mirrors") + ", reflected, total"
                               : std::string()) +
                  ")" +
                  (options.sensorFactorsPath.empty() ? "" : " and " + outputName(options.sensorFactorsPath) +
                                                               " (sensors x patches)"));
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
