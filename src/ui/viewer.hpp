// The 3D view: the scene drawn into a layered offscreen target (patch id, radiance, emission,
// reflectances), mirrors showing their reflections through the stencil (mirrors in mirrors to the
// pipeline's --max-depth, as hemirad render), one layer presented.
#pragma once

#include "gl/gl_objects.hpp"
#include "ui/app_state.hpp"
#include "ui/orbit_camera.hpp"

#include <cstdint>
#include <optional>
#include <vector>

namespace hemirad::ui {

/// Needs a current GL 4.5 context (the window's) for its whole life.
class Viewer {
public:
    Viewer();
    ~Viewer();

    /// Draws the view into the window's framebuffer region (0, 0, width, height).
    void render(AppState& app, const OrbitCamera& camera, int width, int height, std::optional<PatchId> hovered);
    /// The patch under window pixel (x, y) (y from the top) of the last render.
    std::optional<PatchId> pick(int x, int y) const;
    /// The exposure the last frame used (automatic or the app's).
    double exposure() const { return m_exposure; }

private:
    void upload(AppState& app);
    void resize(int width, int height);
    void drawScene(const Eigen::Matrix4f& viewProjection, const Eigen::Matrix4f& model, const Eigen::Vector4f& clip,
                   bool gouraud, std::uint32_t skipGroup = 0);
    /// The mirrors seen in the region of stencil value `depth - 1` (drawn with `model`, path weight
    /// `weight`): each gets stencil `depth`, shows the scene reflected in its plane weighted by
    /// weight x s, is followed in turn, then is retired (stencil 255).
    void drawReflections(const AppState& app, const Eigen::Matrix4f& viewProjection, const Eigen::Matrix4d& model,
                         double weight, std::uint32_t depth);
    /// Fills a full-screen pass with `program` (colour writes off).
    void fullScreen(const gl::Program& program);

    gl::Program m_scene, m_mark, m_survey, m_retire, m_present;
    gl::VertexArray m_vao, m_emptyVao;
    gl::Buffer m_vertices, m_patchData, m_flags, m_row, m_mirrorGroups, m_seenGroups, m_falseColours;
    gl::Framebuffer m_fbo;
    gl::Texture m_layers[6];
    gl::Texture m_idCopy;
    gl::Renderbuffer m_depth;
    int m_width = 0, m_height = 0;
    std::uint64_t m_revision = 0;
    GLsizei m_vertexCount = 0;
    Vec3 m_centre = Vec3::Zero();
    double m_autoExposure = 1.0, m_exposure = 1.0;
    std::vector<std::uint32_t> m_lastFlags;
    int m_lastRowPatch = -2;
    double m_rowMax = 1.0;
    std::vector<std::uint32_t> m_lastFalseColours;
    MirrorGroups m_groups;
};

}  // namespace hemirad::ui
