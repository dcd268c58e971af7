// The GLSL sources of shaders/, embedded in the binary at build time (cmake/EmbedShaders.cmake).
#pragma once

#include "gl/gl_objects.hpp"

#include <string>

namespace hemirad::gl {

/// The text of shaders/<name>; throws hemirad::Error for an unknown name.
const char* shaderText(const std::string& name);

/// Compiles and links shaders/<names...>; the stage follows the extension (.vert .geom .frag .comp).
/// `defines` ("NAME VALUE" lines) are inserted after each stage's #version line.
Program buildProgram(const std::vector<std::string>& names, const std::string& defines = {});

namespace detail {
struct EmbeddedShader {
    const char* name;
    const char* text;
};
extern const EmbeddedShader kEmbeddedShaders[];
}  // namespace detail

}  // namespace hemirad::gl
