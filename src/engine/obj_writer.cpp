// OBJ/MTL writer.
#include "engine/obj_writer.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"

#include <charconv>
#include <filesystem>
#include <map>
#include <tuple>

namespace hemirad {
namespace {

/// `v` in the shortest form that reads back (strtod) as the same double: 0.9, 552.8, 0.8999999761581421;
/// never the 17-digit noise of a fixed precision, and never fewer digits than the value needs (the
/// scene hash, and so an F file's match, depends on the exact values).
struct Shortest {
    double v;
};

std::ostream& operator<<(std::ostream& out, Shortest x) {
    char text[32];
    const auto [end, failed] = std::to_chars(text, text + sizeof text, x.v);
    if (failed != std::errc()) throw Error("cannot write the number " + std::to_string(x.v));
    return out.write(text, end - text);
}

void writeRgb(std::ostream& out, const char* key, const Rgb& c) {
    out << key << ' ' << Shortest{c[0]} << ' ' << Shortest{c[1]} << ' ' << Shortest{c[2]} << '\n';
}

void writeMaterial(std::ostream& out, const Material& m) {
    out << "newmtl " << m.name << '\n';
    writeRgb(out, "Kd", m.rho);
    writeRgb(out, "Ke", m.emission);
    if (m.specular > 0.0) {
        writeRgb(out, "Ks", Rgb::Constant(m.specular));
        out << "illum 3\n\n";
    } else {
        writeRgb(out, "Ks", m.ks);
        out << "illum " << (m.illum == 3 || m.illum == 5 || m.illum == 7 ? 2 : m.illum) << "\n\n";
    }
}

bool sameValues(const Patch& p, const Material& m) {
    return (p.rho == m.rho).all() && (p.emission == m.emission).all() && p.specular == m.specular;
}

}  // namespace

void saveObj(const Scene& scene, const std::string& path) {
    namespace fs = std::filesystem;
    if (isStandardOutput(path))
        throw Error(path, 0, "an OBJ is written with its MTL file beside it: give a file name, not standard output");
    const fs::path objPath(path);
    const fs::path mtlPath = fs::path(objPath).replace_extension(".mtl");

    // Materials actually written: originals, plus one derived material per distinct edited value set.
    std::vector<Material> written = scene.materials;
    std::vector<std::uint32_t> patchMaterial(scene.size());
    using Key = std::tuple<std::uint32_t, double, double, double, double, double, double, double>;
    std::map<Key, std::uint32_t> derived;
    std::map<std::uint32_t, int> derivedCount;
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        if (p.material < scene.materials.size() && sameValues(p, scene.materials[p.material])) {
            patchMaterial[i] = p.material;
            continue;
        }
        const Key key{p.material, p.rho[0], p.rho[1], p.rho[2], p.emission[0], p.emission[1], p.emission[2], p.specular};
        auto [it, added] = derived.emplace(key, static_cast<std::uint32_t>(written.size()));
        if (added) {
            Material m = p.material < scene.materials.size() ? scene.materials[p.material] : Material{};
            m.name = (p.material < scene.materials.size() ? m.name : std::string("material")) + "~" +
                     std::to_string(++derivedCount[p.material]);
            m.rho = p.rho;
            m.emission = p.emission;
            m.specular = p.specular;
            m.ks = Rgb::Constant(p.specular);
            // The illumination model stays the original's (writeMaterial: illum 3 for a mirror).
            written.push_back(m);
        }
        patchMaterial[i] = it->second;
    }

    {
        AtomicFile mtl(mtlPath.string(), false);
        mtl.stream() << "# Hemirad materials: Kd = diffuse reflectance, Ke = emission (W/m^2), "
                        "illum 3 + Ks = mirror reflectance\n\n";
        for (const Material& m : written) writeMaterial(mtl.stream(), m);
        mtl.commit();
    }
    AtomicFile obj(path, false);
    std::ostream& out = obj.stream();
    out << "# Hemirad scene, " << scene.size() << " patches\n";
    if (!scene.unit.empty()) out << "# hemirad unit " << scene.unit << '\n';
    if (scene.up != 0) out << "# hemirad up " << (scene.up == 2 ? 'z' : 'y') << '\n';
    if (scene.camera) {
        const Camera& c = *scene.camera;
        out << "# hemirad camera " << Shortest{c.eye.x()} << ' ' << Shortest{c.eye.y()} << ' ' << Shortest{c.eye.z()} << ' '
            << Shortest{c.target.x()} << ' ' << Shortest{c.target.y()} << ' ' << Shortest{c.target.z()} << ' '
            << Shortest{c.fovY} << '\n';
    }
    out << "mtllib " << mtlPath.filename().string() << '\n';
    for (const Vec3& v : scene.vertices)
        out << "v " << Shortest{v.x()} << ' ' << Shortest{v.y()} << ' ' << Shortest{v.z()} << '\n';
    std::uint32_t object = UINT32_MAX, material = UINT32_MAX;
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        if (p.object != object && p.object < scene.objects.size()) {
            object = p.object;
            out << "o " << scene.objects[object] << '\n';
        }
        if (patchMaterial[i] != material) {
            material = patchMaterial[i];
            out << "usemtl " << written[material].name << '\n';
        }
        out << 'f';
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) out << ' ' << scene.corners[p.firstCorner + k] + 1;
        out << '\n';
    }
    obj.commit();
}

}  // namespace hemirad
