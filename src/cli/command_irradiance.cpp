// `hemirad irradiance SCENE (sun) --dni W --dhi W -o E.csv`: one hour of sun and isotropic sky, the
// direct, sky and reflected irradiance per patch (src/environment).
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "cli/sun_command.hpp"
#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "environment/irradiance.hpp"
#include "environment/sky_view.hpp"
#include "environment/sunlit.hpp"

#include <iomanip>
#include <limits>
#include <sstream>

namespace hemirad {

int runIrradiance(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const Scene scene = loadScene(options, timings, reporter, warnings);
    double metres = 1.0;
    if (!scene.unit.empty()) metres = metresPerUnit(scene.unit);
    else if (!options.lengthUnit.empty()) metres = metresPerUnit(options.lengthUnit);
    else warnings.add("unit", "the scene states no length unit: lengths are taken as metres (give --unit)");
    const Vec3 toSun = sunDirectionFromOptions(options, reporter);

    timings.start("sunlit fractions");
    IrradianceInputs in;
    in.directSun = directIrradiance(scene, toSun, *options.dni, sunlitFractions(scene, toSun));
    timings.start("sky view factors");
    in.skyView = skyViewFactors(scene, options.formFactors).direct;
    timings.stop();
    in.dhi = options.dhi;
    Options withRows = options;
    withRows.allRows = true;
    const FormFactors F = obtainFormFactors(scene, withRows, timings, reporter, warnings);
    timings.start("inter-reflection");
    const IrradianceResult r = solarIrradiance(scene, F, in, metres, options.solver);
    timings.stop();
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
    out << "patch,object,direct_sun (W/m^2),direct_sky (W/m^2),reflected (W/m^2),total (W/m^2),absorbed (W/m^2)\n";
    for (PatchId i = 0; i < scene.size(); ++i) {
        const std::string name = csvField(scene.objects[scene.patches[i].object]);
        out << i << ',' << name << ',' << r.directSun[i] << ',' << r.directSky[i] << ',' << r.reflected[i] << ',' << r.total[i]
            << ',' << r.absorbed[i] << '\n';
    }
    file.commit();
    timings.stop();
    reporter.line("wrote " + outputName(options.output) + " (per patch: direct sun, direct sky, reflected, total, absorbed)");
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
