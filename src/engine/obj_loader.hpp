// Wavefront OBJ/MTL loading: one face = one patch, every input error named with file:line and value.
#pragma once

#include "engine/scene.hpp"
#include "engine/warnings.hpp"

#include <string>

namespace hemirad {

/// The material of patches that name none (OBJ faces before any usemtl, every STL triangle):
/// Kd 0.5, no emission, no mirror, named kDefaultMaterialName.
inline constexpr const char* kDefaultMaterialName = "hemirad_default";
Material defaultMaterial();

/// Loads an OBJ scene and the MTL libraries it names. Throws hemirad::Error on malformed input;
/// recoverable oddities (degenerate or non-planar patches, rho + s > 1, ...) go to `warnings`.
/// `materialsByObject`: materials will be assigned by object name afterwards (loadScene with
/// --materials), which reports the patches left without one; the loader then does not.
Scene loadObj(const std::string& path, Warnings& warnings, bool materialsByObject = false);

/// Loads an MTL library's materials into `out` (appending). Same error rules as loadObj.
void loadMtl(const std::string& path, std::vector<Material>& out, Warnings& warnings);

/// Where `mtllib` names are found: beside the OBJ file (loadObj), or in memory (tests, fuzzing).
class MaterialSource {
public:
    virtual ~MaterialSource() = default;
    /// The library's text and its name for messages; false when there is no such library.
    virtual bool find(const std::string& name, std::string& text, std::string& file) = 0;
};

/// The parsers behind loadObj / loadMtl, on text in memory; `file` names it in messages.
Scene parseObj(const std::string& file, std::string_view text, MaterialSource& libraries, Warnings& warnings,
               bool materialsByObject = false);
void parseMtl(const std::string& file, std::string_view text, std::vector<Material>& out, Warnings& warnings);

/// Reads a whole text file; throws hemirad::Error naming the path when it cannot.
std::string readTextFile(const std::string& path);

}  // namespace hemirad
