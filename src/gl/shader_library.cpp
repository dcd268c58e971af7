// Lookup of embedded shaders.
#include "gl/shader_library.hpp"

#include "engine/error.hpp"

namespace hemirad::gl {

const char* shaderText(const std::string& name) {
    for (const detail::EmbeddedShader* s = detail::kEmbeddedShaders; s->name; ++s)
        if (name == s->name) return s->text;
    throw Error("internal: no embedded shader '" + name + "'");
}

Program buildProgram(const std::vector<std::string>& names, const std::string& defines) {
    std::vector<Stage> stages;
    for (const std::string& name : names) {
        const std::string ext = name.substr(name.rfind('.') + 1);
        GLenum type = GL_VERTEX_SHADER;
        if (ext == "geom") type = GL_GEOMETRY_SHADER;
        else if (ext == "frag") type = GL_FRAGMENT_SHADER;
        else if (ext == "comp") type = GL_COMPUTE_SHADER;
        else if (ext != "vert") throw Error("internal: shader '" + name + "' has no stage extension");
        std::string text = shaderText(name);
        if (!defines.empty()) {
            const std::size_t eol = text.find('\n');
            std::string block;
            std::size_t start = 0;
            while (start < defines.size()) {
                std::size_t end = defines.find('\n', start);
                if (end == std::string::npos) end = defines.size();
                if (end > start) block += "#define " + defines.substr(start, end - start) + "\n";
                start = end + 1;
            }
            text.insert(eol == std::string::npos ? text.size() : eol + 1, block);
        }
        stages.push_back({type, name, text});
    }
    return Program(stages);
}

}  // namespace hemirad::gl
