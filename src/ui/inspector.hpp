// The inspector's picture of how a patch's row of F was made: what the patch sees over its Nusselt
// disk (hemisphere method) or on its unfolded hemicube atlas (hemicube method), ray-cast with Embree
// from the patch centroid and coloured by the radiance of what each direction hits.
#pragma once

#include "gl/gl_objects.hpp"
#include "ui/app_state.hpp"

#include <memory>

namespace hemirad {
class RayScene;
}

namespace hemirad::ui {

class Inspector {
public:
    Inspector();
    ~Inspector();
    /// Recomputes the picture for patch `id` when the patch, method or scene revision changed.
    void update(AppState& app, PatchId id, double exposure);
    /// GL texture with the picture (0 before the first update), and its size.
    GLuint texture() const { return m_texture.id(); }
    int width() const { return m_width; }
    int height() const { return m_height; }
    const std::string& caption() const { return m_caption; }

private:
    std::unique_ptr<RayScene> m_rays;
    std::uint64_t m_geometry = 0;
    std::uint64_t m_revision = 0;
    PatchId m_patch = ~0u;
    std::string m_method;
    gl::Texture m_texture;
    int m_width = 0, m_height = 0;
    std::string m_caption;
};

}  // namespace hemirad::ui
