// Inspector pictures: ray-cast radiance over the Nusselt disk or the hemicube atlas.
#include "ui/inspector_picture.hpp"

#include "engine/tone_map.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "rays/ray_scene.hpp"

#include <cmath>

namespace hemirad::ui {

std::vector<std::uint8_t> InspectorPicture::rgba(double exposure) const {
    std::vector<std::uint8_t> out(std::size_t(width) * height * 4, 255);
    for (std::size_t k = 0; k < kind.size(); ++k) {
        std::array<std::uint8_t, 3> c{255, 255, 255};  // Unused: white
        switch (kind[k]) {
            case Pixel::Unused: break;
            case Pixel::Outside: c = {30, 30, 30}; break;
            case Pixel::Miss: c = {0, 0, 40}; break;       // nothing: the power is lost
            case Pixel::BackFace: c = {90, 0, 0}; break;   // a back face: lost as well
            case Pixel::Hit: c = toSrgb8(radiance[k], exposure); break;
        }
        out[4 * k] = c[0], out[4 * k + 1] = c[1], out[4 * k + 2] = c[2];
    }
    return out;
}

InspectorPicture makeInspectorPicture(const Scene& scene, const RayScene& rays, const std::vector<Rgb>& B, PatchId id,
                                      Projection projection) {
    const Patch& p = scene.patches[id];
    Vec3 t, b;
    orthonormalBasis(p.normal, t, b);
    const Vec3 origin = p.centroid + rays.originOffset() * p.normal;
    InspectorPicture picture;
    auto look = [&](std::size_t k, const Vec3& dir) {
        const RayScene::Hit hit = rays.intersect(origin, dir);
        if (hit.patch == RayScene::kNoHit) {
            picture.kind[k] = InspectorPicture::Pixel::Miss;
        } else if (dir.dot(scene.patches[hit.patch].normal) >= 0.0) {
            picture.kind[k] = InspectorPicture::Pixel::BackFace;
        } else {
            picture.kind[k] = InspectorPicture::Pixel::Hit;
            picture.radiance[k] = B[hit.patch] / kPi;
        }
    };
    const auto allocate = [&](int w, int h, InspectorPicture::Pixel fill) {
        picture.width = w;
        picture.height = h;
        picture.kind.assign(std::size_t(w) * h, fill);
        picture.radiance.assign(std::size_t(w) * h, Rgb::Zero());
    };
    if (projection == Projection::HemicubeAtlas) {
        // The atlas as the hemicube back end lays it out (HemicubeLayout), 64 pixels across a face.
        const HemicubeLayout layout(64);
        allocate(int(layout.width()), int(layout.height()), InspectorPicture::Pixel::Unused);
        const auto faces = hemicubeFaces(p.normal, t, b);
        for (int f = 0; f < 5; ++f) {
            const auto& v = layout.viewport(f);
            for (int py = 0; py < v.height; ++py)
                for (int px = 0; px < v.width; ++px) {
                    const double x = -1.0 + (px + 0.5) * 2.0 / v.width;
                    const double y = f == 0 ? -1.0 + (py + 0.5) * 2.0 / v.height : (py + 0.5) / v.height;
                    // Atlas rows are bottom-up; the picture is top-down.
                    const std::size_t k = std::size_t(picture.height - 1 - (v.y + py)) * picture.width + std::size_t(v.x + px);
                    look(k, (faces[f].forward + x * faces[f].right + y * faces[f].up).normalized());
                }
        }
        picture.caption = "hemicube atlas of patch " + std::to_string(id) + " (top face | +t, -t | +b, -b sides)";
    } else {
        // The Nusselt disk: a disk point (x, y) is the direction (x, y, sqrt(1 - x^2 - y^2)); equal
        // areas carry equal form factor, as the Beckers cells do.
        allocate(192, 192, InspectorPicture::Pixel::Outside);
        for (int py = 0; py < picture.height; ++py)
            for (int px = 0; px < picture.width; ++px) {
                const double x = -1.0 + (px + 0.5) * 2.0 / picture.width, y = 1.0 - (py + 0.5) * 2.0 / picture.height;
                const double r2 = x * x + y * y;
                if (r2 < 1.0) look(std::size_t(py) * picture.width + px, (x * t + y * b + std::sqrt(1.0 - r2) * p.normal).normalized());
            }
        picture.caption = "Nusselt disk of patch " + std::to_string(id) + " (equal areas = equal form factor)";
    }
    return picture;
}

}  // namespace hemirad::ui
