// The hemicube pass on OpenGL: reversed-Z float depth, five viewports, one draw per hemicube.
#include "preprocess/hemicube/hemicube_renderer.hpp"

#include "engine/error.hpp"
#include "gl/shader_library.hpp"
#include "preprocess/form_factor_backend.hpp"
#include "rays/mirror_chain.hpp"

#include <chrono>
#include <map>

namespace hemirad {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// A layer's header in the GPU reduction's touched buffer (hemicube_reduce.comp), all layers'
/// headers first, then their lists:  | count | missed | backfaces | lost | roundedLost |
constexpr std::size_t kTouchedHeader = 5;
/// roundedLost counts in units of 1 / (fixedScale x this): a rounded pixel adds at most 32 of them,
/// so even all 3 x 4096^2 pixels of the largest common atlas stay below 2^32.
constexpr double kRoundedScale = 64.0;

}  // namespace

HemicubeRenderer::HemicubeRenderer(const Scene& scene, const HemicubeGeometry& geometry, const HemicubeLayout& layout,
                                   Reduction reduction, const MirrorLimits& mirrors, std::uint32_t layers)
    : m_scene(scene), m_geometry(geometry), m_layout(layout), m_reduction(reduction), m_layers(std::max(1u, layers)),
      m_limits(mirrors), m_mirrors(scene.hasMirrors()), m_near(1e-6 * geometry.extent) {
    if (m_limits.maxDepth > 254) throw Error("hemicube: --max-depth is limited to 254 (8-bit stencil)");
    {
        MirrorGroups groups = groupMirrors(scene);
        m_groupOfPatch = std::move(groups.groupOfPatch);
        m_groupPatch = std::move(groups.representative);
    }
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

    // Id atlas array (R32UI, a layer per hemicube of a pass) + float depth; reversed Z keeps
    // precision over the whole scene.
    const auto W = GLsizei(layout.width()), H = GLsizei(layout.height()), L = GLsizei(m_layers);
    m_ids = gl::makeTexture();
    gl::BindTexture(GL_TEXTURE_2D_ARRAY, m_ids.id());
    gl::TexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_R32UI, W, H, L);
    m_depth = gl::makeTexture();
    gl::BindTexture(GL_TEXTURE_2D_ARRAY, m_depth.id());
    // The stencil marks mirror portals; scenes without mirrors skip it (less memory traffic).
    gl::TexStorage3D(GL_TEXTURE_2D_ARRAY, 1, m_mirrors ? GL_DEPTH32F_STENCIL8 : GL_DEPTH_COMPONENT32F, W, H, L);
    m_fbo = gl::makeFramebuffer();
    gl::BindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    gl::FramebufferTexture(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, m_ids.id(), 0);
    gl::FramebufferTexture(GL_FRAMEBUFFER, m_mirrors ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT, m_depth.id(), 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0};
    gl::DrawBuffers(1, buffers);
    gl::checkFramebuffer("the hemicube atlas");
    m_instanceBuffer = gl::makeBuffer();
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_instanceBuffer.id());
    gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(m_layers * sizeof(Instance)), nullptr, GL_DYNAMIC_DRAW);
    static_assert(sizeof(Instance) == 80, "hemicube.vert's Hemicube block: mat4 + uvec4 (std430)");

    gl::ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    gl::Enable(GL_DEPTH_TEST);
    gl::DepthFunc(GL_GREATER);
    gl::Enable(GL_SCISSOR_TEST);
    for (int f = 0; f < 5; ++f) {
        const auto& v = layout.viewport(f);
        gl::ViewportIndexedf(GLuint(f), float(v.x), float(v.y), float(v.width), float(v.height));
        gl::ScissorIndexed(GLuint(f), v.x, v.y, v.width, v.height);
    }
    // The read-back atlas: every layer for the CPU reduction, layer 0 for portals after a GPU one.
    m_pixels.resize(std::size_t(W) * std::size_t(H) * (reduction == Reduction::Cpu ? m_layers : 1u));
    if (m_mirrors) {
        m_portal = gl::buildProgram({"hemicube_portal.vert", "hemicube_portal.frag"});
        m_groups = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_groups.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(m_groupOfPatch.size() * 4), m_groupOfPatch.data(),
                       GL_STATIC_DRAW);
        m_levelIds = gl::makeTexture();
        gl::BindTexture(GL_TEXTURE_2D, m_levelIds.id());
        gl::TexStorage2D(GL_TEXTURE_2D, 1, GL_R32UI, W, H);
        gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }

    if (reduction == Reduction::Gpu) {
        m_reduce = gl::buildProgram({"hemicube_reduce.comp"});
        m_collect = gl::buildProgram({"hemicube_collect.comp"});
        m_weights = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_weights.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(layout.weights().size() * sizeof(float)),
                       layout.weights().data(), GL_STATIC_DRAW);
        // Per layer: the dense fixed-point row, and a touched list as long as the row can have
        // nonzeros (at most one per pixel and per patch).
        const std::size_t patches = std::max<std::size_t>(1, scene.size());
        m_capacity = std::min<std::size_t>(patches, m_layout.weights().size());
        m_accumulator = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_accumulator.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(patches * m_layers * 4), nullptr, GL_DYNAMIC_COPY);
        const GLuint zero = 0;
        gl::ClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        m_touched = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_touched.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr((kTouchedHeader + m_capacity) * m_layers * 4), nullptr,
                       GL_DYNAMIC_COPY);
        gl::ClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        m_values = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_values.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(m_capacity * m_layers * 8), nullptr, GL_DYNAMIC_COPY);
        // Fixed point: a row sums to at most 1 (no mirrors), so 2^31 units per 1 cannot overflow.
        m_fixedScale = 2147483648.0;
    }
    gl::check("setting up the hemicube renderer");
}

HemicubeRenderer::~HemicubeRenderer() = default;

void HemicubeRenderer::clearAtlas() {
    gl::BindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    const GLuint zero[4] = {0, 0, 0, 0};
    gl::Disable(GL_SCISSOR_TEST);
    gl::ClearBufferuiv(GL_COLOR, 0, zero);  // every layer of the layered attachment
    if (m_mirrors) {
        gl::ClearBufferfi(GL_DEPTH_STENCIL, 0, 0.0f, 0);
    } else {
        const GLfloat farDepth = 0.0f;
        gl::ClearBufferfv(GL_DEPTH, 0, &farDepth);
    }
    gl::Enable(GL_SCISSOR_TEST);
}

void HemicubeRenderer::beginRow(PatchId i, const Vec3& origin, double weight) {
    const Patch& p = m_scene.patches[i];
    m_eye = origin - m_geometry.centre;
    m_weight = weight;
    m_normal = p.normal;
    Vec3 t, b;
    orthonormalBasis(p.normal, t, b);
    // Top face: symmetric 90-degree frustum; sides: the upper half (elevation 0..45 degrees).
    m_faces = hemicubeFaces(p.normal, t, b);
    clearAtlas();
}

Eigen::Matrix4d HemicubeRenderer::frameOf(const Vec3& eye, const Vec3& normal) const {
    // Rows t, b, n about the eye.
    Vec3 t, b;
    orthonormalBasis(normal, t, b);
    Eigen::Matrix4d frame = Eigen::Matrix4d::Identity();
    frame.block<1, 3>(0, 0) = t.transpose();
    frame.block<1, 3>(1, 0) = b.transpose();
    frame.block<1, 3>(2, 0) = normal.transpose();
    frame.block<3, 1>(0, 3) = -frame.block<3, 3>(0, 0) * eye;
    return frame;
}

void HemicubeRenderer::draw(const Pass& pass) {
    // World -> patch frame, after the portal chain's reflections.
    m_instances.resize(1);
    m_instances[0].frameFromWorld = (frameOf(m_eye, m_normal) * pass.transform).cast<float>();
    m_instances[0].skipCode = pass.skipCode;
    drawInstances(pass);
}

void HemicubeRenderer::drawInstances(const Pass& pass) {
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_instanceBuffer.id());
    gl::BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(m_instances.size() * sizeof(Instance)), m_instances.data());
    gl::FrontFace(pass.mirrored ? GL_CW : GL_CCW);
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_parents.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, m_instanceBuffer.id());
    gl::BindVertexArray(m_vao.id());
    for (int kind = 0; kind < 4; ++kind) {
        const GLint first = GLint(m_geometry.rangeStart[kind]);
        const GLsizei count = GLsizei(m_geometry.rangeStart[kind + 1] - m_geometry.rangeStart[kind]);
        if (count == 0) continue;
        const gl::Program& program = m_draw[kind];
        program.use();
        gl::Uniform1f(program.uniform("planeEpsilon"), pass.planeTest ? float(1e-6 * m_geometry.extent) : -3.0e38f);
        gl::Uniform1f(program.uniform("nearPlane"), float(m_near));
        gl::Uniform4f(program.uniform("clipPlane"), float(pass.clipPlane[0]), float(pass.clipPlane[1]),
                      float(pass.clipPlane[2]), float(pass.clipPlane[3]));
        gl::DrawArraysInstanced(GL_TRIANGLES, first, count, GLsizei(m_instances.size()));
    }
}

void HemicubeRenderer::drawBatch(const std::vector<HemicubeItem>& items, HemicubeStats& stats) {
    if (items.size() > m_layers) throw Error("internal: a hemicube batch of " + std::to_string(items.size()) +
                                             " exceeds the atlas's " + std::to_string(m_layers) + " layers");
    if (m_mirrors) throw Error("internal: hemicube batches are for scenes without mirrors");
    const auto t0 = Clock::now();
    clearAtlas();
    m_instances.resize(items.size());
    for (std::size_t k = 0; k < items.size(); ++k) {
        const PatchId i = items[k].patch;
        m_instances[k].frameFromWorld = frameOf(items[k].origin - m_geometry.centre, m_scene.patches[i].normal).cast<float>();
        m_instances[k].skipCode = m_geometry.codeOfPatch[i];
    }
    drawInstances(Pass{});
    gl::Finish();
    stats.render += since(t0);
    finishPass(items.size(), stats);
    stats.hemicubes += items.size();
    stats.pixels += items.size() * m_layout.weights().size();
    gl::check("computing a batch of hemicubes");
}

void HemicubeRenderer::readPixels(std::vector<std::uint32_t>& ids, HemicubeStats& stats) {
    const auto t0 = Clock::now();
    ids.resize(std::max(ids.size(), m_layout.weights().size()));
    gl::ReadBuffer(GL_COLOR_ATTACHMENT0);  // layer 0 of the layered attachment
    gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl::ReadPixels(0, 0, GLsizei(m_layout.width()), GLsizei(m_layout.height()), GL_RED_INTEGER, GL_UNSIGNED_INT,
                   ids.data());
    stats.readback += since(t0);
}

void HemicubeRenderer::computeRow(PatchId i, const Vec3& origin, double weight, RowAccumulator& row,
                                  HemicubeStats& stats) {
    auto t0 = Clock::now();
    beginRow(i, origin, weight);
    Pass direct;
    direct.skipCode = m_geometry.codeOfPatch[i];
    draw(direct);
    gl::Finish();
    stats.render += since(t0);
    finishPass(1, stats);
    reduceLayer(0, m_weight, row, stats);
    ++stats.hemicubes;
    stats.pixels += m_layout.weights().size();
    if (m_mirrors) {
        // Portals only run for rows that see a mirror (Sillion & Puech extended form factors).
        t0 = Clock::now();
        if (m_reduction == Reduction::Gpu) readPixels(m_pixels, stats);
        if (m_limits.rays) {
            traceMirrorPixels(i, row, stats);
        } else {
            const std::size_t n = m_layout.weights().size();
            std::vector<std::uint32_t> everything(n);
            for (std::size_t k = 0; k < n; ++k) everything[k] = static_cast<std::uint32_t>(k);
            const std::vector<std::uint32_t> levelIds(m_pixels.begin(), m_pixels.begin() + std::ptrdiff_t(n));
            traversePortals(1, levelIds, everything, Eigen::Matrix4d::Identity(), m_weight, row, stats);
        }
        stats.mirrors += since(t0);
    }
    gl::check("computing a hemicube");
}

void HemicubeRenderer::traceMirrorPixels(PatchId i, RowAccumulator& row, HemicubeStats& stats) {
    const Patch& patch = m_scene.patches[i];
    const Vec3 origin = m_eye + m_geometry.centre + m_limits.rays->originOffset() * patch.normal;
    const float* w = m_layout.weights().data();
    const MirrorChainLimits limits{m_limits.maxDepth, m_limits.minWeight};
    RayCounts counts;
    for (int f = 0; f < 5; ++f) {
        const auto& v = m_layout.viewport(f);
        for (int py = 0; py < v.height; ++py)
            for (int px = 0; px < v.width; ++px) {
                const std::size_t k = std::size_t(v.y + py) * m_layout.width() + std::size_t(v.x + px);
                const std::uint32_t id = m_pixels[k];
                if (id - 1u >= 0xfffffffeu || !m_groupOfPatch[id - 1u]) continue;
                // The pixel centre's direction: x in [-1, 1] across; top face y in [-1, 1], sides
                // elevation z in [0, 1] (physics.md §3 conventions).
                const double x = -1.0 + (px + 0.5) * 2.0 / v.width;
                const double y = f == 0 ? -1.0 + (py + 0.5) * 2.0 / v.height : (py + 0.5) / v.height;
                const Vec3 dir = (m_faces[f].forward + x * m_faces[f].right + y * m_faces[f].up).normalized();
                const RayScene::Hit hit = m_limits.rays->intersect(origin, dir);
                // Rasteriser and ray may disagree at a mirror's edge: then the pixel stays as drawn.
                if (hit.patch == RayScene::kNoHit || !(m_scene.patches[hit.patch].specular > 0.0)) continue;
                followMirrorChain(m_scene, *m_limits.rays, origin, dir, hit.patch, hit.t, w[k] * m_weight, 1.0, limits,
                                  [&row](PatchId p, double weight) { row.addWeight(p, weight); }, counts);
            }
    }
    stats.portals += counts.bounces;
    stats.lostWeight += counts.lostWeight;
    stats.cutoffWeight += counts.cutoffWeight;
    stats.missed += counts.misses;
    stats.backfaces += counts.backfaces;
}

void HemicubeRenderer::markPortal(std::uint32_t group, int depth, const std::vector<std::uint32_t>& levelIds) {
    const auto W = GLsizei(m_layout.width()), H = GLsizei(m_layout.height());
    gl::BindTexture(GL_TEXTURE_2D, m_levelIds.id());
    gl::PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    gl::TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RED_INTEGER, GL_UNSIGNED_INT, levelIds.data());
    gl::ActiveTexture(GL_TEXTURE0);
    // Full-atlas pass on viewport 0: inside the parent region (stencil = depth - 1), the pixels that
    // saw the mirror get stencil = depth, id 0 and far depth.
    gl::ViewportIndexedf(0, 0, 0, float(W), float(H));
    gl::ScissorIndexed(0, 0, 0, W, H);
    gl::DepthFunc(GL_ALWAYS);
    gl::Enable(GL_STENCIL_TEST);
    gl::StencilMask(0xff);
    gl::StencilFunc(GL_EQUAL, depth - 1, 0xff);
    gl::StencilOp(GL_KEEP, GL_KEEP, GL_INCR);  // depth - 1 -> depth
    m_portal.use();
    gl::Uniform1ui(m_portal.uniform("group"), group);
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m_groups.id());
    gl::BindTexture(GL_TEXTURE_2D, m_levelIds.id());
    gl::DrawArrays(GL_TRIANGLES, 0, 3);
    gl::Disable(GL_STENCIL_TEST);
    gl::DepthFunc(GL_GREATER);
    const auto& v = m_layout.viewport(0);
    gl::ViewportIndexedf(0, float(v.x), float(v.y), float(v.width), float(v.height));
    gl::ScissorIndexed(0, v.x, v.y, v.width, v.height);
}

void HemicubeRenderer::traversePortals(int depth, const std::vector<std::uint32_t>& levelIds,
                                       const std::vector<std::uint32_t>& region, const Eigen::Matrix4d& transform,
                                       double factor, RowAccumulator& row, HemicubeStats& stats) {
    // Pixels of the region by the mirror plane they see.
    std::map<std::uint32_t, std::vector<std::uint32_t>> portals;
    for (const std::uint32_t p : region) {
        const std::uint32_t id = levelIds[p];
        if (id - 1u < 0xfffffffeu && m_groupOfPatch[id - 1u]) portals[m_groupOfPatch[id - 1u] - 1u].push_back(p);
    }
    const float* w = m_layout.weights().data();
    for (const auto& [group, pixels] : portals) {
        const Patch& m = m_scene.patches[m_groupPatch[group]];
        const double f = factor * m.specular;
        // factor starts at the hemicube's weight: the cut-off is relative to it.
        if (std::uint32_t(depth) > m_limits.maxDepth || f < m_limits.minWeight * m_weight) {
            double cut = 0.0;
            for (const std::uint32_t p : pixels) cut += w[p];
            stats.cutoffWeight += cut * f;
            continue;
        }
        ++stats.portals;
        markPortal(group, depth, levelIds);
        // The portal's pixels show the world reflected in the mirror's plane (n . x + d = 0 in
        // scene-centred coordinates); only what lies in front of the mirror may appear.
        const Vec3 centre = m.centroid - m_geometry.centre;
        const double d = -m.normal.dot(centre);
        Pass pass;
        pass.transform = transform * reflectionMatrix(m.normal, d);
        pass.clipPlane = Eigen::Vector4d(m.normal.x(), m.normal.y(), m.normal.z(), d);
        pass.skipCode = m_geometry.codeOfPatch[m_groupPatch[group]];
        pass.mirrored = depth % 2 == 1;
        pass.planeTest = false;
        gl::Enable(GL_STENCIL_TEST);
        gl::Enable(GL_CLIP_DISTANCE0);
        gl::StencilFunc(GL_EQUAL, depth, 0xff);
        gl::StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
        draw(pass);
        gl::Disable(GL_CLIP_DISTANCE0);
        gl::Disable(GL_STENCIL_TEST);
        gl::FrontFace(GL_CCW);
        std::vector<std::uint32_t> ids;
        readPixels(ids, stats);
        double lost = 0.0;
        for (const std::uint32_t p : pixels) {
            const std::uint32_t id = ids[p];
            if (id - 1u < 0xfffffffeu) {
                row.addWeight(id - 1u, w[p] * f);
            } else {
                lost += w[p] * f;
                (id == 0 ? stats.missed : stats.backfaces) += 1;
            }
        }
        stats.lostWeight += lost;
        traversePortals(depth + 1, ids, pixels, pass.transform, f, row, stats);
    }
}

void HemicubeRenderer::finishPass(std::size_t count, HemicubeStats& stats) {
    const auto W = GLuint(m_layout.width()), H = GLuint(m_layout.height());
    const std::size_t layerPixels = m_layout.weights().size();
    if (m_reduction == Reduction::Cpu) {
        const auto t0 = Clock::now();
        gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
        gl::GetTextureSubImage(m_ids.id(), 0, 0, 0, 0, GLsizei(W), GLsizei(H), GLsizei(count), GL_RED_INTEGER,
                               GL_UNSIGNED_INT, GLsizei(count * layerPixels * 4), m_pixels.data());
        stats.readback += since(t0);
        return;
    }
    auto t0 = Clock::now();
    const auto layers = GLuint(count);
    gl::BindImageTexture(0, m_ids.id(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_R32UI);
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m_weights.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m_accumulator.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m_touched.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, m_values.id());
    gl::MemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    const auto patches = GLuint(std::max<std::size_t>(1, m_scene.size()));
    m_reduce.use();
    gl::Uniform2ui(m_reduce.uniform("size"), W, H);
    gl::Uniform1ui(m_reduce.uniform("patches"), patches);
    gl::Uniform1ui(m_reduce.uniform("layers"), layers);
    gl::Uniform1ui(m_reduce.uniform("capacity"), GLuint(m_capacity));
    gl::Uniform1f(m_reduce.uniform("fixedScale"), float(m_fixedScale));
    gl::Uniform1f(m_reduce.uniform("roundedScale"), float(kRoundedScale));
    gl::DispatchCompute((W + 15) / 16, (H + 15) / 16, layers);
    gl::MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    m_headers.resize(kTouchedHeader * count);
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_touched.id());
    gl::GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(m_headers.size() * 4), m_headers.data());
    // Each layer's pairs go to its place in one output block: one read-back for the whole pass.
    m_pairStart.assign(count + 1, 0);
    for (std::size_t k = 0; k < count; ++k) m_pairStart[k + 1] = m_pairStart[k] + m_headers[kTouchedHeader * k];
    m_collect.use();
    gl::Uniform1ui(m_collect.uniform("layers"), layers);
    gl::Uniform1ui(m_collect.uniform("patches"), patches);
    gl::Uniform1ui(m_collect.uniform("capacity"), GLuint(m_capacity));
    for (std::size_t k = 0; k < count; ++k) {
        const auto n = GLuint(m_headers[kTouchedHeader * k]);
        if (n == 0) continue;
        gl::Uniform1ui(m_collect.uniform("layer"), GLuint(k));
        gl::Uniform1ui(m_collect.uniform("offset"), GLuint(m_pairStart[k]));
        gl::Uniform1ui(m_collect.uniform("count"), n);
        gl::DispatchCompute((n + 63) / 64, 1, 1);
    }
    gl::MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    stats.reduce += since(t0);
    t0 = Clock::now();
    m_pairs.resize(2 * m_pairStart[count]);
    if (!m_pairs.empty()) {
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_values.id());
        gl::GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(m_pairs.size() * 4), m_pairs.data());
    }
    const GLuint zero = 0;  // the headers, for the next pass (the accumulator was cleared by collect)
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_touched.id());
    gl::ClearBufferSubData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, 0, GLsizeiptr(m_headers.size() * 4), GL_RED_INTEGER,
                           GL_UNSIGNED_INT, &zero);
    stats.readback += since(t0);
}

void HemicubeRenderer::reduceLayer(std::size_t k, double weight, RowAccumulator& row, HemicubeStats& stats) {
    if (m_reduction == Reduction::Cpu) {
        reduceIds(m_pixels.data() + k * m_layout.weights().size(), weight, row, stats);
        return;
    }
    const auto t0 = Clock::now();
    const double unit = weight / m_fixedScale;
    for (std::size_t e = m_pairStart[k]; e < m_pairStart[k + 1]; ++e)
        row.addWeight(m_pairs[2 * e], m_pairs[2 * e + 1] * unit);
    const std::uint32_t* header = &m_headers[kTouchedHeader * k];
    stats.missed += header[1];
    stats.backfaces += header[2];
    stats.lostWeight += (header[3] + header[4] / kRoundedScale) * unit;
    stats.reduce += since(t0);
}

void HemicubeRenderer::reduceIds(const std::uint32_t* ids, double weight, RowAccumulator& row, HemicubeStats& stats) {
    const auto t0 = Clock::now();
    // Neighbouring pixels mostly see the same patch: sum runs in a register, touch memory per run.
    const float* w = m_layout.weights().data();
    const std::size_t n = m_layout.weights().size();
    double lost = 0.0;
    std::size_t k = 0;
    while (k < n) {
        const std::uint32_t id = ids[k];
        double sum = w[k];
        const std::size_t start = k++;
        while (k < n && ids[k] == id) sum += w[k++];
        sum *= weight;
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

}  // namespace hemirad
