// hemirad-gui application state: undoable material edits and the re-solve they ask for.
#include "ui/app_state.hpp"

#include "engine/error.hpp"

#include <string>

namespace hemirad::ui {

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

bool AppState::editMaterial(const MaterialEdit& edit) {
    if (!hasScene() || m_selection.empty()) return false;
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
        return false;
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
    return true;
}

void AppState::undo() { replay(m_undo, m_redo, true); }

void AppState::redo() { replay(m_redo, m_undo, false); }

void AppState::replay(std::vector<UndoStep>& from, std::vector<UndoStep>& to, bool undoing) {
    if (from.empty()) return;
    UndoStep step = std::move(from.back());
    from.pop_back();
    const std::shared_ptr<const Mesh> mesh = undoing ? step.meshBefore : step.meshAfter;
    const bool material = !mesh && !step.ids.empty();
    if (material) restore(step.ids, undoing ? step.before : step.after);
    const bool specular = step.before.specular != step.after.specular;
    const std::shared_ptr<const ThermalSetup> thermal = undoing ? step.thermalBefore : step.thermalAfter;
    to.push_back(std::move(step));
    info(std::string(undoing ? "undo " : "redo ") +
         (mesh ? "meshing" : material ? (thermal ? "thermal properties (and the mirror reflectances they set)" : "material edit") : "thermal edit"));
    if (thermal) {
        m_thermal = *thermal;
        m_thermalLoadError.clear();
        ++m_thermalRevision;
        ++m_thermalSetupRevision;
        bump();
    }
    if (mesh) applyMesh(*mesh);
    else if (material) materialsChanged(specular);
}

void AppState::pushUndo(UndoStep step) {
    if (m_cleanDepth && *m_cleanDepth > m_undo.size()) {
        // The saved state was undone: it is gone with the redo history, unless only thermal edits
        // (not saved with the scene) lie between it and here.
        bool sceneChanged = false;
        for (std::size_t k = 0; k < *m_cleanDepth - m_undo.size() && !sceneChanged; ++k)
            sceneChanged = m_redo[m_redo.size() - 1 - k].changesScene();
        if (sceneChanged) m_cleanDepth.reset();
        else m_cleanDepth = m_undo.size();
    }
    m_undo.push_back(std::move(step));
    m_redo.clear();
}

void AppState::pushThermalUndo(const ThermalSetup& before) {
    UndoStep step;
    step.thermalBefore = std::make_shared<const ThermalSetup>(before);
    step.thermalAfter = std::make_shared<const ThermalSetup>(m_thermal);
    pushUndo(std::move(step));
}

bool AppState::dirty() const {
    if (!m_cleanDepth) return true;
    // Only steps that change the scene (materials, mesh) between the saved depth and this one count:
    // below it they are in the undo history, above it (undone) in the redo history, the next last.
    const std::size_t clean = *m_cleanDepth, depth = m_undo.size();
    for (std::size_t k = clean; k < depth; ++k)
        if (m_undo[k].changesScene()) return true;
    for (std::size_t k = 0; k + depth < clean; ++k)
        if (m_redo[m_redo.size() - 1 - k].changesScene()) return true;
    return false;
}

}  // namespace hemirad::ui
