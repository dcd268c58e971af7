// The viewer's GL passes: scene into six layers, mirror reflections through the stencil, present.
#include "ui/viewer.hpp"

#include "engine/error.hpp"
#include "engine/tone_map.hpp"
#include "gl/shader_library.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad::ui {
namespace {

struct Vertex {
    float x, y, z;
    std::uint32_t patch;
    float r, g, b;  // corner radiosity
};

struct PatchData {
    float radiosity[4];
    float emission[4];
    float reflectance[4];  // rho, s
};

// 0 patch ids (picking), 1 radiance, 2 emission, 3 reflectance, 4 specular, 5 level ids (the deepest
// mirror level drawn at each pixel: front faces only; the mirror passes read it).
constexpr int kLayers = 6;
const GLenum kLayerFormats[kLayers] = {GL_R32UI, GL_RGBA16F, GL_RGBA16F, GL_RGBA8, GL_RGBA8, GL_R32UI};
constexpr GLenum kAllLayers[kLayers] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                        GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4, GL_COLOR_ATTACHMENT5};
// A mirror pass adds to the radiance and records what it shows in the level ids; the other layers
// keep the mirror's own values (picking selects the mirror, not what it shows).
constexpr GLenum kMirrorLayers[kLayers] = {GL_NONE, GL_COLOR_ATTACHMENT1, GL_NONE, GL_NONE, GL_NONE, GL_COLOR_ATTACHMENT5};
// The stencil bit of finished portals; depths use the bits below it, so the viewer follows at most
// kRetired - 2 nested mirrors (F's --max-depth allows 254).
constexpr GLint kRetired = 0x80;

void colourWrites(bool on) {
    for (int k = 0; k < kLayers; ++k) gl::ColorMaski(GLuint(k), on, on, on, on);
}

}  // namespace

Viewer::Viewer() {
    m_scene = gl::buildProgram({"viewer_scene.vert", "viewer_scene.frag"});
    m_mark = gl::buildProgram({"viewer_present.vert", "viewer_mark.frag"});
    m_survey = gl::buildProgram({"viewer_present.vert", "viewer_survey.frag"});
    m_retire = gl::buildProgram({"viewer_present.vert", "viewer_retire.frag"});
    m_present = gl::buildProgram({"viewer_present.vert", "viewer_present.frag"});
    m_vao = gl::makeVertexArray();
    m_emptyVao = gl::makeVertexArray();
    m_vertices = gl::makeBuffer();
    m_patchData = gl::makeBuffer();
    m_flags = gl::makeBuffer();
    m_row = gl::makeBuffer();
    m_falseColours = gl::makeBuffer();
    const std::uint32_t none = 0;
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_falseColours.id());
    gl::BufferData(GL_SHADER_STORAGE_BUFFER, 4, &none, GL_DYNAMIC_DRAW);
    m_mirrorGroups = gl::makeBuffer();
    m_seenGroups = gl::makeBuffer();
    gl::BindVertexArray(m_vao.id());
    gl::BindBuffer(GL_ARRAY_BUFFER, m_vertices.id());
    gl::EnableVertexAttribArray(0);
    gl::VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), nullptr);
    gl::EnableVertexAttribArray(1);
    gl::VertexAttribIPointer(1, 1, GL_UNSIGNED_INT, sizeof(Vertex), reinterpret_cast<const void*>(offsetof(Vertex, patch)));
    gl::EnableVertexAttribArray(2);
    gl::VertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<const void*>(offsetof(Vertex, r)));
    gl::BindVertexArray(0);
    gl::check("creating the viewer");
}

Viewer::~Viewer() = default;

void Viewer::resize(int width, int height) {
    if (width == m_width && height == m_height) return;
    m_width = width;
    m_height = height;
    m_fbo = gl::makeFramebuffer();
    gl::BindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    for (int k = 0; k < kLayers; ++k) {
        m_layers[k] = gl::makeTexture();
        gl::BindTexture(GL_TEXTURE_2D, m_layers[k].id());
        gl::TexStorage2D(GL_TEXTURE_2D, 1, kLayerFormats[k], width, height);
        gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl::FramebufferTexture2D(GL_FRAMEBUFFER, kAllLayers[k], GL_TEXTURE_2D, m_layers[k].id(), 0);
    }
    gl::DrawBuffers(kLayers, kAllLayers);
    m_depth = gl::makeRenderbuffer();
    gl::BindRenderbuffer(GL_RENDERBUFFER, m_depth.id());
    gl::RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
    gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m_depth.id());
    gl::checkFramebuffer("the viewer's layers");
    m_idCopy = gl::makeTexture();
    gl::BindTexture(GL_TEXTURE_2D, m_idCopy.id());
    gl::TexStorage2D(GL_TEXTURE_2D, 1, GL_R32UI, width, height);
    // Integer textures sample only with NEAREST filters (the default mipmap filter leaves them incomplete).
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Viewer::upload(AppState& app) {
    if (!app.hasScene()) {
        m_vertexCount = 0;
        return;
    }
    const Scene& scene = app.scene();
    if (m_revision != app.revision()) {
        m_revision = app.revision();
        Vec3 lo, hi;
        scene.bounds(lo, hi);
        m_centre = 0.5 * (lo + hi);
        const std::vector<Rgb>& corner = app.cornerRadiosity();
        std::vector<Vertex> vertices;
        vertices.reserve(scene.corners.size() * 3);
        for (PatchId i = 0; i < scene.size(); ++i) {
            const Patch& p = scene.patches[i];
            auto push = [&](std::uint32_t k) {
                const Vec3 v = scene.corner(p, k) - m_centre;
                const Rgb& c = corner[p.firstCorner + k];
                vertices.push_back({float(v.x()), float(v.y()), float(v.z()), i, float(c[0]), float(c[1]), float(c[2])});
            };
            for (std::uint32_t k = 1; k + 1 < p.cornerCount; ++k) {
                push(0);
                push(k);
                push(k + 1);
            }
        }
        m_vertexCount = GLsizei(vertices.size());
        gl::BindBuffer(GL_ARRAY_BUFFER, m_vertices.id());
        gl::BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(Vertex)), vertices.data(), GL_DYNAMIC_DRAW);
        std::vector<PatchData> data(scene.size());
        std::vector<double> luminances;
        for (PatchId i = 0; i < scene.size(); ++i) {
            const Patch& p = scene.patches[i];
            const Rgb& B = app.radiosity()[i];
            for (int c = 0; c < 3; ++c) {
                data[i].radiosity[c] = float(B[c]);
                data[i].emission[c] = float(p.emission[c]);
                data[i].reflectance[c] = float(p.rho[c]);
            }
            data[i].reflectance[3] = float(p.specular);
            if (!(p.emission > 0.0).any()) luminances.push_back(luminance(B) / kPi);
        }
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_patchData.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(std::max<std::size_t>(1, data.size()) * sizeof(PatchData)),
                       data.data(), GL_DYNAMIC_DRAW);
        m_autoExposure = autoExposure(std::move(luminances), 0.95, 0.8);
        m_groups = groupMirrors(scene);
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_mirrorGroups.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(std::max<std::size_t>(1, scene.size()) * 4),
                       m_groups.groupOfPatch.data(), GL_DYNAMIC_DRAW);
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_seenGroups.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(std::max<std::size_t>(1, m_groups.representative.size()) * 4),
                       nullptr, GL_DYNAMIC_DRAW);
        m_lastFlags.clear();
        m_lastRowPatch = -2;
    }
    // Selection flags and the inspected row change without a revision.
    std::vector<std::uint32_t> flags(scene.size(), 0);
    for (PatchId i : app.selection()) flags[i] |= 1u;
    if (flags != m_lastFlags) {
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_flags.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(std::max<std::size_t>(1, flags.size()) * 4), flags.data(),
                       GL_DYNAMIC_DRAW);
        m_lastFlags = std::move(flags);
    }
    if (app.layer == Layer::FalseColour) {
        std::vector<std::uint32_t> colours = app.falseColourView().colours;
        if (colours != m_lastFalseColours || m_lastFalseColours.empty()) {
            gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_falseColours.id());
            gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(std::max<std::size_t>(1, colours.size()) * 4), colours.data(),
                           GL_DYNAMIC_DRAW);
            m_lastFalseColours = std::move(colours);
        }
    }
    const int rowPatch = app.selection().empty() ? -1 : int(app.selection().front());
    if (rowPatch != m_lastRowPatch) {
        m_lastRowPatch = rowPatch;
        std::vector<float> row = rowPatch >= 0 ? app.formFactorRow(PatchId(rowPatch)) : std::vector<float>{};
        row.resize(scene.size(), 0.0f);
        m_rowMax = std::max(1e-12, double(*std::max_element(row.begin(), row.end())));
        gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_row.id());
        gl::BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(std::max<std::size_t>(1, row.size()) * 4), row.data(),
                       GL_DYNAMIC_DRAW);
    }
}

void Viewer::drawScene(const Eigen::Matrix4f& viewProjection, const Eigen::Matrix4f& model, const Eigen::Vector4f& clip,
                       bool gouraud, std::uint32_t skipGroup) {
    m_scene.use();
    gl::UniformMatrix4fv(m_scene.uniform("viewProjection"), 1, GL_FALSE, viewProjection.data());
    gl::UniformMatrix4fv(m_scene.uniform("model"), 1, GL_FALSE, model.data());
    gl::Uniform4f(m_scene.uniform("clipPlane"), clip[0], clip[1], clip[2], clip[3]);
    gl::Uniform1i(m_scene.uniform("gouraud"), gouraud ? 1 : 0);
    gl::Uniform1ui(m_scene.uniform("skipGroup"), skipGroup);
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_patchData.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m_mirrorGroups.id());
    gl::BindVertexArray(m_vao.id());
    gl::DrawArrays(GL_TRIANGLES, 0, m_vertexCount);
}

void Viewer::fullScreen(const gl::Program& program) {
    colourWrites(false);
    program.use();
    gl::ActiveTexture(GL_TEXTURE0);
    gl::BindTexture(GL_TEXTURE_2D, m_idCopy.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m_mirrorGroups.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, m_seenGroups.id());
    gl::BindVertexArray(m_emptyVao.id());
    gl::DrawArrays(GL_TRIANGLES, 0, 3);
    colourWrites(true);
}

void Viewer::drawReflections(const AppState& app, const Eigen::Matrix4f& viewProjection, const Eigen::Matrix4d& model,
                             double weight, std::uint32_t depth) {
    // Which mirror planes show in this region (a pixel sees one thing, so the portals of one region
    // are disjoint, and following them one after the other with one stencil value is exact).
    const auto copyLevelIds = [this] {
        gl::CopyImageSubData(m_layers[5].id(), GL_TEXTURE_2D, 0, 0, 0, 0, m_idCopy.id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                             m_width, m_height, 1);
    };
    // Past the depth no portal is followed: no survey (and no read-back) for this region.
    const std::uint32_t maxDepth = std::min<std::uint32_t>(app.settings.formFactors.common.maxDepth, kRetired - 2);
    if (depth > maxDepth) return;
    const std::size_t groups = m_groups.representative.size();
    std::vector<std::uint32_t> seen(groups, 0);
    copyLevelIds();
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_seenGroups.id());
    gl::BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(groups * 4), seen.data());
    gl::StencilMask(0xff);
    gl::StencilFunc(GL_EQUAL, GLint(depth - 1), 0xff);
    gl::StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    gl::DepthFunc(GL_ALWAYS);
    gl::DepthMask(GL_FALSE);
    fullScreen(m_survey);
    gl::DepthMask(GL_TRUE);
    gl::MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl::BindBuffer(GL_SHADER_STORAGE_BUFFER, m_seenGroups.id());
    gl::GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(groups * 4), seen.data());

    const Scene& scene = app.scene();
    const double minWeight = app.settings.formFactors.common.minWeight;
    for (std::size_t g = 0; g < groups; ++g) {
        if (!seen[g]) continue;
        const Patch& mirror = scene.patches[m_groups.representative[g]];
        const double w = weight * mirror.specular;
        // hemirad render's weight cut-off (its --max-depth is checked on entry).
        if (w < minWeight) continue;
        // Mark: in the region, the pixels showing this plane get stencil `depth` and far depth.
        copyLevelIds();
        gl::StencilFunc(GL_EQUAL, GLint(depth - 1), 0xff);
        gl::StencilOp(GL_KEEP, GL_KEEP, GL_INCR);
        gl::DepthFunc(GL_ALWAYS);
        m_mark.use();
        gl::Uniform1ui(m_mark.uniform("group"), GLuint(g));
        fullScreen(m_mark);

        // Show the scene reflected in the mirror's plane (n . x + d = 0 in scene-centred coordinates),
        // only what lies in front of it, weighted by the chain's reflectance.
        const Vec3 centre = mirror.centroid - m_centre;
        const double d = -mirror.normal.dot(centre);
        const Eigen::Matrix4d reflected = model * reflectionMatrix(mirror.normal, d);
        gl::StencilFunc(GL_EQUAL, GLint(depth), 0xff);
        gl::StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
        gl::DepthFunc(GL_LESS);
        gl::DrawBuffers(kLayers, kMirrorLayers);
        gl::Enablei(GL_BLEND, 1);
        gl::BlendFunci(1, GL_CONSTANT_COLOR, GL_ONE);
        gl::BlendColor(float(w), float(w), float(w), 1.0f);
        gl::FrontFace(depth % 2 == 1 ? GL_CW : GL_CCW);
        drawScene(viewProjection, reflected.cast<float>(),
                  Eigen::Vector4f(float(mirror.normal.x()), float(mirror.normal.y()), float(mirror.normal.z()), float(d)),
                  app.gouraud, std::uint32_t(g + 1));
        gl::FrontFace(GL_CCW);
        gl::Disablei(GL_BLEND, 1);
        gl::DrawBuffers(kLayers, kAllLayers);

        drawReflections(app, viewProjection, reflected, w, depth + 1);

        // Retire the portal and everything nested in it: set the top stencil bit where the lower
        // bits are >= depth (this portal's subtree; earlier siblings are retired already), so no
        // later test of a depth matches there.
        gl::StencilMask(kRetired);
        gl::StencilFunc(GL_LEQUAL, GLint(depth) | kRetired, kRetired - 1);
        gl::StencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
        gl::DepthFunc(GL_ALWAYS);
        gl::DepthMask(GL_FALSE);
        fullScreen(m_retire);
        gl::StencilMask(0xff);
        gl::DepthMask(GL_TRUE);
    }
}

void Viewer::render(AppState& app, const OrbitCamera& camera, int width, int height, std::optional<PatchId> hovered) {
    if (width <= 0 || height <= 0) return;
    resize(width, height);
    upload(app);
    m_exposure = app.autoExposure ? m_autoExposure : app.exposure;

    gl::BindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    gl::Viewport(0, 0, width, height);
    gl::Disable(GL_SCISSOR_TEST);
    gl::Disable(GL_BLEND);
    const GLuint zeroId[4] = {0, 0, 0, 0};
    const GLfloat background[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    gl::ClearBufferuiv(GL_COLOR, 0, zeroId);
    for (int k = 1; k < 5; ++k) gl::ClearBufferfv(GL_COLOR, k, background);
    gl::ClearBufferuiv(GL_COLOR, 5, zeroId);
    gl::ClearBufferfi(GL_DEPTH_STENCIL, 0, 1.0f, 0);
    if (m_vertexCount > 0) {
        gl::Enable(GL_DEPTH_TEST);
        gl::DepthFunc(GL_LESS);
        gl::Enable(GL_CLIP_DISTANCE0);
        // The camera works in scene-centred coordinates, like the vertex buffer.
        OrbitCamera centred = camera;
        centred.target -= m_centre;
        const Eigen::Matrix4f viewProjection = (centred.projection(double(width) / height) * centred.view()).cast<float>();
        const Eigen::Matrix4f identity = Eigen::Matrix4f::Identity();
        drawScene(viewProjection, identity, Eigen::Vector4f(0, 0, 0, 1), app.gouraud);

        // Mirrors, to the pipeline's mirror depth: the stencil marks the pixels of each mirror plane
        // seen, their depth is reset, and the scene reflected in that plane adds to the radiance
        // weighted by the chain's reflectance; portals nest as in hemirad render's camera rays.
        if (app.showReflections && !m_groups.representative.empty()) {
            gl::Enable(GL_STENCIL_TEST);
            drawReflections(app, viewProjection, Eigen::Matrix4d::Identity(), 1.0, 1);
            gl::Disable(GL_STENCIL_TEST);
        }
        gl::Disable(GL_CLIP_DISTANCE0);
        gl::Disable(GL_DEPTH_TEST);
    }

    // Present the chosen layer into the window.
    gl::BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::Viewport(0, 0, width, height);
    m_present.use();
    const int layer = int(app.layer);
    gl::Uniform1i(m_present.uniform("layer"), layer);
    gl::Uniform1f(m_present.uniform("exposure"), float(m_exposure));
    gl::Uniform1ui(m_present.uniform("hovered"), hovered ? *hovered + 1u : 0u);
    gl::Uniform1f(m_present.uniform("rowMax"), float(m_rowMax));
    gl::Uniform1i(m_present.uniform("anySelected"), app.selection().empty() ? 0 : 1);
    gl::ActiveTexture(GL_TEXTURE0);
    gl::BindTexture(GL_TEXTURE_2D, m_layers[0].id());
    gl::ActiveTexture(GL_TEXTURE1);
    // Textures: 0 patch ids, 1 radiance, 2 emission, 3 reflectance, 4 specular. The radiance layer
    // shows texture 1; emission, reflectance and specular their own; the others sample none of them.
    const int source = layer >= 2 && layer <= 4 ? layer : 1;
    gl::BindTexture(GL_TEXTURE_2D, m_layers[source].id());
    gl::ActiveTexture(GL_TEXTURE0);
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m_flags.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m_row.id());
    gl::BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, m_falseColours.id());
    gl::BindVertexArray(m_emptyVao.id());
    gl::DrawArrays(GL_TRIANGLES, 0, 3);
    gl::BindVertexArray(0);
    gl::check("drawing the view");
}

std::optional<PatchId> Viewer::pick(int x, int y) const {
    if (!m_fbo.id() || x < 0 || y < 0 || x >= m_width || y >= m_height) return std::nullopt;
    gl::BindFramebuffer(GL_READ_FRAMEBUFFER, m_fbo.id());
    gl::ReadBuffer(GL_COLOR_ATTACHMENT0);
    GLuint id = 0;
    gl::ReadPixels(x, m_height - 1 - y, 1, 1, GL_RED_INTEGER, GL_UNSIGNED_INT, &id);
    gl::BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    if (id == 0) return std::nullopt;
    return PatchId(id - 1);
}

}  // namespace hemirad::ui
