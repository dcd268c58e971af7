// `hemirad year SCENE --weather W.epw -o ANNUAL.csv [--hourly H.npy]`: a year of hours against one F.
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "cli/sensor_command.hpp"
#include "cli/sun_command.hpp"
#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "environment/year.hpp"

#include <chrono>
#if __has_include(<malloc.h>)
#include <malloc.h>
#endif
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

namespace hemirad {

namespace {

/// Keeps freed blocks of any size in the process's heap for the next batch: glibc maps blocks above
/// its threshold afresh each time (a batch's N x hours arrays are 50-80 MB on street64k) and returns
/// them on free, so every batch paid for its pages again. Measured on street64k's June fortnight
/// (224 hours, alternate runs): 468,800 page faults instead of 599,600 (the rest are the peak's
/// first touches), 20.1-21.3 s instead of 21.8-24.4. Where a C library refuses the threshold, no
/// block is mapped at all (the same effect).
void keepLargeBlocks() {
#if defined(__GLIBC__)
    if (mallopt(M_MMAP_THRESHOLD, 1 << 30) != 1) mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
#endif
}

}  // namespace

int runYear(const Options& options) {
    keepLargeBlocks();
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const Scene scene = loadScene(options, timings, reporter, warnings);
    timings.start("read weather");
    const Weather weather = readEpw(options.weatherPath);
    timings.stop();
    YearOptions yo;
    yo.up = upFromOptions(options);
    yo.north = northFromOptions(options);
    yo.metresPerUnit = metresFromOptions(scene, options, warnings);
    std::ostringstream where;
    where << "weather: " << weather.place << ", latitude " << weather.latitude << ", longitude " << weather.longitude << ", UTC"
          << std::showpos << weather.timeZone << std::noshowpos << "; " << weather.hours.size() << " hours";
    reporter.line(where.str());

    std::vector<double> sky;
    SkyCoefficients coefficients;
    if (options.skyModel == "isotropic") {
        sky = directSkyViewFromOptions(scene, options, timings, reporter);
    } else {
        coefficients = skyCoefficientsFromOptions(scene, options, timings, reporter);
        yo.sky = &coefficients;
        yo.skyModel = parseSkyModel(options.skyModel);
    }
    Sensors sensors;
    SensorFactors sensorFactorsOf;
    if (!options.sensorsPath.empty() || !options.gridObject.empty()) {
        timings.start("sensors");
        sensors = sensorsFromOptions(scene, options, reporter);
        timings.start("sensor factors");
        sensorFactorsOf = sensorFactorsFromOptions(scene, sensors, options, reporter);
        yo.sensors = &sensors;
        yo.sensorFactors = &sensorFactorsOf;
    }
    SensorSkyCoefficients sensorSky;
    if (yo.sensors && yo.sky) {
        sensorSky = sensorSkyFromOptions(scene, sensors, options, timings, reporter);
        yo.sensorSky = &sensorSky;
    }
    timings.stop();
    Options withRows = options;
    withRows.allRows = true;
    const FormFactors F = obtainFormFactors(scene, withRows, timings, reporter, warnings);
    // Each hour's totals go to the .npy files as they are solved (a year of a large scene is GBs).
    const std::size_t solved = solvedHours(weather).size();
    std::optional<NpyWriter> hourly, sensorHourly;
    if (!options.hourlyPath.empty()) hourly.emplace(options.hourlyPath, solved, scene.size());
    if (yo.sensors && !options.sensorHourlyPath.empty()) sensorHourly.emplace(options.sensorHourlyPath, solved, sensors.size());
    if (hourly || sensorHourly)
        yo.hourly = [&](const double* patches, const double* atSensors) {
            if (hourly) hourly->append(patches);
            if (sensorHourly) sensorHourly->append(atSensors);
        };
    timings.start("hours");
    const auto t0 = std::chrono::steady_clock::now();
    const YearResult year = solveYear(scene, F, sky, weather, yo, options.solver);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timings.stop();
    const auto per = [&year](double s) {
        std::ostringstream ms;
        ms.precision(3);
        ms << (year.hours.empty() ? 0.0 : 1e3 * s / double(year.hours.size()));
        return ms.str();
    };
    std::ostringstream line;
    line.precision(4);
    line << "year: " << year.hours.size() << " hours with sun or sky solved in " << seconds << " s ("
         << (year.hours.empty() ? 0.0 : 1e3 * seconds / double(year.hours.size())) << " ms per hour); "
         << year.incidentWh / 1e3 << " kWh arrive, " << year.absorbedWh / 1e3 << " kWh absorbed; worst hourly balance "
         << year.worstBalance << "; per hour: sun " << per(year.sunSeconds) << " ms" << (yo.sky ? ", sky " + per(year.skySeconds) + " ms" : "")
         << ", solve " << per(year.solveSeconds) << " ms, tallies " << per(year.tallySeconds) << " ms";
    if (year.skyClampedHours > 0)
        line << "; Perez's clearness or brightness kept within the model's fitted ranges in " << year.skyClampedHours
             << " hour(s) (the sun low, where the air mass explodes)";
    if (year.skyUniformHours > 0)
        line << "; " << year.skyUniformHours << " hour(s) where Perez's sky was dark everywhere even so took a uniform sky";
    reporter.line(line.str());

    timings.start("write results");
    {
        AtomicFile file(options.output, false);
        std::ostream& out = file.stream();
        out << std::setprecision(std::numeric_limits<double>::max_digits10);
        const bool mirrors = scene.hasMirrors();  // then a column for the sun they reflect (and a sky model's sky)
        const bool skyThrough = mirrors && yo.sky;
        out << "patch,object,direct_sun (Wh/m^2),direct_sky (Wh/m^2),reflected (Wh/m^2),total (Wh/m^2),absorbed (Wh/m^2)"
            << (mirrors ? ",reflected_sun (Wh/m^2)" : "") << (skyThrough ? ",reflected_sky (Wh/m^2)" : "") << "\n";
        for (PatchId i = 0; i < scene.size(); ++i) {
            const std::string name = csvField(scene.objects[scene.patches[i].object]);
            out << i << ',' << name << ',' << year.directSun[i] << ',' << year.directSky[i] << ',' << year.reflected[i] << ','
                << year.sum[i] << ',' << year.absorbed[i];
            if (mirrors) out << ',' << year.reflectedSun[i];
            if (skyThrough) out << ',' << year.reflectedSky[i];
            out << '\n';
        }
        file.commit();
    }
    if (hourly) hourly->commit();
    if (yo.sensors) {
        AtomicFile file(options.sensorOutputPath, false);
        std::ostream& out = file.stream();
        out << std::setprecision(std::numeric_limits<double>::max_digits10);
        // With mirrors followed: the sky view factor is direct + in mirrors, and the sun and sky the
        // mirrors show each sensor have columns of their own.
        const bool mirrored = !sensorFactorsOf.skyMirrored.empty();
        out << "sensor,name,sky_view_factor" << (mirrored ? ",sky_direct,sky_through_mirrors" : "")
            << ",direct_sun (Wh/m^2),direct_sky (Wh/m^2)" << (mirrored ? ",reflected_sun (Wh/m^2),reflected_sky (Wh/m^2)" : "")
            << ",reflected (Wh/m^2),total (Wh/m^2)\n";
        for (std::size_t s = 0; s < sensors.size(); ++s) {
            out << s << ',' << csvField(sensors.name[s]) << ',';
            if (mirrored)
                out << sensorFactorsOf.skyView[s] + sensorFactorsOf.skyMirrored[s] << ',' << sensorFactorsOf.skyView[s] << ','
                    << sensorFactorsOf.skyMirrored[s];
            else
                out << sensorFactorsOf.skyView[s];
            out << ',' << year.sensorDirectSun[s] << ',' << year.sensorDirectSky[s];
            if (mirrored) out << ',' << year.sensorReflectedSun[s] << ',' << year.sensorReflectedSky[s];
            out << ',' << year.sensorReflected[s] << ',' << year.sensorSum[s] << '\n';
        }
        file.commit();
        if (sensorHourly) sensorHourly->commit();
    }
    timings.stop();
    reporter.line("wrote " + outputName(options.output) + " (per patch: annual sums)" +
                  (options.hourlyPath.empty() ? std::string() : " and " + options.hourlyPath + " (hours x patches, W/m^2)") +
                  (yo.sensors ? ", " + outputName(options.sensorOutputPath) + " (per sensor: annual sums)" : std::string()) +
                  (options.sensorHourlyPath.empty() ? std::string() : " and " + options.sensorHourlyPath + " (hours x sensors, W/m^2)"));
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
