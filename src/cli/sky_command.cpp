// The sky on the command line, shared by `irradiance` and `year`: the isotropic sky's view factors
// (computed, or read from --svf FILE), --sky MODEL's daylight coefficients and one hour's sky
// from them.
#include "cli/sun_command.hpp"
#include "environment/sky_model.hpp"
#include "environment/sky_view.hpp"
#include "environment/weather.hpp"

#include <filesystem>
#include <sstream>

namespace hemirad {

Vec3 upFromOptions(const Options& options) { return options.upAxis == "z" ? Vec3(0, 0, 1) : Vec3(0, 1, 0); }

Vec3 northFromOptions(const Options& options) {
    return options.north ? *options.north : options.upAxis == "z" ? Vec3(0, 1, 0) : Vec3(0, 0, -1);
}

std::vector<double> directSkyViewFromOptions(const Scene& scene, const Options& options, Timings& timings, const Reporter& reporter) {
    const std::string& path = options.skyViewPath;
    if (!path.empty() && std::filesystem::exists(path)) {
        timings.start("read sky view factors");
        SkyView sky = readSkyViewCsv(path, scene);
        timings.stop();
        reporter.line("sky view factors: read from " + path + " (each patch's object, area, centroid and normal checked against the scene)");
        return std::move(sky.direct);
    }
    timings.start("sky view factors");
    const SkyView sky = skyViewFactors(scene, options.formFactors);
    timings.stop();
    if (!path.empty()) {
        timings.start("write sky view factors");
        writeSkyViewCsv(path, scene, sky);
        timings.stop();
        reporter.line("sky view factors (" + sky.method + "): stored in " + path + " for the next run");
    }
    return sky.direct;
}

SkyCoefficients skyCoefficientsFromOptions(const Scene& scene, const Options& options, Timings& timings, const Reporter& reporter) {
    timings.start("daylight coefficients");
    SkyCoefficients sky = skyCoefficients(scene, options.skySubdivision, options.skySamples, upFromOptions(options), northFromOptions(options));
    timings.stop();
    std::ostringstream line;
    line << "sky: " << parseSkyModel(options.skyModel).name() << ", " << sky.grid.size() << " cells ("
         << (options.skySubdivision == 1 ? std::string("Tregenza") : "Reinhart subdivision " + std::to_string(options.skySubdivision))
         << ") x " << options.skySamples * options.skySamples << " direction(s), each an exact shadow pass"
         << (scene.hasMirrors() ? " and the cells through mirrors (first reflections)" : "") << "; below the horizon is dark";
    reporter.line(line.str());
    return sky;
}

SkyConditions skyConditionsFromOptions(const Options& options, const Vec3& toSun) {
    SkyConditions c;
    c.toSun = sceneToSky(toSun, upFromOptions(options), northFromOptions(options));
    c.dni = options.dni ? *options.dni : 0.0;
    c.dhi = options.dhi;
    c.dayOfYear = dayOfYear(options.sunTime);
    return c;
}

void modelSkyHour(const SkyCoefficients& sky, const Options& options, const Vec3& toSun, IrradianceInputs& in, const Reporter& reporter) {
    const SkyConditions c = skyConditionsFromOptions(options, toSun);
    const SkyModel model = parseSkyModel(options.skyModel);
    if (model.kind == SkyModel::Kind::Perez && c.dhi > 0.0) {
        const PerezParameters p = perezParameters(c);
        std::ostringstream line;
        line.precision(4);
        line << "sky: Perez clearness " << p.epsilon << " (bin " << p.bin + 1 << " of 8), brightness " << p.delta
             << (p.clamped ? " (kept within the ranges the model was fitted over)" : "")
             << (c.dayOfYear > 0 ? "" : " (mean Sun-Earth distance: no date with --sun-direction)");
        reporter.line(line.str());
    }
    SkyHour hour = skyHour(sky, model, c);
    if (hour.uniformFallback)
        reporter.line("sky: Perez's sky is dark everywhere for this hour, even within its fitted ranges: the DHI comes from a uniform sky");
    in.directSky = std::move(hour.direct);
    in.reflectedSky = std::move(hour.mirrored);
}

}  // namespace hemirad
