// The material editor's fields: the values they show and when they are loaded from the scene.
#pragma once

#include "ui/app_state.hpp"

#include <cstdint>
#include <vector>

namespace hemirad::ui {

/// What the material editor's fields hold: the first selected patch's values, loaded again when the
/// selection changes, after every edit, undo and redo, and after an edit AppState refused, so that
/// the fields never keep a value the patch does not have. Doubles: a value is stored as typed.
class MaterialFields {
public:
    /// Loads the first selected patch's values when the selection or the materials changed.
    void sync(const AppState& app);
    /// Applies the edit typed into the fields; a refused one (AppState logs why) puts the patch's
    /// values back into the fields. Returns whether it was applied.
    bool apply(AppState& app, const MaterialEdit& edit);

    double emission[3] = {0, 0, 0};  ///< E, W/m^2
    double rho[3] = {0.5, 0.5, 0.5};
    double specular = 0.0;

private:
    void load(const AppState& app);
    std::vector<PatchId> m_selection;
    std::uint64_t m_revision = 0;  ///< the materials revision the fields were loaded at
};

}  // namespace hemirad::ui
