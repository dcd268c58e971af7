// CSV, PLY and PNG writers.
#include "engine/result_writer.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"
#include "engine/tone_map.hpp"

#include <cmath>
#include <cstdio>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb/stb_image_write.h>

namespace hemirad {

void requireFinite(const std::vector<Rgb>& values, const char* what) {
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!values[i].allFinite())
            throw Error(std::string(what) + " of patch " + std::to_string(i) + " is not finite; nothing was written");
}

namespace {

/// An optional per-patch column: empty, or one finite value per patch.
void requirePerPatch(const std::vector<double>& values, const Scene& scene, const char* what) {
    if (values.empty()) return;
    if (values.size() != scene.size())
        throw Error(std::string("internal: ") + what + " has " + std::to_string(values.size()) + " values for " +
                    std::to_string(scene.size()) + " patches");
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
            throw Error(std::string(what) + " of patch " + std::to_string(i) + " is not finite; nothing was written");
}

}  // namespace

void writeRadiosityCsv(const std::string& path, const Scene& scene, const std::vector<Rgb>& B,
                       const std::vector<double>& skyViewFactor) {
    requireFinite(B, "radiosity");
    requirePerPatch(skyViewFactor, scene, "sky view factor");
    const bool sky = !skyViewFactor.empty();
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    out << "patch,area,E_r,E_g,E_b,rho_r,rho_g,rho_b,specular,B_r,B_g,B_b" << (sky ? ",sky_view_factor\n" : "\n");
    char line[512];
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        std::snprintf(line, sizeof line, "%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", i, p.area,
                      p.emission[0], p.emission[1], p.emission[2], p.rho[0], p.rho[1], p.rho[2], p.specular, B[i][0],
                      B[i][1], B[i][2]);
        out << line;
        if (sky) {
            std::snprintf(line, sizeof line, ",%.9g", skyViewFactor[i]);
            out << line;
        }
        out << '\n';
    }
    file.commit();
}

void writeRadiosityPly(const std::string& path, const Scene& scene, const std::vector<Rgb>& corner, double exposure,
                       const std::vector<double>& skyViewFactor) {
    requireFinite(corner, "corner radiosity");
    requirePerPatch(skyViewFactor, scene, "sky view factor");
    const bool sky = !skyViewFactor.empty();
    AtomicFile file(path);
    std::ostream& out = file.stream();
    out << "ply\nformat binary_little_endian 1.0\ncomment Hemirad radiosity: colour = sRGB(exposure * B / pi), "
           "B_* in W/m^2\n"
        << "element vertex " << scene.corners.size()
        << "\nproperty float x\nproperty float y\nproperty float z\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\n"
           "property float B_r\nproperty float B_g\nproperty float B_b\n"
        << "element face " << scene.size() << "\nproperty list uchar int vertex_indices\n"
        << (sky ? "property float sky_view_factor\n" : "") << "end_header\n";
    for (std::size_t c = 0; c < scene.corners.size(); ++c) {
        const Vec3& v = scene.vertices[scene.corners[c]];
        const float xyz[3] = {float(v.x()), float(v.y()), float(v.z())};
        const auto rgb = toSrgb8(corner[c] / kPi, exposure);
        const float b[3] = {float(corner[c][0]), float(corner[c][1]), float(corner[c][2])};
        out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
        out.write(reinterpret_cast<const char*>(rgb.data()), 3);
        out.write(reinterpret_cast<const char*>(b), sizeof b);
    }
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        if (p.cornerCount > 255) throw Error(path, 0, "a patch has more than 255 corners; PLY lists cannot hold it");
        const auto count = static_cast<std::uint8_t>(p.cornerCount);
        out.write(reinterpret_cast<const char*>(&count), 1);
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const auto index = static_cast<std::int32_t>(p.firstCorner + k);
            out.write(reinterpret_cast<const char*>(&index), 4);
        }
        if (sky) {  // per face: a patch's value, as the CSV's (corners would blur it across creases)
            const float value = float(skyViewFactor[i]);
            out.write(reinterpret_cast<const char*>(&value), sizeof value);
        }
    }
    file.commit();
}

void writePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
    if (width <= 0 || height <= 0 || rgb.size() != std::size_t(width) * std::size_t(height) * 3)
        throw Error(path, 0, "internal: image buffer does not match its size");
    AtomicFile file(path);
    auto sink = [](void* context, void* data, int size) {
        static_cast<std::ostream*>(context)->write(static_cast<const char*>(data), size);
    };
    if (!stbi_write_png_to_func(sink, &file.stream(), width, height, 3, rgb.data(), width * 3))
        throw Error(path, 0, "PNG encoding failed");
    file.commit();
}

}  // namespace hemirad
