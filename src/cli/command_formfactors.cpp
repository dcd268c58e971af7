// `hemirad formfactors SCENE.obj -o F.hff|F.mtx`.
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/form_factor_shards.hpp"

#include <iostream>

namespace hemirad {

int runFormFactors(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const Scene scene = loadScene(options, timings, reporter, warnings);
    Options computeOnly = options;
    computeOnly.ffPath.clear();
    const FormFactors F = obtainFormFactors(scene, computeOnly, timings, reporter, warnings);
    timings.start("write F");
    if (options.shards) saveShardedFormFactors(F, options.output, 1);
    else saveFormFactors(F, options.output, formFactorOutputFormat(options));
    timings.stop();
    reporter.line("wrote " + outputName(options.output) + (options.shards ? " (a shard manifest and 1 shard; " : " (") +
                  "scene hash " + hexHash(F.sceneHash) + ")");
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
