// `hemirad sun SCENE (--sun-direction x,y,z | --sun-time T --latitude LAT --longitude LON) [--dni W]
// -o SUN.csv`: the direct sun per patch (src/environment).
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "cli/sun_command.hpp"
#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "environment/irradiance.hpp"
#include "environment/reflected_sun.hpp"
#include "environment/solar_position.hpp"
#include "environment/sunlit.hpp"

#include <iomanip>
#include <limits>
#include <sstream>

namespace hemirad {

Vec3 sunDirectionFromOptions(const Options& options, const Reporter& reporter) {
    Vec3 toSun;
    std::ostringstream where;
    where.precision(6);
    if (options.sunDirectionVector) {
        toSun = options.sunDirectionVector->normalized();
        where << "sun: direction " << toSun.transpose() << " (given)";
    } else {
        const SolarPosition p = solarPosition(options.sunTime, *options.latitude, *options.longitude);
        toSun = sunDirection(p, upFromOptions(options), northFromOptions(options));
        where << "sun: elevation " << p.elevation << " deg, azimuth " << p.azimuth << " deg from north (Michalsky 1988) at "
              << options.sunTime << ", latitude " << *options.latitude << ", longitude " << *options.longitude
              << "; direction " << toSun.transpose();
    }
    reporter.line(where.str());
    return toSun;
}

bool sunBelowHorizon(const Options& options) {
    if (options.sunDirectionVector) return false;  // a direction given is taken as it is
    return !(solarPosition(options.sunTime, *options.latitude, *options.longitude).elevation > 0.0);
}

double metresFromOptions(const Scene& scene, const Options& options, Warnings& warnings) {
    if (!scene.unit.empty()) return metresPerUnit(scene.unit);
    if (!options.lengthUnit.empty()) return metresPerUnit(options.lengthUnit);
    warnings.add("unit", "the scene states no length unit: lengths are taken as metres (give --unit)");
    return 1.0;
}

IrradianceResult patchHour(const Scene& scene, const Options& options, const Vec3& toSun, double metres, Timings& timings,
                           const Reporter& reporter, Warnings& warnings) {
    // The Earth hides a sun below the horizon: no direct sun, nothing for the mirrors to reflect.
    const bool night = sunBelowHorizon(options);
    if (night) reporter.line("sun: below the horizon at " + options.sunTime + ": no direct sun (the sky alone)");
    timings.start("shadow set-up");
    const BeamShadows shadows(scene);
    timings.start("sunlit fractions");
    IrradianceInputs in;
    in.directSun = night ? std::vector<double>(scene.size(), 0.0)
                         : directIrradiance(scene, toSun, *options.dni, shadows.sunlitFractions(toSun));
    in.dhi = options.dhi;
    if (options.skyModel == "isotropic") {
        in.skyView = directSkyViewFromOptions(scene, options, timings, reporter);
    } else {
        modelSkyHour(skyCoefficientsFromOptions(scene, options, timings, reporter), options, toSun, in, reporter);
    }
    if (scene.hasMirrors() && !night) {
        timings.start("reflected sun");
        in.reflectedSun = reflectedSun(shadows, toSun, *options.dni).irradiance;
        timings.stop();
    }
    Options withRows = options;
    withRows.allRows = true;
    const FormFactors F = obtainFormFactors(scene, withRows, timings, reporter, warnings);
    timings.start("inter-reflection");
    IrradianceResult r = solarIrradiance(scene, F, in, metres, options.solver);
    timings.stop();
    return r;
}

int runSun(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const Scene scene = loadScene(options, timings, reporter, warnings);
    const Vec3 toSun = sunDirectionFromOptions(options, reporter);
    const bool night = sunBelowHorizon(options);
    if (night) reporter.line("sun: below the horizon at " + options.sunTime + ": no patch is sunlit");
    timings.start("shadow set-up");
    const BeamShadows shadows(scene);
    timings.start("sunlit fractions");
    const std::vector<double> lit = night ? std::vector<double>(scene.size(), 0.0) : shadows.sunlitFractions(toSun);
    timings.stop();
    double area = 0.0, litArea = 0.0;
    for (PatchId i = 0; i < scene.size(); ++i) {
        area += scene.patches[i].area;
        litArea += scene.patches[i].area * lit[i];
    }
    std::ostringstream summary;
    summary.precision(6);
    summary << "sunlit: " << (area > 0 ? litArea / area : 0.0) << " of the area (exact shadow polygons)";
    reporter.line(summary.str());
    // The sun's first reflections by mirrors, with --dni: a column, and the hot spots with --glare.
    const bool mirrored = options.dni && scene.hasMirrors();
    ReflectedSun reflected;
    reflected.irradiance.assign(scene.size(), 0.0);
    if (mirrored && !night) {
        timings.start("reflected sun");
        reflected = reflectedSun(shadows, toSun, *options.dni);
        timings.stop();
        std::ostringstream line;
        line.precision(4);
        line << "reflected sun: " << reflected.mirrorsLit << " mirror(s) in the sun reach " << reflected.spots.size()
             << " (mirror, receiver) pair(s), exact footprints (first reflections)";
        if (!reflected.spots.empty())
            line << "; the brightest: mirror " << reflected.spots[0].mirror << " on patch " << reflected.spots[0].receiver << ", "
                 << reflected.spots[0].peak << " W/m^2 over " << reflected.spots[0].litArea << " of its area";
        reporter.line(line.str());
    }
    if (!options.glarePath.empty()) {
        if (!mirrored) warnings.add("glare", "the scene has no mirror (s > 0): --glare " + options.glarePath + " lists no spot");
        writeGlareCsv(options.glarePath, scene, reflected);
    }

    timings.start("write CSV");
    AtomicFile file(options.output, false);
    std::ostream& out = file.stream();
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    const std::string unit = scene.unit.empty() ? "" : " (" + scene.unit + "^2)";
    out << "patch,object,area" << unit << ",cos_incidence,sunlit_fraction" << (options.dni ? ",direct_irradiance (W/m^2)" : "")
        << (mirrored ? ",reflected_sun (W/m^2)" : "") << "\n";
    const std::vector<double> E = options.dni ? directIrradiance(scene, toSun, *options.dni, lit) : std::vector<double>();
    for (PatchId i = 0; i < scene.size(); ++i) {
        const std::string name = csvField(scene.objects[scene.patches[i].object]);
        out << i << ',' << name << ',' << scene.patches[i].area << ',' << std::max(0.0, scene.patches[i].normal.dot(toSun)) << ','
            << lit[i];
        if (options.dni) out << ',' << E[i];
        if (mirrored) out << ',' << reflected.irradiance[i];
        out << '\n';
    }
    file.commit();
    timings.stop();
    reporter.line("wrote " + outputName(options.output) + " (per patch: cos of incidence, sunlit fraction" +
                  (options.dni ? std::string(", direct irradiance") : std::string()) +
                  (mirrored ? std::string(", the sun reflected by mirrors") : std::string()) + ")" +
                  (options.glarePath.empty() ? std::string() : " and " + outputName(options.glarePath) + " (reflected-sun spots)"));
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
