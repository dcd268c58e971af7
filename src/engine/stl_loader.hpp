// STL loading (binary and ASCII): one triangle = one patch, vertices merged exactly, every input
// error named with the file and the triangle (binary: its index from 0) or the line (ASCII).
#pragma once

#include "engine/scene.hpp"
#include "engine/warnings.hpp"

#include <string>
#include <string_view>

namespace hemirad {

/// Loads an STL scene. Binary when the file's size is 84 + 50 n for the n of its header, ASCII when
/// it starts with "solid" and holds no NUL byte, else a damaged binary file. Objects: each ASCII
/// `solid NAME` (unnamed: the file's stem, numbered when there are several), the whole binary file
/// (its stem). Every patch gets defaultMaterial(); STL has no units (Scene::unit stays empty).
/// Vertices with bitwise-equal coordinates (-0 = +0) become one vertex. The vertex order decides the
/// emitting side (right-hand rule, as OBJ faces); facet normals against it are counted warnings.
/// Throws hemirad::Error on malformed input; zero-area and duplicate triangles are counted warnings.
Scene loadStl(const std::string& path, Warnings& warnings);

/// The parser behind loadStl, on bytes in memory; `file` names it in messages and its stem names
/// the unnamed objects.
Scene parseStl(const std::string& file, std::string_view bytes, Warnings& warnings);

}  // namespace hemirad
