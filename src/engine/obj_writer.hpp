// Saving a scene as OBJ + MTL (atomically), keeping objects, materials and per-patch edits.
#pragma once

#include "engine/scene.hpp"

#include <string>

namespace hemirad {

/// Writes `path` (.obj) and the material library beside it (same stem, .mtl). A patch whose E, rho
/// or s differ from its material's (edited in the GUI) gets a derived material "<name>~k". Standard
/// output ("-") is refused (there is no "beside" for the MTL).
void saveObj(const Scene& scene, const std::string& path);

}  // namespace hemirad
