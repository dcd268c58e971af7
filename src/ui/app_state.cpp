// hemirad-gui application state: loading, selection, undoable material edits, the worker job.
#include "ui/app_state.hpp"

#include "engine/error.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/obj_loader.hpp"
#include "engine/obj_writer.hpp"
#include "engine/result_writer.hpp"
#include "engine/scene_loader.hpp"
#include "engine/subdivide.hpp"
#include "engine/tone_map.hpp"
#include "engine/vertex_radiosity.hpp"
#include "pipeline/radiosity_pipeline.hpp"
#include "preprocess/form_factor_job.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <sstream>

namespace hemirad::ui {

using Clock = std::chrono::steady_clock;

/// One background computation: optional form factors (all missing rows), then the solve. It works on
/// copies, so the user may keep editing; results are applied by poll() on the UI thread.
struct AppState::Job {
    std::thread thread;
    std::atomic<bool> cancel{false};
    std::atomic<bool> finished{false};
    mutable std::mutex mutex;
    JobStatus status;
    Clock::time_point start = Clock::now();

    // Inputs.
    Scene scene;
    std::shared_ptr<const FormFactors> F;
    bool computeF = false;
    PipelineSettings settings;
    std::vector<Rgb> warmStart;
    std::uint64_t materialsRevision = 0;

    // Outputs.
    std::shared_ptr<const FormFactors> newF;
    std::optional<FormFactorStats> stats;
    double workPerSecond = 0.0;  ///< rays (or pixels) per second of the rows computed, 0 if none
    Radiosity result;
    std::string error;
    // Intermediate radiosity of a running solve (progressive display), newest only.
    std::vector<Rgb> intermediate;
    bool hasIntermediate = false;
    Clock::time_point lastIntermediate;
    std::vector<std::string> messages;
    std::vector<std::pair<std::string, double>> timings;

    void setStage(const std::string& stage, double progress) {
        std::lock_guard<std::mutex> lock(mutex);
        status.stage = stage;
        status.progress = progress;
    }

    /// The library pipeline with this job's settings; its events land in the job's status and log.
    RadiosityPipeline pipeline() {
        FormFactorPolicy policy;
        policy.backend = settings.formFactors;
        policy.statistics = true;  // the pipeline panel shows them
        PipelineEvents events;
        events.cancel = &cancel;
        events.timing = [this](const std::string& stage, double seconds) { timings.emplace_back(stage, seconds); };
        events.message = [this](const std::string& text) { messages.push_back(text); };
        events.progress = [this](const std::string& label, double, const std::string&) -> ProgressCallback {
            setStage(label, 0.0);
            return [this, label](std::size_t done, std::size_t total, double) {
                setStage(label, total ? double(done) / double(total) : 1.0);
            };
        };
        events.formFactorsComputed = [this](const FormFactorRun& run, const Scene& s, const MethodSettings& method) {
            std::ostringstream msg;
            msg << "form factors: " << method.method << ", " << findBackend(method.method).describe(s, method).settings
                << ", " << run.rowsComputed << " rows in " << run.computeSeconds << " s; row sums " << run.stats.rowSumMin
                << ".." << run.stats.rowSumMax << ", reciprocity (mean) " << run.stats.reciprocityMean << ", lost "
                << (run.rowsComputed ? 100.0 * run.counts.lostWeight / double(run.rowsComputed) : 0.0) << "%";
            messages.push_back(msg.str());
            if (run.rowsComputed > 0 && run.computeSeconds > 0.0)
                workPerSecond = double(run.rowsComputed) * expectedWorkPerRow(s, method) / run.computeSeconds;
        };
        return RadiosityPipeline(std::move(policy), std::move(events));
    }

    void run() {
        try {
            const RadiosityPipeline radiosity = pipeline();
            std::shared_ptr<const FormFactors> F = this->F;
            if (computeF) {
                // Rows the materials need that F lacks (all of them when there is no usable F).
                FormFactorUpdate update = radiosity.updateFormFactors(scene, F ? FormFactors(*F) : FormFactors());
                stats = update.stats;
                F = std::make_shared<FormFactors>(std::move(update.F));
                newF = F;
            }
            if (cancel) throw Error("cancelled");
            setStage("solve", 0.0);
            SolverOptions solver = settings.solver;
            solver.progress = [this](int sweep, const std::vector<Rgb>& B) {
                // At most ten updates a second reach the view.
                const auto now = Clock::now();
                if (now - lastIntermediate < std::chrono::milliseconds(100)) return;
                lastIntermediate = now;
                std::lock_guard<std::mutex> lock(mutex);
                intermediate = B;
                hasIntermediate = true;
                status.stage = "solve (sweep " + std::to_string(sweep) + ")";
            };
            result = radiosity.solve(scene, *F, solver, &warmStart);
        } catch (const std::exception& e) {
            error = e.what();
        }
        finished = true;
    }
};

AppState::AppState() : m_start(Clock::now()) {}

AppState::~AppState() {
    if (m_job) {
        m_job->cancel = true;
        if (m_job->thread.joinable()) m_job->thread.join();
    }
}

void AppState::addLog(const std::string& text, bool isError) {
    m_log.push_back({std::chrono::duration<double>(Clock::now() - m_start).count(), text, isError});
    if (m_log.size() > 2000) m_log.erase(m_log.begin(), m_log.begin() + 500);
}

JobStatus AppState::job() const {
    if (!m_job) return {};
    std::lock_guard<std::mutex> lock(m_job->mutex);
    JobStatus s = m_job->status;
    s.running = !m_job->finished;
    s.elapsed = std::chrono::duration<double>(Clock::now() - m_job->start).count();
    return s;
}

bool AppState::isSelected(PatchId id) const {
    return std::find(m_selection.begin(), m_selection.end(), id) != m_selection.end();
}

FalseColourView AppState::falseColourView() const {
    FalseColourView view;
    if (!hasScene()) return view;
    const auto pack = [](const std::array<std::uint8_t, 3>& c) { return std::uint32_t(c[0]) << 16 | std::uint32_t(c[1]) << 8 | c[2]; };
    view.colours.assign(m_scene->size(), pack(kFalseColourNoData));
    try {
        const std::vector<double> values = falseColourValues(*m_scene, m_B, falseColour.quantity);
        view.range = falseColourRange(values, falseColour.scale, falseColour.automatic ? std::nullopt : std::optional<double>(falseColour.min),
                                      falseColour.automatic ? std::nullopt : std::optional<double>(falseColour.max));
        for (PatchId i = 0; i < m_scene->size(); ++i) {
            view.noData |= std::isnan(values[i]);
            view.colours[i] = pack(falseColourOf(values[i], view.range));
        }
    } catch (const std::exception& e) {
        view.error = e.what();
    }
    return view;
}

std::optional<PatchReadout> AppState::readout(PatchId j) const {
    if (!hasScene() || j >= m_scene->size()) return std::nullopt;
    const Patch& p = m_scene->patches[j];
    PatchReadout r;
    r.patch = j;
    r.object = p.object < m_scene->objects.size() ? m_scene->objects[p.object] : std::string("?");
    r.sourceLine = p.sourceLine;
    r.area = p.area;
    r.B = j < m_B.size() ? m_B[j] : p.emission;
    for (int c = 0; c < 3; ++c)
        r.H[c] = p.rho[c] > 0.0 ? (r.B[c] - p.emission[c]) / p.rho[c] : std::numeric_limits<double>::quiet_NaN();
    r.emission = p.emission;
    r.rho = p.rho;
    r.specular = p.specular;
    if (!m_selection.empty() && m_selection.front() != j) {
        r.selected = m_selection.front();
        // Only an F of this mesh: after meshing its ids are another mesh's.
        if (m_F && m_F->size() == m_scene->size() && m_F->rowComputed(*r.selected)) r.fromSelected = m_F->at(*r.selected, j);
    }
    return r;
}

SelectionSummary AppState::selectionSummary() const {
    SelectionSummary sum;
    if (!hasScene()) return sum;
    std::vector<bool> objectSeen(m_scene->objects.size() + 1, false);
    for (PatchId i : m_selection) {
        const Patch& p = m_scene->patches[i];
        const std::size_t object = std::min<std::size_t>(p.object, m_scene->objects.size());
        sum.objects += !objectSeen[object];
        objectSeen[object] = true;
        ++sum.patches;
        sum.area += p.area;
        sum.emission += p.area * p.emission;
        sum.rho += p.area * p.rho;
        sum.specular += p.area * p.specular;
        if (i < m_B.size()) sum.power += p.area * m_B[i];
    }
    if (sum.area > 0.0) {
        sum.emission /= sum.area;
        sum.rho /= sum.area;
        sum.specular /= sum.area;
        sum.radiosity = sum.power / sum.area;
    }
    return sum;
}

void AppState::setScene(Scene scene, const std::string& path) {
    cancel();
    wait();
    poll();
    m_scene = std::make_unique<Scene>(std::move(scene));
    m_source = std::make_unique<const Scene>(*m_scene);
    ++m_sceneId;
    m_meshEdges.assign(std::max<std::size_t>(m_scene->objects.size(), 1), 0.0);
    m_scenePath = path;
    m_F.reset();
    m_fSettings.reset();
    m_stats.reset();
    m_B.assign(m_scene->size(), Rgb::Zero());
    for (PatchId i = 0; i < m_scene->size(); ++i) m_B[i] = m_scene->patches[i].emission;
    m_reports.clear();
    m_timings.clear();
    m_selection.clear();
    m_undo.clear();
    m_redo.clear();
    m_fStale = false;
    m_bStale = true;
    m_cleanDepth = 0;
    m_pendingResolve = false;
    bump();
}

bool AppState::loadScene(const std::string& path) {
    try {
        std::vector<std::string> warnings;
        Warnings sink([&](const std::string& m) { warnings.push_back(m); });
        Scene scene = hemirad::loadScene(path, sink, loading);
        setScene(std::move(scene), path);
        for (const std::string& w : warnings) addLog("warning: " + w, false);
        std::ostringstream msg;
        msg << "loaded " << path << ": " << m_scene->size() << " patches" << (m_scene->hasMirrors() ? ", with mirrors" : "");
        if (sink.count()) msg << "; " << sink.summary();
        info(msg.str());
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

void AppState::setUnit(const std::string& unit) {
    if (!hasScene() || unit == m_scene->unit) return;
    try {
        metresPerUnit(unit);
    } catch (const std::exception& e) {
        error(e.what());
        return;
    }
    m_scene->unit = unit;
    auto source = std::make_unique<Scene>(*m_source);
    source->unit = unit;
    m_source = std::move(source);
    info(unit.empty() ? std::string("scene unit: not stated") : "scene unit: " + unit + " (saved with the scene)");
}

bool AppState::saveScene(const std::string& path) {
    if (!hasScene()) return false;
    try {
        saveObj(*m_scene, path);
        m_scenePath = path;
        m_cleanDepth = m_undo.size();
        info("saved " + path + " (and its .mtl)");
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

void AppState::select(PatchId id, bool additive) {
    if (!hasScene() || id >= m_scene->size()) return;
    if (!additive) m_selection.clear();
    std::vector<PatchId> add{id};
    if (selectionMode == SelectionMode::Object) {
        add.clear();
        const std::uint32_t object = m_scene->patches[id].object;
        for (PatchId i = 0; i < m_scene->size(); ++i)
            if (m_scene->patches[i].object == object) add.push_back(i);
    }
    for (PatchId i : add)
        if (!isSelected(i)) m_selection.push_back(i);
}

void AppState::clearSelection() { m_selection.clear(); }

AppState::Snapshot AppState::snapshot(const std::vector<PatchId>& ids) const {
    Snapshot s;
    for (PatchId i : ids) {
        const Patch& p = m_scene->patches[i];
        s.emission.push_back(p.emission);
        s.rho.push_back(p.rho);
        s.specular.push_back(p.specular);
    }
    return s;
}

void AppState::restore(const std::vector<PatchId>& ids, const Snapshot& s) {
    for (std::size_t k = 0; k < ids.size(); ++k) {
        Patch& p = m_scene->patches[ids[k]];
        p.emission = s.emission[k];
        p.rho = s.rho[k];
        p.specular = s.specular[k];
    }
}

void AppState::materialsChanged(bool specularChanged) {
    ++m_materialsRevision;
    bump();
    // F depends on geometry and mirrors only (Scene::geometryHash); a diffuse or emission edit
    // keeps it, and rows of patches that stop being black are added on the next run.
    // Undoing a mirror edit makes F valid again.
    if (m_F) m_fStale = m_scene->geometryHash() != m_fGeometryHash;
    m_bStale = true;
    if (specularChanged) info("mirror reflectance changed: form factors must be recomputed");
    if (autoResolve && m_F && !m_fStale) refreshRadiosity();
}

void AppState::refreshRadiosity() {
    if (m_job && !m_job->finished) m_pendingResolve = true;
    else resolve();
}

void AppState::editMaterial(const MaterialEdit& edit) {
    if (!hasScene() || m_selection.empty()) return;
    const auto check = [&](const Rgb& c, const char* what, bool unit) {
        if (!c.allFinite() || (c < 0.0).any() || (unit && (c > 1.0).any()))
            throw Error(std::string(what) + " must be finite and " + (unit ? "in [0, 1]" : ">= 0"));
    };
    try {
        if (edit.emission) check(*edit.emission, "emission", false);
        if (edit.rho) check(*edit.rho, "diffuse reflectance", true);
        if (edit.specular && !(*edit.specular >= 0.0 && *edit.specular <= 1.0))
            throw Error("mirror reflectance must be in [0, 1]");
        // As the MTL loader: a patch may not reflect more than it receives (rho_c + s <= 1).
        for (PatchId i : m_selection) {
            const Patch& p = m_scene->patches[i];
            const Rgb rho = edit.rho ? *edit.rho : p.rho;
            const double s = edit.specular ? *edit.specular : p.specular;
            if ((rho + s > 1.0 + 1e-9).any())
                throw Error("patch " + std::to_string(i) + " would reflect more than it receives: rho + s = " +
                            std::to_string((rho + s).maxCoeff()) + " > 1; lower the diffuse or the mirror reflectance");
        }
    } catch (const Error& e) {
        error(e.what());
        return;
    }
    UndoStep step;
    step.ids = m_selection;
    step.before = snapshot(step.ids);
    bool specularChanged = false;
    for (PatchId i : step.ids) {
        Patch& p = m_scene->patches[i];
        if (edit.emission) p.emission = *edit.emission;
        if (edit.rho) p.rho = *edit.rho;
        if (edit.specular && *edit.specular != p.specular) {
            p.specular = *edit.specular;
            specularChanged = true;
        }
    }
    step.after = snapshot(step.ids);
    pushUndo(std::move(step));
    materialsChanged(specularChanged);
}

void AppState::undo() { replay(m_undo, m_redo, true); }

void AppState::redo() { replay(m_redo, m_undo, false); }

void AppState::replay(std::vector<UndoStep>& from, std::vector<UndoStep>& to, bool undoing) {
    if (from.empty()) return;
    UndoStep step = std::move(from.back());
    from.pop_back();
    const std::shared_ptr<const Mesh> mesh = undoing ? step.meshBefore : step.meshAfter;
    if (!mesh) restore(step.ids, undoing ? step.before : step.after);
    const bool specular = step.before.specular != step.after.specular;
    to.push_back(std::move(step));
    info(std::string(undoing ? "undo " : "redo ") + (mesh ? "meshing" : "material edit"));
    if (mesh) applyMesh(*mesh);
    else materialsChanged(specular);
}

void AppState::pushUndo(UndoStep step) {
    if (m_cleanDepth && *m_cleanDepth > m_undo.size()) m_cleanDepth.reset();  // the saved state was undone and is now gone
    m_undo.push_back(std::move(step));
    m_redo.clear();
}

std::vector<double> AppState::meshEdgesFor(double maxEdge, MeshTarget target) const {
    if (!(maxEdge >= 0.0) || !std::isfinite(maxEdge))
        throw Error("maximum edge length must be a positive number (0: as loaded), got " + std::to_string(maxEdge));
    std::vector<double> edges = m_meshEdges;
    if (target == MeshTarget::Scene) {
        std::fill(edges.begin(), edges.end(), maxEdge);
        return edges;
    }
    if (m_selection.empty()) throw Error("select the objects to mesh first (or mesh the whole scene)");
    for (PatchId i : m_selection) edges[std::min<std::size_t>(m_scene->patches[i].object, edges.size() - 1)] = maxEdge;
    return edges;
}

MeshingPreview AppState::meshingPreview(double maxEdge, MeshTarget target) const {
    MeshingPreview preview;
    if (!hasScene()) return preview;
    try {
        const std::vector<double> edges = meshEdgesFor(maxEdge, target);
        const std::size_t patches = subdividedSize(*m_source, edges);
        if (patches > kMaxGuiPatches)
            throw Error("meshing to edges of " + std::to_string(maxEdge) + " would make " + std::to_string(patches) +
                        " patches, more than hemirad-gui meshes (" + std::to_string(kMaxGuiPatches) +
                        "); use hemirad subdivide and the command line for that");
        preview.patches = patches;
        for (std::size_t k = 0; k < edges.size(); ++k) preview.objects += edges[k] != m_meshEdges[k];
    } catch (const Error& e) {
        preview.error = e.what();
    }
    return preview;
}

bool AppState::mesh(double maxEdge, MeshTarget target, bool asLoaded) {
    if (!hasScene()) return false;
    const MeshingPreview preview = meshingPreview(maxEdge, target);
    if (!preview.error.empty()) {
        error(preview.error);
        return false;
    }
    std::vector<double> edges = meshEdgesFor(maxEdge, target);  // the preview's, which did not throw
    if (edges == m_meshEdges) {
        info("the mesh already has these edge lengths: nothing to do");
        return true;
    }
    // A running job works on its own copy of the scene; applyMesh stops it before the switch.
    auto next = std::make_shared<Mesh>();
    next->edges = std::move(edges);
    next->scene = subdivide(*m_source, next->edges);
    // Material edits carry over: each new patch takes the values of the patch covering its centroid.
    // Coarsening can merge patches edited apart; those take the covering patch's values (undo keeps them).
    const std::vector<PatchId> from = coveringPatches(*m_scene, next->scene);
    for (PatchId j = 0; j < next->scene.size(); ++j) {
        const Patch& old = m_scene->patches[from[j]];
        Patch& p = next->scene.patches[j];
        p.emission = old.emission;
        p.rho = old.rho;
        p.specular = old.specular;
    }
    std::size_t merged = 0;
    const std::vector<PatchId> to = coveringPatches(next->scene, *m_scene);
    for (PatchId i = 0; i < m_scene->size(); ++i) {
        const Patch &old = m_scene->patches[i], &p = next->scene.patches[to[i]];
        merged += (old.emission != p.emission).any() || (old.rho != p.rho).any() || old.specular != p.specular;
    }
    std::ostringstream msg;
    msg << "meshed " << (target == MeshTarget::Scene ? "the scene" : std::to_string(preview.objects) + " object(s)");
    if (maxEdge > 0) msg << " to edges <= " << maxEdge;
    else msg << " back to the patches as loaded";
    msg << ": " << m_scene->size() << " -> " << next->scene.size() << " patches";
    if (merged) msg << "; " << merged << " patch(es) edited apart were merged and take the values of the patch now covering them";
    if (asLoaded) {
        applyMesh(*next);
        m_undo.clear();
        m_redo.clear();
        m_cleanDepth = 0;
        info(msg.str());
        return true;
    }
    UndoStep step;
    step.meshBefore = std::make_shared<Mesh>(Mesh{*m_scene, m_meshEdges});
    step.meshAfter = next;
    pushUndo(std::move(step));
    info(msg.str());
    applyMesh(*next);
    return true;
}

void AppState::applyMesh(const Mesh& next) {
    cancel();
    wait();
    poll();
    const std::vector<PatchId> from = coveringPatches(*m_scene, next.scene);
    std::vector<bool> wasSelected(m_scene->size(), false);
    for (PatchId i : m_selection) wasSelected[i] = true;
    std::vector<Rgb> B(next.scene.size());
    std::vector<PatchId> selection;
    for (PatchId j = 0; j < next.scene.size(); ++j) {
        B[j] = from[j] < m_B.size() ? m_B[from[j]] : next.scene.patches[j].emission;
        if (wasSelected[from[j]]) selection.push_back(j);
    }
    const std::string unit = m_scene->unit;  // a setting of the scene, not of a mesh: undo keeps it
    *m_scene = next.scene;
    m_scene->unit = unit;
    m_meshEdges = next.edges;
    m_B = std::move(B);
    m_selection = std::move(selection);
    m_corner.clear();
    m_reports.clear();
    ++m_materialsRevision;  // the material editor reloads: its patch ids changed
    bump();
    m_fStale = m_F && m_scene->geometryHash() != m_fGeometryHash;
    m_bStale = true;
    if (m_F && m_fStale) info("the mesh changed: form factors must be recomputed (Run)");
    // Back on the mesh F was made for (undo): re-solve from the carried-over radiosity.
    if (autoResolve && m_F && !m_fStale) resolve();
}

void AppState::startJob(bool computeF, std::shared_ptr<const FormFactors> F) {
    if (!hasScene()) return;
    if (m_job && !m_job->finished) {
        error("a computation is running; cancel it first");
        return;
    }
    if (m_job && m_job->thread.joinable()) m_job->thread.join();
    m_job = std::make_unique<Job>();
    m_job->scene = *m_scene;
    m_job->F = std::move(F);
    m_job->computeF = computeF;
    m_job->settings = settings;
    m_job->warmStart = m_B;
    m_job->materialsRevision = m_materialsRevision;
    m_job->thread = std::thread([job = m_job.get()] { job->run(); });
}

FormFactorEstimate AppState::formFactorEstimate() const {
    FormFactorEstimate e;
    if (!hasScene()) return e;
    const MethodSettings& method = settings.formFactors;
    const BackendDescriptor& backend = findBackend(method.method);
    e.workUnit = backend.workUnit;
    e.description = backend.describe(*m_scene, method).settings;
    e.workPerRow = backend.workPerRow(*m_scene, method);
    // The rows Run would compute: the missing ones of a reusable F, else every row needed.
    FormFactorPolicy policy;
    policy.backend = method;
    const bool reuse = m_F && !m_fStale && formFactorsMatchSettings();
    e.rows = RadiosityPipeline(policy, {}).missingRows(*m_scene, reuse ? m_F.get() : nullptr).size();
    e.reusesF = reuse;
    e.memoryBound = formFactorMemoryBound(*m_scene, method, e.rows);
    if (const auto it = m_workPerSecond.find(method.method); it != m_workPerSecond.end())
        e.seconds = double(e.rows) * e.workPerRow / it->second;
    return e;
}

bool AppState::formFactorsMatchSettings() const {
    return m_F && m_fSettings && sameFormFactorSettings(*m_fSettings, settings.formFactors);
}

void AppState::runPipeline() {
    if (!hasScene()) return;
    // Only an F made with the panel's settings is reused (or completed with missing rows).
    const bool reuse = m_F && !m_fStale && formFactorsMatchSettings();
    if (m_F && !m_fStale && !reuse) info("the form-factor settings changed since F was made: computing F again");
    FormFactorPolicy policy;
    policy.backend = settings.formFactors;
    const bool needF = !reuse || !RadiosityPipeline(policy, {}).missingRows(*m_scene, m_F.get()).empty();
    info(needF ? "running: form factors and solve" : "running: solve (form factors are current)");
    startJob(needF, reuse ? m_F : nullptr);
}

void AppState::recomputeFormFactors() {
    if (!hasScene()) return;
    info("running: form factors (recomputed) and solve");
    startJob(true, nullptr);
}

void AppState::resolve() {
    if (!hasScene()) return;
    if (!m_F || m_fStale) {
        error("no current form factors: run the pipeline first");
        return;
    }
    // Every re-solve (an edit, undo, the one queued while a job ran) goes through here: rows the
    // materials now need that F lacks (a black patch made reflective) are computed first.
    for (PatchId i : neededRows(*m_scene, false))
        if (!m_F->rowComputed(i)) return runPipeline();
    startJob(false, m_F);
}

void AppState::cancel() {
    if (m_job && !m_job->finished) {
        m_job->cancel = true;
        info("cancelling...");
    }
}

void AppState::wait() {
    if (m_job && m_job->thread.joinable()) m_job->thread.join();
}

bool AppState::poll() {
    if (m_job && !m_job->finished) {
        // Progressive display: show the solve's newest intermediate radiosity.
        std::lock_guard<std::mutex> lock(m_job->mutex);
        if (!m_job->hasIntermediate || m_job->intermediate.size() != m_B.size()) return false;
        m_B.swap(m_job->intermediate);
        m_job->hasIntermediate = false;
        bump();
        return true;
    }
    if (!m_job) return false;
    if (m_job->thread.joinable()) m_job->thread.join();
    std::unique_ptr<Job> job = std::move(m_job);
    for (const std::string& m : job->messages) info(m);
    if (!job->error.empty()) {
        if (job->error.find("cancelled") != std::string::npos) info("cancelled");
        else error(job->error);
        return false;
    }
    if (job->newF) {
        m_F = job->newF;
        m_fSettings = job->settings.formFactors;
        m_stats = job->stats;
        m_fGeometryHash = job->scene.geometryHash();
        m_fStale = m_fGeometryHash != m_scene->geometryHash();
    }
    if (job->scene.size() == m_scene->size()) m_B = job->result.B;
    m_reports = job->result.reports;
    m_timings = job->timings;
    if (job->workPerSecond > 0.0) m_workPerSecond[job->settings.formFactors.method] = job->workPerSecond;
    for (const SolveReport& r : m_reports) {
        std::ostringstream msg;
        msg << "solve: " << r.solver << " (" << r.channels << ") " << (r.converged ? "converged" : "NOT converged") << " in "
            << r.iterations << " iterations, residual " << r.residual << ", " << r.seconds << " s";
        info(msg.str());
    }
    m_bStale = job->materialsRevision != m_materialsRevision;
    bump();
    if ((m_bStale && autoResolve) || m_pendingResolve) {
        m_pendingResolve = false;
        if (m_F && !m_fStale) resolve();
    }
    return true;
}

bool AppState::importFormFactors(const std::string& path) {
    if (!hasScene()) return false;
    // A running job would replace the imported F with its own.
    cancel();
    wait();
    poll();
    try {
        auto F = std::make_shared<FormFactors>(loadFormFactors(path));
        checkFormFactorsMatch(*F, m_scene->geometryHash(), m_scene->size(), path);
        m_stats = computeStats(*F, *m_scene);
        m_F = std::move(F);
        m_fSettings = settings.formFactors;  // Run reuses it until the panel's settings change
        m_fGeometryHash = m_scene->geometryHash();
        m_fStale = false;
        m_bStale = true;
        bump();
        info("imported form factors from " + path);
        if (autoResolve) refreshRadiosity();  // the picture shows the imported F's radiosity
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

bool AppState::exportFormFactors(const std::string& path) {
    if (!m_F) {
        error("no form factors to export yet: run the pipeline");
        return false;
    }
    try {
        saveFormFactors(*m_F, path);
        info("exported form factors to " + path);
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

bool AppState::exportPly(const std::string& path) {
    if (!hasScene()) return false;
    try {
        std::vector<double> lum;
        for (const Rgb& b : m_B) lum.push_back(luminance(b) / kPi);
        const double scale = autoExposure ? hemirad::autoExposure(std::move(lum), 0.9, 0.85) : exposure;
        writeRadiosityPly(path, *m_scene, cornerRadiosity(), scale);
        info("exported " + path);
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

std::vector<ObjectSummary> AppState::objectTable() const {
    return hasScene() ? summarizeObjects(*m_scene, m_B) : std::vector<ObjectSummary>{};
}

bool AppState::exportObjectTable(const std::string& path) {
    if (!hasScene()) return false;
    try {
        writeObjectTable(path, objectTable());
        info("exported " + path + " (per object: area, B and H)");
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

std::vector<float> AppState::formFactorRow(PatchId i) const {
    // An F of another mesh (stale after meshing) has other patch ids.
    if (!m_F || !hasScene() || m_F->size() != m_scene->size() || i >= m_F->size() || !m_F->rowComputed(i)) return {};
    std::vector<float> row(m_scene->size(), 0.0f);
    for (std::uint64_t k = m_F->rowBegin(i); k < m_F->rowEnd(i); ++k) row[m_F->columns()[k]] = m_F->values()[k];
    return row;
}

const std::vector<Rgb>& AppState::cornerRadiosity() {
    if (m_cornerRevision != m_revision || m_corner.size() != (hasScene() ? m_scene->corners.size() : 0)) {
        m_corner = hasScene() ? hemirad::cornerRadiosity(*m_scene, m_B, creaseDegrees) : std::vector<Rgb>{};
        m_cornerRevision = m_revision;
    }
    return m_corner;
}

}  // namespace hemirad::ui
