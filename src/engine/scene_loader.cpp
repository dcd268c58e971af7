// Scene files by extension, and materials by object name for formats without (or beside) their own.
#include "engine/scene_loader.hpp"

#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "engine/stl_loader.hpp"
#include "engine/text_reader.hpp"

#include <cctype>
#include <filesystem>
#include <set>
#include <unordered_map>

namespace hemirad {
namespace {

constexpr std::size_t kNamed = 4;  // names a warning lists before "and N more"
constexpr const char* kFallback = "default";  // the material of the objects without one

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

/// "'a', 'b', 'c', 'd' and 2 more".
std::string nameList(const std::vector<std::string>& names) {
    std::string text;
    for (std::size_t k = 0; k < names.size() && k < kNamed; ++k) text += (k ? ", '" : "'") + names[k] + "'";
    if (names.size() > kNamed) text += " and " + std::to_string(names.size() - kNamed) + " more";
    return text;
}

bool hasOwnMaterial(const Scene& scene, const Patch& p) {
    return p.material < scene.materials.size() && scene.materials[p.material].name != kDefaultMaterialName;
}

/// The objects (in scene order) with at least one patch that has no material of its own.
std::vector<std::string> objectsWithoutMaterial(const Scene& scene) {
    std::vector<char> without(scene.objects.size(), 0);
    for (const Patch& p : scene.patches)
        if (!hasOwnMaterial(scene, p)) without[p.object] = 1;
    std::vector<std::string> names;
    for (std::size_t o = 0; o < without.size(); ++o)
        if (without[o]) names.push_back(scene.objects[o]);
    return names;
}

}  // namespace

const std::vector<std::string>& sceneExtensions() {
    static const std::vector<std::string> extensions = {".obj", ".stl"};
    return extensions;
}

Scene loadScene(const std::string& path, Warnings& warnings, const SceneLoadOptions& options) {
    const std::string ext = lowerExtension(path);
    const bool byObject = !options.materials.empty();
    Scene scene;
    if (ext == ".obj") {
        scene = loadObj(path, warnings, byObject);
    } else if (ext == ".stl") {
        scene = loadStl(path, warnings);
    } else {
        throw Error(path, 0, (ext.empty() ? std::string("no file extension") : "unknown scene file type " + quote(ext)) +
                                 ": Hemirad reads .obj (with its .mtl libraries) and .stl (binary or ASCII)");
    }
    if (byObject) {
        std::vector<Material> library;
        loadMtl(options.materials, library, warnings);
        assignMaterialsByObject(scene, library, options.materials, warnings);
    } else if (ext == ".stl") {
        const std::vector<std::string> without = objectsWithoutMaterial(scene);
        if (!without.empty())
            warnings.add("objects without a material",
                         path + ": " + std::to_string(without.size()) + " object(s) without a material (STL has none): " +
                             nameList(without) +
                             "; they get the default (Kd 0.5, no emission). --materials FILE.mtl gives materials "
                             "by object name",
                         without.size());
    }
    return scene;
}

void assignMaterialsByObject(Scene& scene, const std::vector<Material>& library, const std::string& file,
                             Warnings& warnings) {
    std::unordered_map<std::string, std::size_t> byName;  // a name defined twice: the later (parseMtl warned)
    for (std::size_t k = 0; k < library.size(); ++k) byName[library[k].name] = k;
    const auto fallback = byName.find(kFallback);
    // Library materials join the scene's when a patch takes them, so unused ones are not saved with it.
    std::vector<std::uint32_t> sceneIndex(library.size(), UINT32_MAX);
    auto use = [&](std::size_t k) {
        if (sceneIndex[k] == UINT32_MAX) {
            sceneIndex[k] = static_cast<std::uint32_t>(scene.materials.size());
            scene.materials.push_back(library[k]);
        }
        return sceneIndex[k];
    };
    std::vector<char> hasPatches(scene.objects.size(), 0);
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        hasPatches[p.object] = 1;
        // An OBJ's faces before any o/g form the object "default": 'default' is the fallback there
        // too, never a name match that would override their own materials.
        const std::string& name = scene.objects[p.object];
        if (const auto match = byName.find(name); match != byName.end() && name != kFallback)
            scene.applyMaterial(i, use(match->second));
        else if (fallback != byName.end() && !hasOwnMaterial(scene, p))
            scene.applyMaterial(i, use(fallback->second));
    }

    std::set<std::string> objectNames;
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
        if (hasPatches[o]) objectNames.insert(scene.objects[o]);
    std::vector<std::string> unknown, objects(objectNames.begin(), objectNames.end());
    std::set<std::string> listed;
    for (const Material& m : library)
        if (m.name != kFallback && !objectNames.count(m.name) && listed.insert(m.name).second) unknown.push_back(m.name);
    if (!unknown.empty())
        warnings.add("materials naming no object",
                     file + ": " + std::to_string(unknown.size()) + " material(s) name no object of " + scene.path +
                         ": " + nameList(unknown) + " (its objects: " + nameList(objects) + ")",
                     unknown.size());

    const std::vector<std::string> without = objectsWithoutMaterial(scene);
    if (!without.empty())
        warnings.add("objects without a material",
                     file + ": " + std::to_string(without.size()) +
                         " object(s) match no material, and there is no 'default': " + nameList(without) +
                         "; they get the built-in default (Kd 0.5, no emission)",
                     without.size());
}

}  // namespace hemirad
