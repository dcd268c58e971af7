// `hemirad solve SCENE.obj [--ff F] -o B.csv|B.ply`.
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "engine/object_table.hpp"
#include "engine/result_writer.hpp"
#include "engine/tone_map.hpp"
#include "engine/vertex_radiosity.hpp"


namespace hemirad {

void writeSolveOutput(const Options& options, const Scene& scene, const Radiosity& result, Timings& timings,
                      const Reporter& reporter, Warnings& warnings) {
    const std::string format = options.output.empty() ? "" : outputFormat(options);
    // Opt-in: a second F, over the two-sided scene (parseOptions makes --sky-view need -o).
    const std::vector<double> sky =
        options.skyView ? skyViewTotals(options, scene, timings, reporter, warnings) : std::vector<double>();
    if (format == "csv") {
        timings.start("write CSV");
        writeRadiosityCsv(options.output, scene, result.B, sky);
        timings.stop();
    } else if (format == "ply") {
        timings.start("vertex radiosity");
        const std::vector<Rgb> corner = cornerRadiosity(scene, result.B, options.crease);
        timings.start("write PLY");
        double exposure = options.exposure;
        if (exposure <= 0.0) {
            std::vector<double> lum;
            lum.reserve(scene.size());
            for (const Rgb& b : result.B) lum.push_back(luminance(b) / kPi);
            exposure = autoExposure(std::move(lum), 0.9, 0.85);
        }
        writeRadiosityPly(options.output, scene, corner, exposure, sky);
        timings.stop();
    }
    if (!options.objectsPath.empty()) {
        timings.start("write object table");
        writeObjectTable(options.objectsPath, summarizeObjects(scene, result.B), scene.unit);
        timings.stop();
    }
}

int runSolve(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const SolvedScene solved = solveFromOptions(options, timings, reporter, warnings);
    writeSolveOutput(options, solved.scene, solved.result, timings, reporter, warnings);
    if (!options.output.empty())
        reporter.line("wrote " + outputName(options.output) + (options.skyView ? " (with each patch's sky_view_factor)" : ""));
    if (!options.objectsPath.empty()) reporter.line("wrote " + outputName(options.objectsPath) + " (per object: area, B and H)");
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
