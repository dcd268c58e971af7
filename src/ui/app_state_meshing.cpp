// hemirad-gui application state: meshing objects (preview, apply, undo) and the F it makes stale.
#include "ui/app_state.hpp"

#include "engine/error.hpp"
#include "engine/subdivide.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace hemirad::ui {

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
    const std::string unit = m_scene->unit;  // settings of the scene, not of a mesh: undo keeps them
    const int up = m_scene->up;
    *m_scene = next.scene;
    m_scene->unit = unit;
    m_scene->up = up;
    m_meshEdges = next.edges;
    ++m_meshRevision;  // a rate measured on the old mesh does not time this one
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

}  // namespace hemirad::ui
