// hemirad-gui application state: the thermal files and per-object edits (checked by src/thermal),
// the thermal run on the worker thread, its result and the exchange table's export.
#include "ui/app_state.hpp"

#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "thermal/conductor_writers.hpp"
#include "thermal/thermal_files.hpp"
#include "ui/thermal_job.hpp"

#include <cmath>
#include <cstdio>
#include <exception>

namespace hemirad::ui {

bool AppState::loadThermalProperties(const std::string& path) {
    if (!hasScene()) return false;
    try {
        ThermalSetup next = m_thermal;
        next.propertiesPath = path;
        next.propertiesText = readTextFile(path);
        next.emissivity.clear();  // the file gives every emissivity again
        // The file's specular reflectances become the scene's (F depends on them), as in hemirad thermal.
        Scene withFile = *m_scene;
        std::vector<std::string> sources;
        thermal::applyPropertiesText(next.propertiesText, path, withFile, sources);
        checkThermalSetup(withFile, next);
        // One undoable step: the thermal setup, and the mirror reflectances the file sets.
        UndoStep step;
        for (PatchId i = 0; i < m_scene->size(); ++i)
            if (withFile.patches[i].specular != m_scene->patches[i].specular) step.ids.push_back(i);
        step.thermalBefore = std::make_shared<const ThermalSetup>(m_thermal);
        step.thermalAfter = std::make_shared<const ThermalSetup>(next);
        const bool specular = !step.ids.empty();
        if (specular) {
            step.before = snapshot(step.ids);
            for (PatchId i : step.ids) m_scene->patches[i].specular = withFile.patches[i].specular;
            step.after = snapshot(step.ids);
            info("thermal properties set the mirror reflectance of " + std::to_string(step.ids.size()) + " patches (undoable)");
        }
        pushUndo(std::move(step));
        if (specular) materialsChanged(true);
        m_thermal = std::move(next);
        m_thermalLoadError.clear();
        ++m_thermalRevision;
        ++m_thermalSetupRevision;
        info("thermal properties: " + path);
        for (const std::string& s : sources) info("properties  " + s);
        return true;
    } catch (const std::exception& e) {
        m_thermalLoadError = e.what();
        ++m_thermalRevision;
        error(e.what());
        return false;
    }
}

bool AppState::loadThermalConditions(const std::string& path) {
    if (!hasScene()) return false;
    try {
        ThermalSetup next = m_thermal;
        next.conditionsPath = path;
        next.conditionsText = readTextFile(path);
        next.condition.clear();  // the file gives every object's condition and the environment
        next.environment.reset();
        checkThermalSetup(*m_scene, next);
        const ThermalSetup before = m_thermal;
        m_thermal = std::move(next);
        pushThermalUndo(before);
        m_thermalLoadError.clear();
        ++m_thermalRevision;
        ++m_thermalSetupRevision;
        info("boundary conditions: " + path);
        return true;
    } catch (const std::exception& e) {
        m_thermalLoadError = e.what();
        ++m_thermalRevision;
        error(e.what());
        return false;
    }
}

namespace {

/// Whether `object` is an object of `scene` that holds patches (what the thermal table lists).
bool hasPatches(const Scene& scene, std::uint32_t object) {
    for (const Patch& p : scene.patches)
        if (p.object == object) return true;
    return false;
}

/// Applies `change` to a copy of `setup` and keeps it if the library accepts the result for `scene`.
template <class Change>
bool tryEdit(const Scene& scene, ThermalSetup& setup, Change change, std::string& why) {
    ThermalSetup next = setup;
    change(next);
    try {
        checkThermalSetup(scene, next);
    } catch (const std::exception& e) {
        why = e.what();
        return false;
    }
    setup = std::move(next);
    return true;
}

}  // namespace

bool AppState::setObjectEmissivity(std::uint32_t object, double emissivity) {
    if (!hasScene() || !hasPatches(*m_scene, object)) return false;
    std::string why;
    if (!std::isfinite(emissivity)) why = "emissivity must be a finite number";
    std::string curve;  // the object's emissivity against temperature, which a constant replaces
    {
        std::optional<double> environment;
        std::string unreadable;
        for (const ObjectThermalRow& r : thermalObjects(environment, unreadable))
            if (r.object == object) curve = r.emissivityCurve;
    }
    const ThermalSetup before = m_thermal;
    const bool ok = why.empty() && tryEdit(*m_scene, m_thermal, [&](ThermalSetup& s) { s.emissivity[object] = emissivity; }, why);
    ++m_thermalRevision;  // refused: the panel's field goes back to the value in effect
    if (ok) {
        ++m_thermalSetupRevision;
        pushThermalUndo(before);
    }
    if (!ok) error("emissivity of '" + m_scene->objects[object] + "' refused: " + why);
    if (ok && !curve.empty()) {
        char value[32];
        std::snprintf(value, sizeof value, "%.4g", emissivity);
        info("emissivity of '" + m_scene->objects[object] + "': the constant " + value + " replaces its " +
             curve.substr(0, curve.find(" (shown")));
    }
    return ok;
}

bool AppState::setObjectCondition(std::uint32_t object, const ObjectCondition& condition) {
    if (!hasScene() || !hasPatches(*m_scene, object)) return false;
    std::string why;
    if (!std::isfinite(condition.value)) why = "the value must be a finite number";
    const ThermalSetup before = m_thermal;
    const bool ok = why.empty() && tryEdit(*m_scene, m_thermal, [&](ThermalSetup& s) { s.condition[object] = condition; }, why);
    ++m_thermalRevision;
    if (ok) {
        ++m_thermalSetupRevision;
        pushThermalUndo(before);
    }
    if (!ok) error("condition of '" + m_scene->objects[object] + "' refused: " + why);
    return ok;
}

bool AppState::setThermalEnvironment(std::optional<double> kelvin) {
    if (!hasScene()) return false;
    std::string why;
    if (kelvin && !std::isfinite(*kelvin)) why = "the environment's temperature must be a finite number";
    const ThermalSetup before = m_thermal;
    const bool ok = why.empty() && tryEdit(*m_scene, m_thermal, [&](ThermalSetup& s) { s.environment = kelvin; }, why);
    ++m_thermalRevision;
    if (ok) {
        ++m_thermalSetupRevision;
        pushThermalUndo(before);
    }
    if (!ok) error("environment refused: " + why);
    return ok;
}

std::vector<ObjectThermalRow> AppState::thermalObjects(std::optional<double>& environment, std::string& why) const {
    why.clear();
    environment.reset();
    if (!hasScene()) return {};
    try {
        return objectThermalRows(*m_scene, m_thermal, environment);
    } catch (const std::exception& e) {
        why = e.what();
        return {};
    }
}

void AppState::runThermal() {
    if (!hasScene()) return;
    if (busy()) {
        error("a computation is running; cancel it first");
        return;
    }
    ThermalInputs inputs;
    try {
        inputs = buildThermalInputs(*m_scene, m_thermal);
    } catch (const std::exception& e) {
        error("thermal: " + std::string(e.what()));
        return;
    }
    if (m_thermal.propertiesPath.empty())
        info("thermal: no properties file: emissivity = 1 - mean(Kd) - s from the MTL (the visible diffuse "
             "reflectance taken as the IR one)");
    if (m_scene->unit.empty()) info("thermal: the scene states no length unit: lengths are taken as metres");
    // Only an F made for this geometry and these settings is reused; its missing rows are added.
    const bool reuse = m_F && !m_fStale && formFactorsMatchSettings();
    info(reuse ? "running: thermal (every row of F, then the solve)" : "running: thermal (form factors, then the solve)");
    m_thermalJob.reset();
    m_thermalJob = std::make_unique<ThermalJob>(*m_scene, reuse ? m_F : nullptr, std::move(inputs), settings);
    m_thermalJobRevisions = {m_materialsRevision, m_thermalSetupRevision};
}

bool AppState::finishWorkerJob(WorkerJob& job, const std::string& what) {
    job.wait();
    for (const std::string& m : job.messages) info(m);
    if (!job.error.empty()) {
        if (job.error.find("cancelled") != std::string::npos) info("cancelled");
        else error(what + ": " + job.error);
        return false;
    }
    if (job.newF && job.scene().geometryHash() == m_scene->geometryHash() && job.scene().size() == m_scene->size()) {
        // F with every row serves the radiosity solves too.
        m_F = job.newF;
        m_fSettings = job.settings().formFactors;
        if (job.stats) m_stats = job.stats;
        m_fGeometryHash = job.scene().geometryHash();
        m_fStale = false;
    }
    return true;
}

void AppState::pollThermal() {
    std::unique_ptr<ThermalJob> job = std::move(m_thermalJob);
    if (!finishWorkerJob(*job, "thermal")) return;
    m_thermalResult = std::move(job->result);
    m_thermalResult->materialsRevision = m_thermalJobRevisions.first;
    m_thermalResult->setupRevision = m_thermalJobRevisions.second;
    m_timings = job->timings;
    bump();
}

const ThermalResult* AppState::thermalResult() const {
    if (!hasScene() || !m_thermalResult || m_thermalResult->solution.T.size() != m_scene->size()) return nullptr;
    return &*m_thermalResult;
}

bool AppState::thermalStale() const {
    const ThermalResult* r = thermalResult();
    return r && (r->geometryHash != m_scene->geometryHash() || r->materialsRevision != m_materialsRevision ||
                 r->setupRevision != m_thermalSetupRevision);
}

bool AppState::exportThermalExchange(const std::string& path) {
    const ThermalResult* r = thermalResult();
    if (!r) {
        error("no thermal result to export: press Run thermal first");
        return false;
    }
    try {
        thermal::writeExchangeMatrix(path, r->objects, r->exchange);
        info("exported " + path + " (net power between objects and to the environment, W)");
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

bool AppState::exportThermalConductors(const std::string& path) {
    const ThermalResult* r = thermalResult();
    if (!r) {
        error("no thermal result to export: press Run thermal first");
        return false;
    }
    const std::string format = thermal::conductorFormatFor(path);
    if (format.empty()) {
        error(path + ": the conductors' format comes from the extension: .csv, .mtx, .esatan or .cnd (ESATAN-TMS), .sinda or .inp "
                     "(SINDA/FLUINT)");
        return false;
    }
    try {
        thermal::writeConductors(path, format, r->conductors);
        info("exported " + path + " (" + std::to_string(r->conductors.couplings.size()) + " radiative conductors GR between objects and " +
             "the environment, m^2; " + format + ")");
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

}  // namespace hemirad::ui
