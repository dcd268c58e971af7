// GL object helpers.
#include "gl/gl_objects.hpp"

#include "engine/error.hpp"

#include <cstdio>

namespace hemirad::gl {

void deleteBuffer(GLuint id) { DeleteBuffers(1, &id); }
void deleteTexture(GLuint id) { DeleteTextures(1, &id); }
void deleteFramebuffer(GLuint id) { DeleteFramebuffers(1, &id); }
void deleteRenderbuffer(GLuint id) { DeleteRenderbuffers(1, &id); }
void deleteVertexArray(GLuint id) { DeleteVertexArrays(1, &id); }
void deleteProgram(GLuint id) { DeleteProgram(id); }

namespace {
/// One fresh name from a glGen* function (they all share this signature).
GLuint generate(PFNGLGENBUFFERSPROC gen) {
    GLuint id = 0;
    gen(1, &id);
    return id;
}
}  // namespace

Buffer makeBuffer() { return Buffer(generate(GenBuffers)); }
Texture makeTexture() { return Texture(generate(GenTextures)); }
Framebuffer makeFramebuffer() { return Framebuffer(generate(GenFramebuffers)); }
Renderbuffer makeRenderbuffer() { return Renderbuffer(generate(GenRenderbuffers)); }
VertexArray makeVertexArray() { return VertexArray(generate(GenVertexArrays)); }

Program::Program(const std::vector<Stage>& stages) : m_program(CreateProgram()) {
    std::vector<GLuint> shaders;
    auto cleanup = [&] {
        for (GLuint s : shaders) DeleteShader(s);
    };
    for (const Stage& stage : stages) {
        const GLuint shader = CreateShader(stage.type);
        shaders.push_back(shader);
        const char* text = stage.text.c_str();
        ShaderSource(shader, 1, &text, nullptr);
        CompileShader(shader);
        GLint ok = 0;
        GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            GLint length = 0;
            GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
            std::string log(std::size_t(std::max(length, 1)), '\0');
            GetShaderInfoLog(shader, length, nullptr, log.data());
            cleanup();
            throw Error("OpenGL: shader " + stage.name + " does not compile:\n" + log.c_str());
        }
        AttachShader(m_program.id(), shader);
    }
    LinkProgram(m_program.id());
    cleanup();
    GLint ok = 0;
    GetProgramiv(m_program.id(), GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        GetProgramiv(m_program.id(), GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        GetProgramInfoLog(m_program.id(), length, nullptr, log.data());
        std::string names;
        for (const auto& stage : stages) names += (names.empty() ? "" : " + ") + stage.name;
        throw Error("OpenGL: program " + names + " does not link:\n" + log.c_str());
    }
}

void checkFramebuffer(const char* what) {
    const GLenum status = CheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status == GL_FRAMEBUFFER_COMPLETE) return;
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", status);
    throw Error(std::string("OpenGL: framebuffer for ") + what + " is incomplete (status " + code + ")");
}

}  // namespace hemirad::gl
