// Inspector pictures: made when the patch, method or scene revision changes, tone-mapped again
// whenever the view's exposure changes.
#include "ui/inspector.hpp"

#include "rays/ray_scene.hpp"

namespace hemirad::ui {

Inspector::Inspector() = default;
Inspector::~Inspector() = default;

void Inspector::update(AppState& app, PatchId id, double exposure) {
    if (!app.hasScene() || id >= app.scene().size()) return;
    const Scene& scene = app.scene();
    const std::string method = app.settings.formFactors.method;
    const bool stale = id != m_patch || method != m_method || app.revision() != m_revision;
    if (!stale && exposure == m_exposure && m_texture.id()) return;
    if (stale) {
        m_patch = id;
        m_method = method;
        m_revision = app.revision();
        const std::uint64_t geometry = scene.geometryHash();
        if (!m_rays || geometry != m_geometry) {
            m_rays = std::make_unique<RayScene>(scene);
            m_geometry = geometry;
        }
        m_picture = makeInspectorPicture(scene, *m_rays, app.radiosity(), id, findBackend(method).projection);
    }
    // The view's exposure of this frame (it changes after a solve, an edit or an undo).
    m_exposure = exposure;
    const std::vector<std::uint8_t> rgba = m_picture.rgba(exposure);
    if (!m_texture.id() || m_textureWidth != m_picture.width || m_textureHeight != m_picture.height) {
        m_texture = gl::makeTexture();
        gl::BindTexture(GL_TEXTURE_2D, m_texture.id());
        gl::TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, m_picture.width, m_picture.height);
        gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        m_textureWidth = m_picture.width;
        m_textureHeight = m_picture.height;
    }
    gl::BindTexture(GL_TEXTURE_2D, m_texture.id());
    gl::PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl::TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, m_picture.width, m_picture.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
}

}  // namespace hemirad::ui
