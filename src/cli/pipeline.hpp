// The CLI's side of the library pipeline: Options -> RadiosityPipeline, its events -> the Reporter.
#pragma once

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/warnings.hpp"
#include "pipeline/radiosity_pipeline.hpp"

namespace hemirad {

/// The pipeline for these options, reporting through `reporter` and timing into `timings`.
RadiosityPipeline makePipeline(const Options& options, Timings& timings, const Reporter& reporter);

/// Loads the scene named by options.inputs[0] (OBJ or STL, --materials by object name) and
/// subdivides it when --subdivide is given.
Scene loadScene(const Options& options, Timings& timings, const Reporter& reporter, Warnings& warnings);

/// Computes F for the rows a solve needs (all rows with --all-rows), or reuses --ff FILE when its
/// scene hash matches (computing only rows it lacks); creates FILE when absent. Applies
/// --enforce-reciprocity and --normalize-rows. Throws hemirad::Error when FILE belongs to another
/// scene, UsageError for a policy the scene cannot take (checked before any row is computed).
FormFactors obtainFormFactors(const Scene& scene, const Options& options, Timings& timings,
                              const Reporter& reporter, Warnings& warnings);

/// The scene and its radiosity, as solve and render make them: loaded, F obtained (obtainFormFactors;
/// released once B is solved), solved and reported.
struct SolvedScene {
    Scene scene;
    Radiosity result;
};
SolvedScene solveFromOptions(const Options& options, Timings& timings, const Reporter& reporter, Warnings& warnings);

/// The F format formfactors -o writes (outputFormat: the extension's, or --format's for -o -).
FormFactorFormat formFactorOutputFormat(const Options& options);
/// "standard output" for "-", else the path: for "wrote ..." lines.
std::string outputName(const std::string& path);

/// The sky view factor of every patch (direct + through mirrors, 0..1), as `sky-view` computes it with
/// the run's method settings: a second F, over the scene made two-sided. Timed and reported; a mirror
/// chain cut off by --max-depth is warned. Throws hemirad::Error as skyViewFactors does.
std::vector<double> skyViewTotals(const Options& options, const Scene& scene, Timings& timings, const Reporter& reporter,
                                  Warnings& warnings);

/// Writes B as solve -o asks (CSV per patch, or PLY with vertex radiosity; --sky-view adds each
/// patch's sky view factor, skyViewTotals); nothing without -o.
void writeSolveOutput(const Options& options, const Scene& scene, const Radiosity& result, Timings& timings,
                      const Reporter& reporter, Warnings& warnings);
/// Vertex radiosity, the camera-ray image and its PNG, as render -o asks.
void writeRenderOutput(const Options& options, const Scene& scene, const Radiosity& result, Timings& timings,
                       const Reporter& reporter);

}  // namespace hemirad
