// `hemirad irradiance SCENE (sun) --dni W --dhi W [--sky MODEL] -o E.csv`: one hour of sun and sky, the
// direct, sky and reflected irradiance per patch (src/environment).
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "cli/sun_command.hpp"
#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "environment/irradiance.hpp"

#include <iomanip>
#include <limits>
#include <sstream>

namespace hemirad {

int runIrradiance(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const Scene scene = loadScene(options, timings, reporter, warnings);
    const double metres = metresFromOptions(scene, options, warnings);
    const Vec3 toSun = sunDirectionFromOptions(options, reporter);
    const IrradianceResult r = patchHour(scene, options, toSun, metres, timings, reporter, warnings);
    std::ostringstream line;
    line.precision(6);
    line << "irradiance: " << r.incidentPower << " W arrive (sun and sky), " << r.absorbedPower << " W absorbed, "
         << r.escapedPower << " W leave; balance " << std::setprecision(3) << r.balance << " (" << r.report.solver
         << ", relative residual " << r.report.residualOriginal << ")";
    reporter.line(line.str());

    timings.start("write CSV");
    AtomicFile file(options.output, false);
    std::ostream& out = file.stream();
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    const bool mirrors = scene.hasMirrors();  // then a column for the sun they reflect (and a sky model's sky)
    const bool skyThrough = mirrors && options.skyModel != "isotropic";
    out << "patch,object,direct_sun (W/m^2),direct_sky (W/m^2),reflected (W/m^2),total (W/m^2),absorbed (W/m^2)"
        << (mirrors ? ",reflected_sun (W/m^2)" : "") << (skyThrough ? ",reflected_sky (W/m^2)" : "") << "\n";
    for (PatchId i = 0; i < scene.size(); ++i) {
        const std::string name = csvField(scene.objects[scene.patches[i].object]);
        out << i << ',' << name << ',' << r.directSun[i] << ',' << r.directSky[i] << ',' << r.reflected[i] << ',' << r.total[i]
            << ',' << r.absorbed[i];
        if (mirrors) out << ',' << r.reflectedSun[i];
        if (skyThrough) out << ',' << r.reflectedSky[i];
        out << '\n';
    }
    file.commit();
    timings.stop();
    reporter.line("wrote " + outputName(options.output) + " (per patch: direct sun, direct sky, reflected, total, absorbed)");
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
