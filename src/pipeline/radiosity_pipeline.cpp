// The radiosity pipeline: one code path for reuse, merge, memory check and post-processing of F.
#include "pipeline/radiosity_pipeline.hpp"

#include "engine/error.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/form_factor_shards.hpp"
#include "engine/reciprocal_closure.hpp"
#include "engine/subdivide.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <sstream>

namespace hemirad {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

void mergeAddedRows(FormFactors& current, const FormFactors& added, std::size_t rows, const Scene& scene,
                    const MethodSettings& method) {
    const FormFactorProvenance provenance = added.provenance;
    current.replaceRows(added);
    current.provenance.rowSumBound = std::max(current.provenance.rowSumBound, provenance.rowSumBound);
    current.parameters["rows_added"] = std::to_string(rows) + " with " + provenance.method + ", " +
                                       findBackend(method.method).describe(scene, method).settings;
}

RadiosityPipeline::RadiosityPipeline(FormFactorPolicy policy, PipelineEvents events)
    : m_policy(std::move(policy)), m_events(std::move(events)) {}

void RadiosityPipeline::message(const std::string& text) const {
    if (m_events.message) m_events.message(text);
}

void RadiosityPipeline::timing(const std::string& stage, double seconds) const {
    if (m_events.timing) m_events.timing(stage, seconds);
}

Scene RadiosityPipeline::load(const std::string& path, double subdivideEdge, Warnings& warnings,
                              const SceneLoadOptions& loading) const {
    auto t0 = Clock::now();
    Scene scene = loadScene(path, warnings, loading);
    timing("load scene", since(t0));
    std::ostringstream out;
    out << "scene: " << path << ", " << scene.size() << " patches, " << scene.vertices.size() << " vertices"
        << (scene.hasMirrors() ? ", with mirrors" : "")
        << (loading.materials.empty() ? "" : ", materials by object name from " + loading.materials);
    if (subdivideEdge > 0) {
        t0 = Clock::now();
        scene = subdivide(scene, subdivideEdge);
        timing("subdivide", since(t0));
        out << "; subdivided to " << scene.size() << " patches (edges <= " << subdivideEdge << ")";
    }
    message(out.str());
    return scene;
}

std::vector<PatchId> RadiosityPipeline::missingRows(const Scene& scene, const FormFactors* current) const {
    std::vector<PatchId> rows = neededRows(scene, m_policy.allRows);
    if (!current || current->size() != scene.size()) return rows;
    std::vector<PatchId> missing;
    for (PatchId i : rows)
        if (!current->rowComputed(i)) missing.push_back(i);
    return missing;
}

void RadiosityPipeline::checkBeforeComputing(const Scene& scene) const {
    if (m_policy.normalizeRows && scene.hasMirrors())
        throw Error("--normalize-rows: rows of extended form factors (mirrors) need not sum to 1; the scene has mirrors");
    const BackendDescriptor& backend = findBackend(m_policy.backend.method);
    if (backend.validate) backend.validate(m_policy.backend);
}

FormFactorUpdate RadiosityPipeline::computeMissingRows(const Scene& scene, FormFactors current) const {
    const bool haveCurrent = current.size() == scene.size();
    const std::vector<PatchId> rows = missingRows(scene, haveCurrent ? &current : nullptr);
    FormFactorUpdate update;
    if (!rows.empty()) {
        const MethodSettings& method = m_policy.backend;
        if (m_policy.memoryCheck) checkFormFactorMemory(scene, method, rows);
        const BackendDescriptor& backend = findBackend(method.method);
        const double workPerRow = backend.workPerRow(scene, method);
        ProgressCallback progress =
            m_events.progress ? m_events.progress("form factors", workPerRow, backend.workUnit) : ProgressCallback{};
        FormFactorRun run = computeFormFactors(scene, method, rows, progress, m_events.cancel);
        timing("acceleration structure", run.prepareSeconds);
        timing("form factors", run.computeSeconds);
        timing("F diagnostics", run.statsSeconds);
        if (m_events.formFactorsComputed) m_events.formFactorsComputed(run, scene, method);
        update.rowsComputed = rows.size();
        update.changed = true;
        if (haveCurrent) {
            mergeAddedRows(current, run.F, rows.size(), scene, method);
            update.F = std::move(current);
            refreshStats(scene, update);
        } else {
            update.F = std::move(run.F);
            update.stats = run.stats;
        }
    } else {
        update.F = std::move(current);
        refreshStats(scene, update);
    }
    return update;
}

void RadiosityPipeline::refreshStats(const Scene& scene, FormFactorUpdate& update, bool needed) const {
    if (!m_policy.statistics && !needed) return;
    const auto t0 = Clock::now();
    update.stats = computeStats(update.F, scene);
    timing("F diagnostics", since(t0));
}

void RadiosityPipeline::postProcess(const Scene& scene, FormFactorUpdate& update) const {
    if (m_policy.enforceReciprocity || m_policy.dropBelow > 0.0) {
        // Dropping pairs ends with the same closure, toward the row sums from before.
        const auto t0 = Clock::now();
        const bool dropping = m_policy.dropBelow > 0.0;
        const std::string line = dropping ? describe(dropBelow(update.F, scene, m_policy.dropBelow))
                                          : describe(enforceReciprocity(update.F, scene));
        timing(dropping ? "drop below" : "enforce reciprocity", since(t0));
        message("form factors: " + line);
        refreshStats(scene, update, bool(m_events.formFactorsChanged));
        if (m_events.formFactorsChanged) m_events.formFactorsChanged(*update.stats, update.F.memoryBytes());
        update.changed = true;
    }
    if (m_policy.normalizeRows) {
        const double worst = normalizeRows(update.F);
        message("form factors: rows normalised to sum 1 (largest correction " + std::to_string(worst) + ")");
        refreshStats(scene, update);
        update.changed = true;
    }
}

FormFactorUpdate RadiosityPipeline::updateFormFactors(const Scene& scene, FormFactors current) const {
    checkBeforeComputing(scene);
    FormFactorUpdate update = computeMissingRows(scene, std::move(current));
    postProcess(scene, update);
    return update;
}

FormFactorUpdate RadiosityPipeline::formFactorsWithFile(const Scene& scene, const StoredFormFactors& file,
                                                        Warnings& warnings) const {
    checkBeforeComputing(scene);
    const std::string& path = file.path;
    const bool reuse = !path.empty() && !file.recompute && std::filesystem::exists(path);
    const bool sharded = !path.empty() && (file.sharded || isShardManifest(path));
    FormFactors current;
    if (reuse) {
        const auto t0 = Clock::now();
        current = loadFormFactors(path, scene.size());  // another N refused before it is allocated
        timing("load F", since(t0));
        checkFormFactorsMatch(current, scene.geometryHash(), scene.size(), path);
        if (!current.provenance.sceneHashKnown)
            warnings.add("unverified F files", path + ": has no Hemirad scene hash; only its size (" +
                                                   std::to_string(current.size()) + " patches) could be checked");
        message("form factors: reused " + path + " (" + std::to_string(current.computedRows()) +
                " rows; scene geometry and mirrors unchanged)");
        const std::size_t missing = missingRows(scene, &current).size();
        if (missing)
            message("form factors: computing " + std::to_string(missing) +
                    " rows the file lacks (patches that were black when it was computed)");
    }
    auto store = [&](const FormFactors& F) {
        const auto t0 = Clock::now();
        if (sharded) saveShardedFormFactors(F, path, 1);
        else saveFormFactors(F, path);
        timing("write F", since(t0));
        message(reuse ? "form factors: updated " + path : "form factors: stored in " + path);
    };
    FormFactorUpdate update = computeMissingRows(scene, std::move(current));
    // A reused file gains the rows it lacked and stays as computed: post-processing is applied
    // after loading, each time. A new file stores F as post-processed.
    if (reuse && update.rowsComputed) store(update.F);
    postProcess(scene, update);
    if (!path.empty() && !reuse) store(update.F);
    return update;
}

Radiosity RadiosityPipeline::solve(const Scene& scene, const FormFactors& F, SolverOptions solver,
                                   const std::vector<Rgb>* initial) const {
    if (solver.solver == "auto") solver.solver = chooseSolver(scene.size(), scene);
    const auto t0 = Clock::now();
    Radiosity result = solveRadiosity(scene, F, solver, initial && initial->size() == scene.size() ? initial : nullptr);
    timing("solve (" + solver.solver + ")", since(t0));
    return result;
}

}  // namespace hemirad
