// The inspector's picture of how a patch's row of F was made (inspector_picture.hpp) as a GL
// texture: remade when the patch, method or scene revision changes, tone-mapped with the view's
// exposure of the frame it is drawn in.
#pragma once

#include "gl/gl_objects.hpp"
#include "ui/app_state.hpp"
#include "ui/inspector_picture.hpp"

#include <memory>

namespace hemirad {
class RayScene;
}

namespace hemirad::ui {

class Inspector {
public:
    Inspector();
    ~Inspector();
    /// Recomputes the picture for patch `id` when the patch, method or scene revision changed, and
    /// tone-maps it again when `exposure` (the view's, this frame) changed.
    void update(AppState& app, PatchId id, double exposure);
    /// GL texture with the picture (0 before the first update), and its size.
    GLuint texture() const { return m_texture.id(); }
    int width() const { return m_picture.width; }
    int height() const { return m_picture.height; }
    const std::string& caption() const { return m_picture.caption; }

private:
    std::unique_ptr<RayScene> m_rays;
    std::uint64_t m_geometry = 0;
    std::uint64_t m_revision = 0;
    PatchId m_patch = ~0u;
    std::string m_method;
    double m_exposure = 0.0;
    InspectorPicture m_picture;
    gl::Texture m_texture;
    int m_textureWidth = 0, m_textureHeight = 0;
};

}  // namespace hemirad::ui
