// Wavefront OBJ/MTL loading: one face = one patch, every input error named with file:line and value.
#pragma once

#include "engine/scene.hpp"
#include "engine/warnings.hpp"

#include <string>

namespace hemirad {

/// Loads an OBJ scene and the MTL libraries it names. Throws hemirad::Error on malformed input;
/// recoverable oddities (degenerate or non-planar patches, rho + s > 1, ...) go to `warnings`.
Scene loadObj(const std::string& path, Warnings& warnings);

/// Loads an MTL library's materials into `out` (appending). Same error rules as loadObj.
void loadMtl(const std::string& path, std::vector<Material>& out, Warnings& warnings);

/// Reads a whole text file; throws hemirad::Error naming the path when it cannot.
std::string readTextFile(const std::string& path);

}  // namespace hemirad
