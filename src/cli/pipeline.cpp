// CLI pipeline stages.
#include "cli/pipeline.hpp"

#include "engine/form_factor_file.hpp"
#include "engine/obj_loader.hpp"
#include "engine/subdivide.hpp"

#include <filesystem>
#include <sstream>

namespace hemirad {

Scene loadScene(const Options& options, Timings& timings, const Reporter& reporter, Warnings& warnings) {
    timings.start("load scene");
    Scene scene = loadObj(options.inputs.at(0), warnings);
    timings.stop();
    std::ostringstream out;
    out << "scene: " << options.inputs[0] << ", " << scene.size() << " patches, " << scene.vertices.size()
        << " vertices" << (scene.hasMirrors() ? ", with mirrors" : "");
    if (options.subdivide > 0) {
        timings.start("subdivide");
        scene = subdivide(scene, options.subdivide);
        timings.stop();
        out << "; subdivided to " << scene.size() << " patches (edges <= " << options.subdivide << ")";
    }
    reporter.line(out.str());
    return scene;
}

namespace {

FormFactorRun compute(const Scene& scene, const Options& options, const std::vector<PatchId>& rows, Timings& timings,
                      const Reporter& reporter) {
    if (options.memoryCheck) checkFormFactorMemory(scene, options.formFactors, rows);
    const double raysPerRow = expectedWorkPerRow(scene, options.formFactors);
    FormFactorRun run = computeFormFactors(scene, options.formFactors, rows,
                                           reporter.progress("form factors", raysPerRow, findBackend(options.formFactors.method).workUnit));
    timings.add("acceleration structure", run.prepareSeconds);
    timings.add("form factors", run.computeSeconds);
    timings.add("F diagnostics", run.statsSeconds);
    reporter.formFactorSummary(run, scene, options.formFactors);
    return run;
}

}  // namespace

FormFactors obtainFormFactors(const Scene& scene, const Options& options, Timings& timings, const Reporter& reporter,
                              Warnings& warnings) {
    const std::vector<PatchId> needed = neededRows(scene, options.allRows);
    FormFactors F;
    const bool reuse = !options.ffPath.empty() && !options.recomputeFf && std::filesystem::exists(options.ffPath);
    if (reuse) {
        timings.start("load F");
        F = loadFormFactors(options.ffPath);
        timings.stop();
        checkFormFactorsMatch(F, scene.geometryHash(), scene.size(), options.ffPath);
        if (F.parameters.count("scene_hash"))
            warnings.add("unverified F files", options.ffPath + ": has no Hemirad scene hash; only its size (" +
                                                   std::to_string(F.size()) + " patches) could be checked");
        std::vector<PatchId> missing;
        for (PatchId i : needed)
            if (!F.rowComputed(i)) missing.push_back(i);
        reporter.line("form factors: reused " + options.ffPath + " (" + std::to_string(F.computedRows()) +
                      " rows; scene geometry and mirrors unchanged)");
        if (!missing.empty()) {
            reporter.line("form factors: computing " + std::to_string(missing.size()) +
                          " rows the file lacks (patches that were black when it was computed)");
            FormFactorRun run = compute(scene, options, missing, timings, reporter);
            F.replaceRows(run.F);
            F.parameters["rows_added"] = std::to_string(missing.size()) + " with " + run.F.parameters["method"] +
                                         " samples=" + run.F.parameters["samples"] + " origins=" +
                                         run.F.parameters["origins"];
            timings.start("write F");
            saveFormFactors(F, options.ffPath);
            timings.stop();
            reporter.line("form factors: updated " + options.ffPath);
        }
    } else {
        F = compute(scene, options, needed, timings, reporter).F;
    }
    if (options.enforceReciprocity) {
        timings.start("enforce reciprocity");
        const std::size_t changed = enforceReciprocity(F, scene);
        timings.stop();
        reporter.line("form factors: reciprocity enforced: " + std::to_string(changed) +
                      " entries replaced by the pair's area-weighted mean (A_i F_ij + A_j F_ji) / 2");
        reporter.formFactorStats(computeStats(F, scene), F.memoryBytes());
    }
    if (options.normalizeRows) {
        if (scene.hasMirrors())
            throw UsageError("--normalize-rows: rows of extended form factors (mirrors) need not sum to 1");
        const double worst = normalizeRows(F);
        reporter.line("form factors: rows normalised to sum 1 (largest correction " + std::to_string(worst) + ")");
    }
    if (!options.ffPath.empty() && !reuse) {
        timings.start("write F");
        saveFormFactors(F, options.ffPath);
        timings.stop();
        reporter.line("form factors: stored in " + options.ffPath);
    }
    return F;
}

Radiosity solveScene(const Scene& scene, const FormFactors& F, const Options& options, Timings& timings,
                     const Reporter& reporter) {
    const SolverKind kind = options.solver.kind == SolverKind::Auto ? chooseSolver(scene.size(), scene) : options.solver.kind;
    timings.start("solve (" + solverName(kind) + ")");
    SolverOptions solverOptions = options.solver;
    solverOptions.kind = kind;
    Radiosity result = solveRadiosity(scene, F, solverOptions);
    timings.stop();
    reporter.solveSummary(result);
    return result;
}

}  // namespace hemirad
