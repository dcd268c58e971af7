// Inspector pictures.
#include "ui/inspector.hpp"

#include "engine/tone_map.hpp"
#include "preprocess/backend_registry.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "rays/ray_scene.hpp"

#include <cmath>

namespace hemirad::ui {

Inspector::Inspector() = default;
Inspector::~Inspector() = default;

void Inspector::update(AppState& app, PatchId id, double exposure) {
    if (!app.hasScene() || id >= app.scene().size()) return;
    const Scene& scene = app.scene();
    const std::string method = app.settings.formFactors.method;
    if (id == m_patch && method == m_method && app.revision() == m_revision) return;
    m_patch = id;
    m_method = method;
    m_revision = app.revision();
    const std::uint64_t geometry = scene.geometryHash();
    if (!m_rays || geometry != m_geometry) {
        m_rays = std::make_unique<RayScene>(scene);
        m_geometry = geometry;
    }
    const Patch& p = scene.patches[id];
    Vec3 t, b;
    orthonormalBasis(p.normal, t, b);
    const Vec3 origin = p.centroid + m_rays->originOffset() * p.normal;
    const std::vector<Rgb>& B = app.radiosity();
    auto shade = [&](const Vec3& dir) -> std::array<std::uint8_t, 3> {
        const RayScene::Hit hit = m_rays->intersect(origin, dir);
        if (hit.patch == RayScene::kNoHit) return {0, 0, 40};  // nothing: the power is lost
        const Patch& q = scene.patches[hit.patch];
        if (dir.dot(q.normal) >= 0.0) return {90, 0, 0};        // back face: lost as well
        return toSrgb8(B[hit.patch] / kPi, exposure);
    };
    std::vector<std::uint8_t> rgba;
    if (findBackend(method).projection == Projection::HemicubeAtlas) {
        // The atlas as the hemicube back end lays it out (HemicubeLayout), 64 pixels across a face.
        const HemicubeLayout layout(64);
        m_width = int(layout.width());
        m_height = int(layout.height());
        rgba.assign(std::size_t(m_width) * m_height * 4, 255);
        const auto faces = hemicubeFaces(p.normal, t, b);
        for (int f = 0; f < 5; ++f) {
            const auto& v = layout.viewport(f);
            for (int py = 0; py < v.height; ++py)
                for (int px = 0; px < v.width; ++px) {
                    const double x = -1.0 + (px + 0.5) * 2.0 / v.width;
                    const double y = f == 0 ? -1.0 + (py + 0.5) * 2.0 / v.height : (py + 0.5) / v.height;
                    const auto c = shade((faces[f].forward + x * faces[f].right + y * faces[f].up).normalized());
                    // Atlas rows are bottom-up; the picture is top-down.
                    const std::size_t k = (std::size_t(m_height - 1 - (v.y + py)) * m_width + std::size_t(v.x + px)) * 4;
                    rgba[k] = c[0], rgba[k + 1] = c[1], rgba[k + 2] = c[2];
                }
        }
        m_caption = "hemicube atlas of patch " + std::to_string(id) + " (top face | +t, -t | +b, -b sides)";
    } else {
        // The Nusselt disk: a disk point (x, y) is the direction (x, y, sqrt(1 - x^2 - y^2)); equal
        // areas carry equal form factor, as the Beckers cells do.
        m_width = m_height = 192;
        rgba.assign(std::size_t(m_width) * m_height * 4, 255);
        for (int py = 0; py < m_height; ++py)
            for (int px = 0; px < m_width; ++px) {
                const double x = -1.0 + (px + 0.5) * 2.0 / m_width, y = 1.0 - (py + 0.5) * 2.0 / m_height;
                const double r2 = x * x + y * y;
                const std::size_t k = (std::size_t(py) * m_width + px) * 4;
                if (r2 >= 1.0) {
                    rgba[k] = rgba[k + 1] = rgba[k + 2] = 30;
                    continue;
                }
                const auto c = shade((x * t + y * b + std::sqrt(1.0 - r2) * p.normal).normalized());
                rgba[k] = c[0], rgba[k + 1] = c[1], rgba[k + 2] = c[2];
            }
        m_caption = "Nusselt disk of patch " + std::to_string(id) + " (equal areas = equal form factor)";
    }
    m_texture = gl::makeTexture();
    gl::BindTexture(GL_TEXTURE_2D, m_texture.id());
    gl::TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, m_width, m_height);
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl::PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl::TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, m_width, m_height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
}

}  // namespace hemirad::ui
