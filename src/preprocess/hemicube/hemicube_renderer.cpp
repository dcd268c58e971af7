// The hemicube pass on OpenGL: reversed-Z float depth, five viewports, one draw per hemicube.
#include "preprocess/hemicube/hemicube_renderer.hpp"

#include "engine/error.hpp"
#include "gl/shader_library.hpp"
#include "preprocess/hemicube/hemicube_row_pool.hpp"
#include "preprocess/form_factor_backend.hpp"
#include "rays/mirror_chain.hpp"

#include <chrono>
#include <map>

namespace hemirad {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// A layer's header in the GPU reduction's touched buffer (hemicube_reduce.comp): the headers of
/// all the atlas's layers first (whatever a pass draws), then the lists.
///   | count | missed | backfaces | lost | roundedLost |
constexpr std::size_t kTouchedHeader = 5;
/// roundedLost counts in units of 1 / (fixedScale x this): a rounded pixel adds at most 32 of them,
/// so even all 3 x 4096^2 pixels of the largest common atlas stay below 2^32.
constexpr double kRoundedScale = 64.0;

}  // namespace

HemicubeRenderer::HemicubeRenderer(const Scene& scene, const HemicubeGeometry& geometry, const HemicubeLayout& layout,
                                   Reduction reduction, const MirrorLimits& mirrors, std::uint32_t layers,
                                   std::uint32_t inFlight, std::mutex* exclusive)
    : m_exclusive(exclusive), m_lifetimeLock(lockDriver()), m_scene(scene), m_geometry(geometry), m_layout(layout),
      m_reduction(reduction), m_layers(std::max(1u, layers)), m_limits(mirrors), m_mirrors(scene.hasMirrors()), m_near(1e-6 * geometry.extent) {
    if (m_limits.maxDepth > 254) throw Error("hemicube: --max-depth is limited to 254 (8-bit stencil)");
    if (reduction == Reduction::Auto) throw Error("internal: the hemicube renderer needs a resolved --reduce");
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
    // Portals after a GPU reduction read layer 0 back.
    if (reduction == Reduction::Gpu && m_mirrors) m_pixels.resize(std::size_t(W) * std::size_t(H));
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
        m_plan = gl::buildProgram({"hemicube_plan.comp"});
        m_layoutBuffer = gl::makeBuffer();
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_layoutBuffer.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr((3 + 2 * std::size_t(m_layers)) * 4), nullptr, GL_DYNAMIC_COPY);
        // Fixed point: a row sums to at most 1 (no mirrors), so 2^31 units per 1 cannot overflow.
        m_fixedScale = 2147483648.0;
    }
    // With one pass in flight nothing overlaps: the CPU reduction then reads into plain memory
    // (Mesa's read-back into a buffer object costs llvmpipe 0.37 ms a row at R = 256, 8x the plain one).
    m_inFlight = std::max(1u, inFlight);
    m_slots.resize(m_inFlight);
    for (Slot& slot : m_slots) makeSlot(slot, m_layers, m_slots.size() > 1);
    makeSlot(m_rowSlot, 1, false);
    gl::check("setting up the hemicube renderer");
    if (m_lifetimeLock) m_lifetimeLock.unlock();
}

HemicubeRenderer::~HemicubeRenderer() {
    m_lifetimeLock = lockDriver();
    for (Slot& slot : m_slots) releaseSlot(slot);
    releaseSlot(m_rowSlot);
}

void HemicubeRenderer::makeSlot(Slot& slot, std::uint32_t layers, bool overlapped) {
    if (m_reduction == Reduction::Cpu && !overlapped) {
        slot.host.resize(layers * m_layout.weights().size());
        slot.data = slot.host.data();
        return;
    }
    const std::size_t words = m_reduction == Reduction::Cpu ? layers * m_layout.weights().size()
                                                             : 6 * std::size_t(layers) + 1 + 2 * m_capacity * layers;
    const auto bytes = GLsizeiptr(words * 4);
    slot.buffer = gl::makeBuffer();
    gl::BindBuffer(GL_COPY_WRITE_BUFFER, slot.buffer.id());
    // Host memory the GPU writes into (client storage), mapped once: no copy, no map per pass.
    const GLbitfield access = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    gl::BufferStorage(GL_COPY_WRITE_BUFFER, bytes, nullptr, access | GL_CLIENT_STORAGE_BIT);
    slot.data = static_cast<const std::uint32_t*>(gl::MapBufferRange(GL_COPY_WRITE_BUFFER, 0, bytes, access));
    if (!slot.data) throw Error("hemicube: cannot map a " + std::to_string(bytes) + "-byte result buffer");
    gl::GenQueries(3, slot.queries);
    gl::BindBuffer(GL_COPY_WRITE_BUFFER, 0);
}

void HemicubeRenderer::releaseSlot(Slot& slot) {
    if (slot.fence) gl::DeleteSync(slot.fence);
    slot.fence = nullptr;
    if (slot.queries[0]) gl::DeleteQueries(3, slot.queries);
    slot.queries[0] = 0;
}

void HemicubeRenderer::clearAtlas(std::size_t count) {
    if (m_reduction == Reduction::Gpu) gl::MemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT);  // after the last pass's image loads
    if (count < m_layers) {
        // Only the layers this pass draws (a mirror row's hemicube, a last short pass): the whole
        // array would be 3 R^2 x 12 bytes a layer.
        const GLuint zero = 0;
        gl::ClearTexSubImage(m_ids.id(), 0, 0, 0, 0, GLsizei(m_layout.width()), GLsizei(m_layout.height()),
                             GLsizei(count), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        if (m_mirrors) {
            const struct {
                float depth;
                std::uint32_t stencil;
            } farStencil{0.0f, 0};
            gl::ClearTexSubImage(m_depth.id(), 0, 0, 0, 0, GLsizei(m_layout.width()), GLsizei(m_layout.height()),
                                 GLsizei(count), GL_DEPTH_STENCIL, GL_FLOAT_32_UNSIGNED_INT_24_8_REV, &farStencil);
        } else {
            const GLfloat farDepth = 0.0f;
            gl::ClearTexSubImage(m_depth.id(), 0, 0, 0, 0, GLsizei(m_layout.width()), GLsizei(m_layout.height()),
                                 GLsizei(count), GL_DEPTH_COMPONENT, GL_FLOAT, &farDepth);
        }
        return;
    }
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
    clearAtlas(1);
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

void HemicubeRenderer::submit(const std::vector<HemicubeItem>& items, HemicubeStats& stats) {
    if (items.size() > m_layers || items.empty())
        throw Error("internal: a hemicube pass of " + std::to_string(items.size()) + " hemicubes for an atlas of " +
                    std::to_string(m_layers) + " layers");
    if (m_busy == m_inFlight) throw Error("internal: every hemicube pass slot is in flight");
    Slot& slot = m_slots[(m_first + m_busy) % m_slots.size()];
    if (m_pool && slot.rowsLeft->load(std::memory_order_acquire) != 0) {
        const auto t0 = Clock::now();
        m_pool->waitFor([&slot] { return slot.rowsLeft->load(std::memory_order_acquire) == 0; });
        stats.wait += since(t0);
    }
    const auto lock = lockDriver();
    const auto t0 = Clock::now();
    ++m_busy;
    slot.items = items;
    if (slot.queries[0]) gl::QueryCounter(slot.queries[0], GL_TIMESTAMP);
    clearAtlas(items.size());
    m_instances.resize(items.size());
    for (std::size_t k = 0; k < items.size(); ++k) {
        const PatchId i = items[k].patch;
        m_instances[k].frameFromWorld = frameOf(items[k].origin - m_geometry.centre, m_scene.patches[i].normal).cast<float>();
        m_instances[k].skipCode = m_geometry.codeOfPatch[i];
    }
    drawInstances(Pass{});
    stats.render += since(t0);
    startResults(slot, items.size(), stats);
    stats.hemicubes += items.size();
    stats.pixels += items.size() * m_layout.weights().size();
    gl::check("drawing a pass of hemicubes");
}

void HemicubeRenderer::useRowPool(HemicubeRowPool* pool) {
    if (m_busy) throw Error("internal: a row pool joins a hemicube renderer with passes in flight");
    if (pool && !m_pool) {
        const auto lock = lockDriver();
        m_slots.emplace_back();
        makeSlot(m_slots.back(), m_layers, m_slots.front().host.empty());
    }
    m_pool = pool;
}

void HemicubeRenderer::handToPool(Slot& slot) {
    std::size_t rows = 0;
    forEachRow(slot.items, [&rows](std::size_t, std::size_t) { ++rows; });
    slot.rowsLeft->store(rows, std::memory_order_release);
    forEachRow(slot.items, [this, &slot](std::size_t first, std::size_t last) {
        m_pool->post([this, &slot, first, last](RowAccumulator& row, HemicubeStats& stats) {
            const PatchId patch = slot.items[first].patch;
            reduceRow(slot, first, last, row, stats);
            slot.rowsLeft->fetch_sub(1, std::memory_order_acq_rel);  // the slot is not read after this
            return patch;
        });
    });
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
    auto lock = lockDriver();
    auto t0 = Clock::now();
    if (m_rowSlot.queries[0]) gl::QueryCounter(m_rowSlot.queries[0], GL_TIMESTAMP);
    beginRow(i, origin, weight);
    Pass direct;
    direct.skipCode = m_geometry.codeOfPatch[i];
    draw(direct);
    stats.render += since(t0);
    startResults(m_rowSlot, 1, stats);
    await(m_rowSlot, stats);
    if (lock) lock.unlock();
    reduceLayer(m_rowSlot, 0, 1, m_weight, row, stats);
    ++stats.hemicubes;
    stats.pixels += m_layout.weights().size();
    if (m_exclusive) lock.lock();  // the portals' draws, and the check below
    if (m_mirrors) {
        // Portals only run for rows that see a mirror (Sillion & Puech extended form factors).
        t0 = Clock::now();
        const std::size_t n = m_layout.weights().size();
        const std::uint32_t* ids = m_rowSlot.data;
        if (m_reduction == Reduction::Gpu) {
            readPixels(m_pixels, stats);
            ids = m_pixels.data();
        }
        if (m_limits.rays) {
            traceMirrorPixels(i, ids, row, stats);
        } else {
            std::vector<std::uint32_t> everything(n);
            for (std::size_t k = 0; k < n; ++k) everything[k] = static_cast<std::uint32_t>(k);
            const std::vector<std::uint32_t> levelIds(ids, ids + n);
            traversePortals(1, levelIds, everything, Eigen::Matrix4d::Identity(), m_weight, row, stats);
        }
        stats.mirrors += since(t0);
    }
    gl::check("computing a hemicube");
}

void HemicubeRenderer::traceMirrorPixels(PatchId i, const std::uint32_t* ids, RowAccumulator& row,
                                         HemicubeStats& stats) {
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
                const std::uint32_t id = ids[k];
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

void HemicubeRenderer::startResults(Slot& slot, std::size_t count, HemicubeStats& stats) {
    auto t0 = Clock::now();  // issuing commands counts as render, a read that waits as readback
    const auto W = GLuint(m_layout.width()), H = GLuint(m_layout.height());
    if (slot.queries[0]) gl::QueryCounter(slot.queries[1], GL_TIMESTAMP);
    if (m_reduction == Reduction::Cpu) {
        // The layers' ids into the slot: a pixel-pack buffer (the call returns before the copy
        // runs), or plain memory (after a Finish, so the draw is render's time and the copy readback's).
        gl::PixelStorei(GL_PACK_ALIGNMENT, 4);
        const auto bytes = GLsizei(count * m_layout.weights().size() * 4);
        if (slot.host.empty()) {
            gl::BindBuffer(GL_PIXEL_PACK_BUFFER, slot.buffer.id());
            gl::GetTextureSubImage(m_ids.id(), 0, 0, 0, 0, GLsizei(W), GLsizei(H), GLsizei(count), GL_RED_INTEGER,
                                   GL_UNSIGNED_INT, bytes, nullptr);
            gl::BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        } else {
            gl::Finish();
            stats.render += since(t0);
            t0 = Clock::now();
            gl::GetTextureSubImage(m_ids.id(), 0, 0, 0, 0, GLsizei(W), GLsizei(H), GLsizei(count), GL_RED_INTEGER,
                                   GL_UNSIGNED_INT, bytes, slot.host.data());
            stats.readback += since(t0);
            return;  // read at once: nothing left to wait for, nothing timed
        }
    } else {
        // Reduce every layer into its dense fixed-point row and touched list; plan where each
        // layer's pairs go; gather them into the slot. No result comes back before the fence.
        const auto layers = GLuint(count);
        const auto patches = GLuint(std::max<std::size_t>(1, m_scene.size()));
        gl::BindImageTexture(0, m_ids.id(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_R32UI);
        gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m_weights.id());
        gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m_accumulator.id());
        gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m_touched.id());
        gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, slot.buffer.id());
        gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, m_layoutBuffer.id());
        gl::MemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        m_reduce.use();
        gl::Uniform2ui(m_reduce.uniform("size"), W, H);
        gl::Uniform1ui(m_reduce.uniform("patches"), patches);
        gl::Uniform1ui(m_reduce.uniform("atlasLayers"), GLuint(m_layers));
        gl::Uniform1ui(m_reduce.uniform("capacity"), GLuint(m_capacity));
        gl::Uniform1f(m_reduce.uniform("fixedScale"), float(m_fixedScale));
        gl::Uniform1f(m_reduce.uniform("roundedScale"), float(kRoundedScale));
        gl::DispatchCompute((W + 15) / 16, (H + 15) / 16, layers);
        gl::MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        m_plan.use();
        gl::Uniform1ui(m_plan.uniform("layers"), layers);
        gl::DispatchCompute(1, 1, 1);
        gl::MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
        m_collect.use();
        gl::Uniform1ui(m_collect.uniform("layers"), layers);
        gl::Uniform1ui(m_collect.uniform("atlasLayers"), GLuint(m_layers));
        gl::Uniform1ui(m_collect.uniform("patches"), patches);
        gl::Uniform1ui(m_collect.uniform("capacity"), GLuint(m_capacity));
        gl::BindBuffer(GL_DISPATCH_INDIRECT_BUFFER, m_layoutBuffer.id());
        gl::DispatchComputeIndirect(0);
        gl::BindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
        gl::MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
    }
    gl::QueryCounter(slot.queries[2], GL_TIMESTAMP);
    if (slot.fence) gl::DeleteSync(slot.fence);
    slot.fence = gl::FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    gl::Flush();  // the pass starts now, not when the CPU next waits
    stats.render += since(t0);
}

void HemicubeRenderer::await(Slot& slot, HemicubeStats& stats) {
    const auto t0 = Clock::now();
    while (slot.fence) {
        const GLenum status = gl::ClientWaitSync(slot.fence, GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000ull);
        if (status == GL_ALREADY_SIGNALED || status == GL_CONDITION_SATISFIED) break;
        if (status == GL_WAIT_FAILED) throw Error("hemicube: waiting for a pass failed (" + gl::describeContext() + ")");
    }
    if (slot.fence) gl::DeleteSync(slot.fence);
    slot.fence = nullptr;
    stats.wait += since(t0);
    if (!slot.queries[0]) return;
    GLuint64 t[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) gl::GetQueryObjectui64v(slot.queries[k], GL_QUERY_RESULT, &t[k]);
    stats.gpuDraw += 1e-9 * double(t[1] - t[0]);
    stats.gpuFinish += 1e-9 * double(t[2] - t[1]);
}

void HemicubeRenderer::reduceLayer(const Slot& slot, std::size_t k, std::size_t count, double weight,
                                   RowAccumulator& row, HemicubeStats& stats) const {
    if (m_reduction == Reduction::Cpu) {
        reduceIds(slot.data + k * m_layout.weights().size(), weight, row, stats);
        return;
    }
    const auto t0 = Clock::now();
    const double unit = weight / m_fixedScale;
    const std::uint32_t* header = slot.data + kTouchedHeader * k;
    const std::uint32_t* pairs = slot.data + 6 * count + 1 + 2 * std::size_t(slot.data[kTouchedHeader * count + k]);
    for (std::uint32_t e = 0; e < header[0]; ++e) row.addWeight(pairs[2 * e], pairs[2 * e + 1] * unit);
    stats.missed += header[1];
    stats.backfaces += header[2];
    stats.lostWeight += (header[3] + header[4] / kRoundedScale) * unit;
    stats.reduce += since(t0);
}

void HemicubeRenderer::reduceIds(const std::uint32_t* ids, double weight, RowAccumulator& row,
                                 HemicubeStats& stats) const {
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
