// CLI pipeline stages: the library pipeline with the console reporter.
#include "cli/pipeline.hpp"

#include "engine/atomic_file.hpp"

namespace hemirad {

RadiosityPipeline makePipeline(const Options& options, Timings& timings, const Reporter& reporter) {
    FormFactorPolicy policy;
    policy.backend = options.formFactors;
    policy.allRows = options.allRows;
    policy.enforceReciprocity = options.enforceReciprocity;
    policy.dropBelow = options.dropBelow;
    policy.normalizeRows = options.normalizeRows;
    policy.memoryCheck = options.memoryCheck;
    PipelineEvents events;
    events.message = [&reporter](const std::string& text) { reporter.line(text); };
    events.timing = [&timings](const std::string& stage, double seconds) { timings.add(stage, seconds); };
    events.progress = [&reporter](const std::string& label, double workPerRow, const std::string& unit) {
        return reporter.progress(label, workPerRow, unit);
    };
    events.formFactorsComputed = [&reporter](const FormFactorRun& run, const Scene& scene, const MethodSettings& method) {
        reporter.formFactorSummary(run, scene, method);
    };
    events.formFactorsChanged = [&reporter](const FormFactorStats& stats, std::size_t bytes) {
        reporter.formFactorStats(stats, bytes);
    };
    return RadiosityPipeline(std::move(policy), std::move(events));
}

Scene loadScene(const Options& options, Timings& timings, const Reporter& reporter, Warnings& warnings) {
    return makePipeline(options, timings, reporter)
        .load(options.inputs.at(0), options.subdivide, warnings, {options.materials});
}

FormFactors obtainFormFactors(const Scene& scene, const Options& options, Timings& timings, const Reporter& reporter,
                              Warnings& warnings) {
    const RadiosityPipeline pipeline = makePipeline(options, timings, reporter);
    try {
        pipeline.checkBeforeComputing(scene);
    } catch (const Error& e) {
        throw UsageError(e.what());
    }
    StoredFormFactors file;
    file.path = options.ffPath;
    file.recompute = options.recomputeFf;
    file.otherSettings = options.reuseFfAnyway;
    file.sharded = options.shards;
    return pipeline.formFactorsWithFile(scene, file, warnings).F;
}

SolvedScene solveFromOptions(const Options& options, Timings& timings, const Reporter& reporter, Warnings& warnings) {
    SolvedScene solved;
    solved.scene = loadScene(options, timings, reporter, warnings);
    const FormFactors F = obtainFormFactors(solved.scene, options, timings, reporter, warnings);
    solved.result = makePipeline(options, timings, reporter).solve(solved.scene, F, options.solver);
    reporter.solveSummary(solved.result);
    return solved;
}

FormFactorFormat formFactorOutputFormat(const Options& options) {
    return outputFormat(options) == "hff" ? FormFactorFormat::Hff : FormFactorFormat::Mtx;
}

std::string outputName(const std::string& path) { return isStandardOutput(path) ? "standard output" : path; }

}  // namespace hemirad
