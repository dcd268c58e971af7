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

namespace {

bool normalisedRecorded(const FormFactors& F) {
    const auto it = F.parameters.find("rows");
    return it != F.parameters.end() && it->second == "normalised to sum 1";
}

}  // namespace

PostProcessing pendingPostProcessing(const FormFactorPolicy& policy, const FormFactors& F) {
    PostProcessing steps;
    const std::optional<double> dropped = sparsifiedThreshold(F);
    if (policy.dropBelow > 0.0 && !(dropped && *dropped == policy.dropBelow)) steps.dropBelow = policy.dropBelow;
    else if (policy.enforceReciprocity && !F.parameters.count("reciprocity")) steps.enforceReciprocity = true;
    steps.normalizeRows =
        policy.normalizeRows && (steps.dropBelow > 0.0 || steps.enforceReciprocity || !normalisedRecorded(F));
    return steps;
}

std::string recordedPostProcessing(const FormFactors& F) {
    std::string text;
    auto add = [&](const std::string& line) { text += (text.empty() ? "" : "; ") + line; };
    if (const auto it = F.parameters.find("sparsified"); it != F.parameters.end()) add(it->second);
    if (const auto it = F.parameters.find("reciprocity"); it != F.parameters.end()) add("reciprocity " + it->second);
    if (normalisedRecorded(F)) add("rows normalised to sum 1");
    return text;
}

StoredFormFactorRule StoredFormFactorRule::computed(const std::string& path) {
    StoredFormFactorRule rule;
    rule.m_store = !path.empty();
    return rule;
}

StoredFormFactorRule StoredFormFactorRule::reused(const FormFactors& F, std::size_t rows, std::size_t missing,
                                                  const std::string& path) {
    StoredFormFactorRule rule;
    rule.m_store = true;
    const std::string steps = recordedPostProcessing(F);
    if (missing && !steps.empty()) {
        rule.m_lines.push_back("form factors: " + path + " lacks " + std::to_string(missing) +
                               " rows (patches that were black when it was computed) and was post-processed (" + steps +
                               "): computing F again whole, to be stored there");
        return rule;
    }
    rule.m_reuse = true;
    rule.m_lines.push_back("form factors: reused " + path + " (" + std::to_string(rows) +
                           " rows; scene geometry and mirrors unchanged)");
    if (!steps.empty())
        rule.m_lines.push_back("form factors: " + path + " holds F as post-processed when it was stored (" + steps +
                               "); steps it records are not applied again");
    if (missing)
        rule.m_lines.push_back("form factors: computing " + std::to_string(missing) +
                               " rows the file lacks (patches that were black when it was computed)");
    return rule;
}

void checkStoredFormFactors(const FormFactors& F, const Scene& scene, const MethodSettings& settings, bool otherSettings,
                            const std::string& path, Warnings& warnings) {
    checkFormFactorsMatch(F, scene.geometryHash(), scene.size(), path);
    if (!F.provenance.sceneHashKnown) {
        warnings.add("unverified F files", path + ": has no Hemirad scene hash; only its size (" +
                                               std::to_string(F.size()) + " patches) could be checked");
        return;  // nor settings: a foreign file
    }
    const auto made = F.parameters.find("settings");
    if (made == F.parameters.end()) {
        warnings.add("F files without their settings", path + ": records no form-factor settings (written before they were "
                                                              "recorded, or not by Hemirad): reused without comparing them");
        return;
    }
    const std::string difference = formFactorSettingsDifference(made->second, settings);
    if (difference.empty()) return;
    if (!otherSettings)
        throw Error(path + " was computed with other form-factor settings: " + difference +
                    "; compute F again with --recompute-ff, or reuse it as it is with --reuse-ff-anyway");
    warnings.add("F files reused with other settings",
                 path + " was computed with other form-factor settings: " + difference + "; reused as it is (--reuse-ff-anyway)");
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
    // A post-processed F cannot take new rows (StoredFormFactorRule): computed again whole.
    if (current.size() == scene.size() && !recordedPostProcessing(current).empty() && !missingRows(scene, &current).empty())
        current = FormFactors();
    const bool haveCurrent = current.size() == scene.size();
    const std::vector<PatchId> rows = missingRows(scene, haveCurrent ? &current : nullptr);
    FormFactorUpdate update;
    if (!rows.empty()) {
        // What the back end leaves to the scene and the machine (--estimator auto), decided once.
        std::string note;
        const MethodSettings method = resolveSettings(scene, m_policy.backend, rows, note);
        if (!note.empty()) message("form factors: " + note);
        if (m_policy.memoryCheck) checkFormFactorMemory(scene, method, rows);
        const BackendDescriptor& backend = findBackend(method.method);
        const double workPerRow = backend.workPerRow(scene, method);
        ProgressCallback progress =
            m_events.progress ? m_events.progress("form factors", workPerRow, backend.workUnit) : ProgressCallback{};
        FormFactorRun run = computeFormFactors(scene, method, rows, progress, m_events.cancel);
        // A reuse compares the settings asked for (auto stays auto; the estimator parameter says what ran).
        run.F.parameters["settings"] = formFactorSettingsText(m_policy.backend);
        timing("acceleration structure", run.prepareSeconds);
        timing("form factors", run.computeSeconds);
        timing("assemble F", run.assembleSeconds);
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
    } else if (haveCurrent) {
        update.F = std::move(current);
        refreshStats(scene, update);
    } else {
        // No row needed and none held (issue 35 #6, #18: an F of 0 x 0 could be neither solved nor read
        // back): N x N with the scene's hash, every row marked not computed.
        update.F = formFactorsWithoutRows(scene, m_policy.backend);
        update.changed = true;
        message(kNoRowsNeeded);
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
    const PostProcessing steps = pendingPostProcessing(m_policy, update.F);
    if (steps.enforceReciprocity || steps.dropBelow > 0.0) {
        // Dropping pairs ends with the same closure, toward the row sums from before.
        const auto t0 = Clock::now();
        const bool dropping = steps.dropBelow > 0.0;
        const std::string line = dropping ? describe(dropBelow(update.F, scene, steps.dropBelow))
                                          : describe(enforceReciprocity(update.F, scene));
        timing(dropping ? "drop below" : "enforce reciprocity", since(t0));
        message("form factors: " + line);
        refreshStats(scene, update, bool(m_events.formFactorsChanged));
        if (m_events.formFactorsChanged) m_events.formFactorsChanged(*update.stats, update.F.memoryBytes());
        update.changed = true;
    }
    if (steps.normalizeRows) {
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
    const bool exists = !path.empty() && !file.recompute && std::filesystem::exists(path);
    const bool sharded = !path.empty() && (file.sharded || isShardManifest(path));
    StoredFormFactorRule rule = StoredFormFactorRule::computed(path);
    FormFactors current;
    if (exists) {
        const auto t0 = Clock::now();
        current = loadFormFactors(path, scene.size());  // another N refused before it is allocated
        timing("load F", since(t0));
        checkStoredFormFactors(current, scene, m_policy.backend, file.otherSettings, path, warnings);
        rule = StoredFormFactorRule::reused(current, current.computedRows(), missingRows(scene, &current).size(), path);
        for (const std::string& line : rule.lines()) message(line);
        if (!rule.reuse()) current = FormFactors();
    }
    auto store = [&](const FormFactors& F) {
        const auto t0 = Clock::now();
        if (sharded) saveShardedFormFactors(F, path, 1);
        else saveFormFactors(F, path);
        timing("write F", since(t0));
        message(rule.reuse() ? "form factors: updated " + path : "form factors: stored in " + path);
    };
    FormFactorUpdate update = computeMissingRows(scene, std::move(current));
    if (rule.storeBeforePostProcessing(update.rowsComputed > 0)) store(update.F);
    postProcess(scene, update);
    if (rule.storeAfterPostProcessing()) store(update.F);
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
