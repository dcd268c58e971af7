// The material editor's fields, loaded from the first selected patch.
#include "ui/material_fields.hpp"

namespace hemirad::ui {

void MaterialFields::sync(const AppState& app) {
    if (app.selection() != m_selection || app.materialsRevision() != m_revision) load(app);
}

bool MaterialFields::apply(AppState& app, const MaterialEdit& edit) {
    if (app.editMaterial(edit)) return true;
    // Refused (rho + s > 1, a value out of range): the fields show what the patch still has.
    load(app);
    return false;
}

void MaterialFields::load(const AppState& app) {
    m_selection = app.selection();
    m_revision = app.materialsRevision();
    if (!app.hasScene() || m_selection.empty()) return;
    const Patch& p = app.scene().patches[m_selection.front()];
    for (int c = 0; c < 3; ++c) {
        emission[c] = p.emission[c];
        rho[c] = p.rho[c];
    }
    specular = p.specular;
}

}  // namespace hemirad::ui
