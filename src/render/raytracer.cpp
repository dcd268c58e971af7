// Camera-ray renderer over the Embree adapter.
#include "render/raytracer.hpp"

#include "engine/error.hpp"
#include "engine/tone_map.hpp"
#include "rays/ray_scene.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

Camera defaultCamera(const Scene& scene) {
    if (scene.camera) return *scene.camera;
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    Camera c;
    c.target = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * (hi - lo).norm(), 1e-9);
    const Vec3 direction = Vec3(0.25, 0.35, -1.0).normalized();
    c.fovY = 40.0;
    c.eye = c.target + direction * (radius / std::sin(0.5 * c.fovY * kPi / 180.0)) * 1.05;
    return c;
}

namespace {

/// Camera rays through the image: direction for a point (px, py) in [0, 1]^2, rows top to bottom.
struct CameraRays {
    Vec3 forward, right, up;
    double tanHalf, aspect;

    explicit CameraRays(const RenderOptions& options) {
        if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384)
            throw Error("image size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                        " is out of range (1..16384)");
        const Camera& cam = options.camera;
        forward = (cam.target - cam.eye).normalized();
        Vec3 u = cam.up.normalized();
        if (std::abs(forward.dot(u)) > 0.999) u = std::abs(forward.z()) < 0.9 ? Vec3(0, 0, 1) : Vec3(1, 0, 0);
        right = forward.cross(u).normalized();
        up = right.cross(forward);
        tanHalf = std::tan(0.5 * cam.fovY * kPi / 180.0);
        aspect = double(options.width) / options.height;
    }
    Vec3 direction(double px, double py) const {
        return (forward + (2.0 * px - 1.0) * tanHalf * aspect * right + (1.0 - 2.0 * py) * tanHalf * up).normalized();
    }
};

Rgb shade(const Scene& scene, const RayScene& rays, const std::vector<Rgb>& B, const std::vector<Rgb>& corner,
          const RenderOptions& options, Vec3 origin, Vec3 dir) {
    Rgb radiance = Rgb::Zero();
    double weight = 1.0;
    for (int depth = 0; depth <= options.maxMirrorDepth && weight > 1e-4; ++depth) {
        const RayScene::Hit hit = rays.intersect(origin, dir);
        if (hit.patch == RayScene::kNoHit) break;
        const Patch& p = scene.patches[hit.patch];
        if (dir.dot(p.normal) >= 0.0) break;  // back face: radiosity leaves the front only
        Rgb value;
        if (options.flat) {
            value = B[hit.patch];
        } else {
            const std::uint32_t c0 = p.firstCorner, c1 = p.firstCorner + hit.fanCorner, c2 = c1 + 1;
            const double u = hit.u, v = hit.v;
            value = (1.0 - u - v) * corner[c0] + u * corner[c1] + v * corner[c2];
        }
        radiance += weight * value / kPi;
        if (p.specular <= 0.0) break;
        weight *= p.specular;
        const Vec3 point = origin + double(hit.t) * dir;
        dir = (dir - 2.0 * dir.dot(p.normal) * p.normal).normalized();
        origin = point + rays.originOffset() * p.normal;
    }
    return radiance;
}

}  // namespace

RadianceImage renderRadiance(const Scene& scene, const RayScene& rays, const std::vector<Rgb>& B,
                             const std::vector<Rgb>& corner, const RenderOptions& options) {
    const CameraRays camera(options);
    if (B.size() != scene.size() || corner.size() != scene.corners.size())
        throw Error("renderRadiance: radiosity arrays do not match the scene");
    const int strata = std::max(1, static_cast<int>(std::sqrt(double(std::max(1, options.samplesPerPixel)))));

    RadianceImage image;
    image.width = options.width;
    image.height = options.height;
    image.pixels.assign(std::size_t(options.width) * options.height, Rgb::Zero());
#pragma omp parallel for schedule(dynamic, 1)
    for (int y = 0; y < options.height; ++y)
        for (int x = 0; x < options.width; ++x) {
            Rgb sum = Rgb::Zero();
            for (int sy = 0; sy < strata; ++sy)
                for (int sx = 0; sx < strata; ++sx) {
                    const double px = (x + (sx + 0.5) / strata) / options.width;
                    const double py = (y + (sy + 0.5) / strata) / options.height;
                    sum += shade(scene, rays, B, corner, options, options.camera.eye, camera.direction(px, py));
                }
            image.pixels[std::size_t(y) * options.width + x] = sum / double(strata * strata);
        }
    return image;
}

std::vector<PatchId> renderPatchIds(const Scene& scene, const RayScene& rays, const RenderOptions& options) {
    const CameraRays camera(options);
    std::vector<PatchId> ids(std::size_t(options.width) * options.height, RayScene::kNoHit);
#pragma omp parallel for schedule(dynamic, 1)
    for (int y = 0; y < options.height; ++y)
        for (int x = 0; x < options.width; ++x) {
            const Vec3 dir = camera.direction((x + 0.5) / options.width, (y + 0.5) / options.height);
            const RayScene::Hit hit = rays.intersect(options.camera.eye, dir);
            PatchId& id = ids[std::size_t(y) * options.width + x];
            if (hit.patch != RayScene::kNoHit) id = dir.dot(scene.patches[hit.patch].normal) < 0.0 ? hit.patch : kBackFace;
        }
    return ids;
}

std::vector<std::uint8_t> toneMap(const RadianceImage& image, double exposure, double& scale) {
    if (exposure > 0.0) {
        scale = exposure;
    } else {
        std::vector<double> lum(image.pixels.size());
        for (std::size_t k = 0; k < lum.size(); ++k) lum[k] = luminance(image.pixels[k]);
        scale = autoExposure(std::move(lum), 0.97, 0.85);
    }
    std::vector<std::uint8_t> rgb(image.pixels.size() * 3);
    for (std::size_t k = 0; k < image.pixels.size(); ++k) {
        const auto px = toSrgb8(image.pixels[k], scale);
        std::copy(px.begin(), px.end(), rgb.begin() + 3 * k);
    }
    return rgb;
}

}  // namespace hemirad
