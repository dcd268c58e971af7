// RAII owners for GL objects, shader programs with their info logs in errors, framebuffer checks.
#pragma once

#include "gl/gl_api.hpp"

#include <string>
#include <utility>
#include <vector>

namespace hemirad::gl {

/// Owns one GL name; deleted with the context current. Move-only.
template <void (*Delete)(GLuint)>
class Object {
public:
    Object() = default;
    explicit Object(GLuint id) : m_id(id) {}
    ~Object() { reset(); }
    Object(Object&& o) noexcept : m_id(std::exchange(o.m_id, 0)) {}
    Object& operator=(Object&& o) noexcept {
        if (this != &o) {
            reset();
            m_id = std::exchange(o.m_id, 0);
        }
        return *this;
    }
    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;
    GLuint id() const { return m_id; }
    void reset() {
        if (m_id) Delete(m_id);
        m_id = 0;
    }

private:
    GLuint m_id = 0;
};

void deleteBuffer(GLuint id);
void deleteTexture(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteRenderbuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteProgram(GLuint id);

using Buffer = Object<deleteBuffer>;
using Texture = Object<deleteTexture>;
using Framebuffer = Object<deleteFramebuffer>;
using Renderbuffer = Object<deleteRenderbuffer>;
using VertexArray = Object<deleteVertexArray>;

Buffer makeBuffer();
Texture makeTexture();
Framebuffer makeFramebuffer();
Renderbuffer makeRenderbuffer();
VertexArray makeVertexArray();

/// One shader stage: its type (GL_VERTEX_SHADER, ...), a name for messages and the GLSL text.
struct Stage {
    GLenum type;
    std::string name;
    std::string text;
};

/// A linked program. Compile and link failures throw hemirad::Error with the stage name and log.
class Program {
public:
    Program() = default;
    explicit Program(const std::vector<Stage>& stages);
    GLuint id() const { return m_program.id(); }
    void use() const { UseProgram(m_program.id()); }
    /// Uniform location; -1 (ignored by glUniform) when the linker dropped it.
    GLint uniform(const char* name) const { return GetUniformLocation(m_program.id(), name); }

private:
    Object<deleteProgram> m_program;
};

/// Throws hemirad::Error naming the framebuffer status unless the bound framebuffer is complete.
void checkFramebuffer(const char* what);

}  // namespace hemirad::gl
