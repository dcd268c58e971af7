// The hemicube pass on OpenGL: reversed-Z float depth, five viewports, one draw per hemicube.
#include "preprocess/hemicube/hemicube_renderer.hpp"

#include "engine/error.hpp"
#include "gl/shader_library.hpp"

#include <array>
#include <chrono>

namespace hemirad {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

using Mat4 = std::array<float, 16>;  // column-major

/// World -> clip for a camera at `eye` looking along `forward` with `up`, frustum [l, r] x [b, t]
/// at distance `near`, infinite far plane, reversed Z into [0, 1] (depth = near / distance).
Mat4 faceMatrix(const Vec3& eye, const Vec3& forward, const Vec3& up, double l, double r, double b, double t,
                double near) {
    const Vec3 right = forward.cross(up);
    Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
    view.block<1, 3>(0, 0) = right.transpose();
    view.block<1, 3>(1, 0) = up.transpose();
    view.block<1, 3>(2, 0) = -forward.transpose();
    view(0, 3) = -right.dot(eye);
    view(1, 3) = -up.dot(eye);
    view(2, 3) = forward.dot(eye);
    Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
    projection(0, 0) = 2 * near / (r - l);
    projection(0, 2) = (r + l) / (r - l);
    projection(1, 1) = 2 * near / (t - b);
    projection(1, 2) = (t + b) / (t - b);
    projection(2, 3) = near;
    projection(3, 2) = -1;
    const Eigen::Matrix4d m = projection * view;
    Mat4 out;
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) out[std::size_t(c * 4 + row)] = float(m(row, c));
    return out;
}

}  // namespace

HemicubeRenderer::HemicubeRenderer(const Scene& scene, const HemicubeGeometry& geometry, const HemicubeLayout& layout,
                                   Reduction reduction)
    : m_scene(scene), m_geometry(geometry), m_layout(layout), m_reduction(reduction) {
    for (int kind = 0; kind < 4; ++kind)
        if (geometry.rangeStart[kind + 1] > geometry.rangeStart[kind])
            m_draw[kind] = gl::buildProgram({"hemicube.vert", "hemicube.geom", "hemicube.frag"},
                                            "HEMICUBE_KIND " + std::to_string(kind));

    m_vao = gl::makeVertexArray();
    gl::BindVertexArray(m_vao.id());
    m_vertices = gl::makeBuffer();
    gl::BindBuffer(GL_ARRAY_BUFFER, m_vertices.id());
    gl::BufferData(GL_ARRAY_BUFFER, GLsizeiptr(geometry.vertices.size() * sizeof(HemicubeGeometry::Vertex)),
                   geometry.vertices.data(), GL_STATIC_DRAW);
    gl::EnableVertexAttribArray(0);
    gl::VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(HemicubeGeometry::Vertex), nullptr);
    gl::EnableVertexAttribArray(1);
    gl::VertexAttribIPointer(1, 1, GL_UNSIGNED_INT, sizeof(HemicubeGeometry::Vertex),
                             reinterpret_cast<const void*>(offsetof(HemicubeGeometry::Vertex, code)));
    gl::EnableVertexAttribArray(2);
    gl::VertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(HemicubeGeometry::Vertex),
                            reinterpret_cast<const void*>(offsetof(HemicubeGeometry::Vertex, u)));
    gl::EnableVertexAttribArray(3);
    gl::VertexAttribIPointer(3, 4, GL_UNSIGNED_INT, sizeof(HemicubeGeometry::Vertex),
                             reinterpret_cast<const void*>(offsetof(HemicubeGeometry::Vertex, grid)));
    m_parents = gl::makeBuffer();
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_parents.id());
    const HemicubeGeometry::ParentRecord none{};
    gl::BufferData(GL_SHADER_STORAGE_BUFFER,
                   GLsizeiptr(std::max<std::size_t>(1, geometry.parents.size()) * sizeof(HemicubeGeometry::ParentRecord)),
                   geometry.parents.empty() ? &none : static_cast<const void*>(geometry.parents.data()), GL_STATIC_DRAW);

    // Id atlas (R32UI) + float depth; reversed Z keeps precision over the whole scene.
    const auto W = GLsizei(layout.width()), H = GLsizei(layout.height());
    m_ids = gl::makeTexture();
    gl::BindTexture(GL_TEXTURE_2D, m_ids.id());
    gl::TexStorage2D(GL_TEXTURE_2D, 1, GL_R32UI, W, H);
    m_depth = gl::makeRenderbuffer();
    gl::BindRenderbuffer(GL_RENDERBUFFER, m_depth.id());
    gl::RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
    m_fbo = gl::makeFramebuffer();
    gl::BindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m_ids.id(), 0);
    gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m_depth.id());
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0};
    gl::DrawBuffers(1, buffers);
    gl::checkFramebuffer("the hemicube atlas");

    gl::ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    gl::Enable(GL_DEPTH_TEST);
    gl::DepthFunc(GL_GREATER);
    gl::Enable(GL_SCISSOR_TEST);
    for (int f = 0; f < 5; ++f) {
        const auto& v = layout.viewport(f);
        gl::ViewportIndexedf(GLuint(f), float(v.x), float(v.y), float(v.width), float(v.height));
        gl::ScissorIndexed(GLuint(f), v.x, v.y, v.width, v.height);
    }
    m_pixels.resize(std::size_t(W) * std::size_t(H));

    if (reduction == Reduction::Gpu) {
        m_reduce = gl::buildProgram({"hemicube_reduce.comp"});
        m_collect = gl::buildProgram({"hemicube_collect.comp"});
        m_weights = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_weights.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(layout.weights().size() * sizeof(float)),
                       layout.weights().data(), GL_STATIC_DRAW);
        const GLsizeiptr patches = GLsizeiptr(std::max<std::size_t>(1, scene.size()));
        std::vector<std::uint32_t> zeros(std::size_t(patches) + 4, 0);
        m_accumulator = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_accumulator.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, patches * 4, zeros.data(), GL_DYNAMIC_COPY);
        m_touched = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_touched.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, (patches + 4) * 4, zeros.data(), GL_DYNAMIC_COPY);
        m_values = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_values.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, patches * 4, nullptr, GL_DYNAMIC_COPY);
        // Fixed point: a row sums to at most 1 (no mirrors), so 2^31 units per 1 cannot overflow.
        m_fixedScale = 2147483648.0;
    }
    gl::check("setting up the hemicube renderer");
}

HemicubeRenderer::~HemicubeRenderer() = default;

void HemicubeRenderer::render(PatchId i) {
    const Patch& p = m_scene.patches[i];
    const Vec3 eye = p.centroid - m_geometry.centre;
    Vec3 t, b;
    orthonormalBasis(p.normal, t, b);
    const Vec3& n = p.normal;
    const double near = 1e-6 * m_geometry.extent;
    // Top face: symmetric 90-degree frustum; sides: the upper half (elevation 0..45 degrees).
    const Mat4 faces[5] = {faceMatrix(eye, n, b, -near, near, -near, near, near),
                           faceMatrix(eye, t, n, -near, near, 0, near, near),
                           faceMatrix(eye, -t, n, -near, near, 0, near, near),
                           faceMatrix(eye, b, n, -near, near, 0, near, near),
                           faceMatrix(eye, -b, n, -near, near, 0, near, near)};
    gl::BindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    const GLuint zero[4] = {0, 0, 0, 0};
    gl::Disable(GL_SCISSOR_TEST);
    gl::ClearBufferuiv(GL_COLOR, 0, zero);
    const GLfloat farDepth = 0.0f;
    gl::ClearBufferfv(GL_DEPTH, 0, &farDepth);
    gl::Enable(GL_SCISSOR_TEST);
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_parents.id());
    gl::BindVertexArray(m_vao.id());
    for (int kind = 0; kind < 4; ++kind) {
        const GLint first = GLint(m_geometry.rangeStart[kind]);
        const GLsizei count = GLsizei(m_geometry.rangeStart[kind + 1] - m_geometry.rangeStart[kind]);
        if (count == 0) continue;
        const gl::Program& program = m_draw[kind];
        program.use();
        gl::UniformMatrix4fv(program.uniform("faceMatrix"), 5, GL_FALSE, faces[0].data());
        gl::Uniform3f(program.uniform("eye"), float(eye.x()), float(eye.y()), float(eye.z()));
        gl::Uniform3f(program.uniform("normal"), float(n.x()), float(n.y()), float(n.z()));
        gl::Uniform1ui(program.uniform("skipCode"), m_geometry.codeOfPatch[i]);
        gl::Uniform1f(program.uniform("planeEpsilon"), float(1e-6 * m_geometry.extent));
        gl::Uniform1f(program.uniform("nearPlane"), float(near));
        gl::Uniform4f(program.uniform("clipPlane"), 0, 0, 0, 1);
        gl::DrawArrays(GL_TRIANGLES, first, count);
    }
}

void HemicubeRenderer::computeRow(PatchId i, RowAccumulator& row, HemicubeStats& stats) {
    auto t0 = Clock::now();
    render(i);
    gl::Finish();
    stats.render += since(t0);
    if (m_reduction == Reduction::Cpu) reduceOnCpu(row, stats);
    else reduceOnGpu(row, stats);
    ++stats.hemicubes;
    stats.pixels += m_pixels.size();
    gl::check("computing a hemicube");
}

std::vector<std::uint32_t> HemicubeRenderer::readIds() {
    gl::BindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    gl::ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
    std::vector<std::uint32_t> ids(m_pixels.size());
    gl::ReadPixels(0, 0, GLsizei(m_layout.width()), GLsizei(m_layout.height()), GL_RED_INTEGER, GL_UNSIGNED_INT,
                   ids.data());
    return ids;
}

void HemicubeRenderer::reduceOnCpu(RowAccumulator& row, HemicubeStats& stats) {
    auto t0 = Clock::now();
    gl::ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl::ReadPixels(0, 0, GLsizei(m_layout.width()), GLsizei(m_layout.height()), GL_RED_INTEGER, GL_UNSIGNED_INT,
                   m_pixels.data());
    stats.readback += since(t0);
    t0 = Clock::now();
    // Neighbouring pixels mostly see the same patch: sum runs in a register, touch memory per run.
    const float* w = m_layout.weights().data();
    const std::uint32_t* ids = m_pixels.data();
    const std::size_t n = m_pixels.size();
    double lost = 0.0;
    std::size_t k = 0;
    while (k < n) {
        const std::uint32_t id = ids[k];
        double sum = w[k];
        const std::size_t start = k++;
        while (k < n && ids[k] == id) sum += w[k++];
        if (id - 1u < 0xfffffffeu) {
            row.addWeight(id - 1u, sum);
        } else {
            lost += sum;
            (id == 0 ? stats.missed : stats.backfaces) += k - start;
        }
    }
    stats.lostWeight += lost;
    stats.reduce += since(t0);
}

void HemicubeRenderer::reduceOnGpu(RowAccumulator& row, HemicubeStats& stats) {
    auto t0 = Clock::now();
    const auto W = GLuint(m_layout.width()), H = GLuint(m_layout.height());
    gl::BindImageTexture(0, m_ids.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m_weights.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m_accumulator.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m_touched.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, m_values.id());
    gl::MemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    m_reduce.use();
    gl::Uniform2ui(m_reduce.uniform("size"), W, H);
    gl::Uniform1f(m_reduce.uniform("fixedScale"), float(m_fixedScale));
    gl::Uniform1f(m_reduce.uniform("factor"), 1.0f);
    gl::DispatchCompute((W + 15) / 16, (H + 15) / 16, 1);
    gl::MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    std::uint32_t header[4] = {};
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_touched.id());
    gl::GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof header, header);
    const std::uint32_t count = header[0];
    if (count > 0) {
        m_collect.use();
        gl::DispatchCompute((count + 63) / 64, 1, 1);
        gl::MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    stats.reduce += since(t0);
    t0 = Clock::now();
    std::vector<std::uint32_t> list(count), values(count);
    if (count > 0) {
        gl::GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 16, GLsizeiptr(count) * 4, list.data());
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_values.id());
        gl::GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(count) * 4, values.data());
    }
    const std::uint32_t zeros[4] = {0, 0, 0, 0};
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_touched.id());
    gl::BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zeros, zeros);
    stats.readback += since(t0);
    for (std::uint32_t k = 0; k < count; ++k) row.addWeight(list[k], values[k] / m_fixedScale);
    stats.missed += header[1];
    stats.backfaces += header[2];
    stats.lostWeight += header[3] / m_fixedScale;
}

}  // namespace hemirad
