// The stages shared by the CLI commands: load (+ subdivide), obtain F (compute or reuse), solve.
#pragma once

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "engine/warnings.hpp"

namespace hemirad {

/// Loads the scene named by options.inputs[0] and subdivides it when --subdivide is given.
Scene loadScene(const Options& options, Timings& timings, const Reporter& reporter, Warnings& warnings);

/// Computes F for the rows a solve needs (all rows with --all-rows), or reuses --ff FILE when its
/// scene hash matches (computing only rows it lacks); creates FILE when absent. Applies
/// --enforce-reciprocity. Throws hemirad::Error when FILE belongs to another scene.
FormFactors obtainFormFactors(const Scene& scene, const Options& options, Timings& timings,
                              const Reporter& reporter, Warnings& warnings);

/// Solves and reports.
Radiosity solveScene(const Scene& scene, const FormFactors& F, const Options& options, Timings& timings,
                     const Reporter& reporter);

}  // namespace hemirad
