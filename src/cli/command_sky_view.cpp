// `hemirad sky-view SCENE -o SVF.csv`: the sky view factor of every patch (src/environment); the same
// values for solve --sky-view and render --false-color sky_view_factor.
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "environment/sky_view.hpp"

#include <algorithm>
#include <sstream>

namespace hemirad {

namespace {

/// The report line (area-weighted mean, min, max; the largest part through mirrors) and the warning
/// for mirror chains cut off by --max-depth.
void reportSkyView(const Scene& scene, const SkyView& sky, const std::vector<double>& total, const Reporter& reporter,
                   Warnings& warnings) {
    double area = 0.0, weighted = 0.0;
    for (PatchId i = 0; i < scene.size(); ++i) {
        area += scene.patches[i].area;
        weighted += scene.patches[i].area * total[i];
    }
    std::ostringstream line;
    line.precision(6);
    line << "sky view factor (" << sky.method << "): area-weighted mean " << (area > 0 ? weighted / area : 0.0) << ", min "
         << (total.empty() ? 0.0 : *std::min_element(total.begin(), total.end())) << ", max "
         << (total.empty() ? 0.0 : *std::max_element(total.begin(), total.end()));
    if (!sky.mirrored.empty()) line << "; through mirrors up to " << *std::max_element(sky.mirrored.begin(), sky.mirrored.end());
    reporter.line(line.str());
    if (sky.cutoffWeight > 0.0) {
        std::ostringstream cut;
        cut << "mirror chains cut off by --max-depth carried " << sky.cutoffWeight << " (counted as sky)";
        warnings.add("mirror depth", cut.str());
    }
}

/// The sky view factors with the run's method settings, timed and reported.
SkyView measuredSkyView(const Options& options, const Scene& scene, Timings& timings, const Reporter& reporter,
                        Warnings& warnings) {
    timings.start("sky view factors");
    const SkyView sky = skyViewFactors(scene, options.formFactors);
    timings.stop();
    reportSkyView(scene, sky, sky.total(), reporter, warnings);
    return sky;
}

}  // namespace

std::vector<double> skyViewTotals(const Options& options, const Scene& scene, Timings& timings, const Reporter& reporter,
                                  Warnings& warnings) {
    return measuredSkyView(options, scene, timings, reporter, warnings).total();
}

int runSkyView(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const Scene scene = loadScene(options, timings, reporter, warnings);
    const SkyView sky = measuredSkyView(options, scene, timings, reporter, warnings);
    timings.start("write CSV");
    writeSkyViewCsv(options.output, scene, sky);
    timings.stop();
    reporter.line("wrote " + outputName(options.output) + " (per patch: sky view factor, direct and through mirrors)");
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
