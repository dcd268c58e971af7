// The one place a scene file is read: the loader chosen by extension (.obj, .stl), then the
// materials assigned by object name (--materials).
#pragma once

#include "engine/scene.hpp"
#include "engine/warnings.hpp"

#include <string>
#include <vector>

namespace hemirad {

/// How loadScene reads a scene beyond the file itself.
struct SceneLoadOptions {
    /// An MTL library whose materials go to the objects of the same name (--materials; "" = none).
    std::string materials;
};

/// The scene file types loadScene reads, by extension (lower case, with the dot).
const std::vector<std::string>& sceneExtensions();

/// Loads a scene by its extension, case-insensitive: .obj (+ its MTL libraries, loadObj) or .stl
/// (loadStl), then assigns options.materials by object name (assignMaterialsByObject). An STL
/// without --materials has its objects without a material reported as a warning. Throws
/// hemirad::Error naming the file (an unknown extension: with the types read).
Scene loadScene(const std::string& path, Warnings& warnings, const SceneLoadOptions& options = {});

/// Materials by object name: each object (STL solid, OBJ o/g name) whose name equals a material of
/// `library` takes it for all its patches, overriding an OBJ's own; a material named "default"
/// goes to the patches of the other objects that have no material of their own (defaultMaterial()).
/// Warned, counted: the objects left with no material (they keep defaultMaterial()), and the
/// library's names that match no object (typos). `file` names the library in messages.
void assignMaterialsByObject(Scene& scene, const std::vector<Material>& library, const std::string& file,
                             Warnings& warnings);

}  // namespace hemirad
