// OBJ/MTL reader written for diagnostics: every error names file:line and the offending value.
// (tinyobjloader was not used: it reads "nan" as 0, drops short faces silently and loses face lines.)
#include "engine/obj_loader.hpp"

#include "engine/error.hpp"
#include "engine/polygon.hpp"
#include "engine/text_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

namespace hemirad {
namespace fs = std::filesystem;

std::string readTextFile(const std::string& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw Error(path, 0, "is a directory, not a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, 0, std::string("cannot open: ") + std::strerror(errno));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw Error(path, 0, "read error");
    return buffer.str();
}

namespace {

/// Rejects binary input early with the line of the first NUL byte.
void rejectBinary(const std::string& path, std::string_view text) {
    const std::size_t nul = text.find('\0');
    if (nul == std::string::npos) return;
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + nul, '\n'));
    throw Error(path, line, "contains a NUL byte: this is not a text OBJ/MTL file");
}

Rgb readColor(const TextReader& r, const char* what) {
    const std::size_t n = r.tokens().size() - 1;
    if (n >= 1 && (r.tokens()[1] == "spectral" || r.tokens()[1] == "xyz"))
        r.fail(std::string(what) + ": only RGB colours are supported, not " + quote(r.tokens()[1]));
    if (n != 1 && n != 3) r.fail(std::string(what) + " needs 1 or 3 values, found " + std::to_string(n));
    Rgb c;
    for (int k = 0; k < 3; ++k) c[k] = r.number(n == 1 ? 1 : 1 + k, what);
    if ((c < 0.0).any()) r.fail(std::string(what) + " " + quote(r.rest(1)) + " has a negative value");
    return c;
}

/// Finishes a material: s = mean(Ks) for mirror illumination models; a mirror without Kd has no
/// diffuse part (rho = 0, not the default 0.5); rho_c + s > 1 creates energy and is an error.
void finishMaterial(Material& m, bool hasKd, const std::string& file, int line) {
    m.specular = (m.illum == 3 || m.illum == 5 || m.illum == 7) ? m.ks.mean() : 0.0;
    if (m.specular > 1.0) {
        std::ostringstream msg;
        msg << "material '" << m.name << "': mirror reflectance mean(Ks) = " << m.specular << " exceeds 1";
        throw Error(file, line, msg.str());
    }
    if (m.specular > 0.0 && !hasKd) m.rho = Rgb::Zero();
    const Rgb total = m.rho + m.specular;
    if ((total > 1.0 + 1e-9).any()) {
        std::ostringstream msg;
        msg << "material '" << m.name << "' reflects more than it receives: ";
        if (m.specular > 0.0) msg << "Kd + mean(Ks) = " << total.maxCoeff() << " (Kd " << m.rho.maxCoeff() << ", s "
                                  << m.specular << ")";
        else msg << "Kd = " << m.rho.maxCoeff();
        msg << " exceeds 1 in a channel (physical materials have rho + s <= 1)";
        throw Error(file, line, msg.str());
    }
}

}  // namespace

void loadMtl(const std::string& path, std::vector<Material>& out, Warnings& warnings) {
    parseMtl(path, readTextFile(path), out, warnings);
}

void parseMtl(const std::string& path, std::string_view text, std::vector<Material>& out, Warnings& warnings) {
    rejectBinary(path, text);
    TextReader r(path, text);
    static const std::set<std::string_view> ignored = {
        "Ka", "Ns", "Ni", "d", "Tr", "Tf", "sharpness", "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor",
        "bump", "disp", "decal", "refl", "norm"};
    Material* current = nullptr;
    int currentLine = 0;
    bool hasKd = false;
    std::set<std::string> seen;
    const std::size_t first = out.size();
    auto finish = [&] {
        if (current) finishMaterial(*current, hasKd, path, currentLine);
    };
    while (r.next()) {
        const auto& t = r.tokens();
        if (t.empty() || t[0][0] == '#') continue;
        const std::string_view key = t[0];
        if (key == "newmtl") {
            finish();
            if (t.size() < 2) r.fail("newmtl without a name");
            Material m;
            m.name = r.rest(1);
            if (!seen.insert(m.name).second)
                warnings.add("duplicate materials", Error::locate(path, r.line()) + "material '" + m.name +
                                                        "' defined again; the later definition is used");
            out.push_back(m);
            current = &out.back();
            currentLine = r.line();
            hasKd = false;
            continue;
        }
        if (ignored.count(key) || key.substr(0, 4) == "map_") continue;
        if (!current) r.fail(quote(key) + " before any newmtl");
        if (key == "Kd") {
            current->rho = readColor(r, "Kd");
            hasKd = true;
        } else if (key == "Ke") {
            current->emission = readColor(r, "Ke");
        } else if (key == "Ks") {
            current->ks = readColor(r, "Ks");
        } else if (key == "illum") {
            const long illum = r.integer(1, "illum");
            if (illum < 0 || illum > 10) r.fail("illum " + quote(t[1]) + " is not an illumination model 0..10");
            current->illum = static_cast<int>(illum);
        } else {
            warnings.add("unknown MTL statements ignored",
                         Error::locate(path, r.line()) + "unknown MTL statement " + quote(key) + " ignored");
        }
    }
    finish();
    if (out.size() == first) warnings.add("empty material libraries", path + ": defines no material");
}

namespace {

struct FaceRecord {
    std::vector<long> vertexIndex;  // as written, resolved later
    std::string material;
    int materialLine = 0;
    std::uint32_t object = 0;
    int line = 0;
};

/// Parses "v", "v/vt", "v//vn" or "v/vt/vn" and checks the texture/normal parts against their counts.
long parseFaceVertex(const TextReader& r, std::string_view token, long texcoords, long normals) {
    long parts[3] = {0, 0, 0};
    int part = 0;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= token.size(); ++i) {
        if (i < token.size() && token[i] != '/') continue;
        if (part > 2) r.fail("face vertex " + quote(token) + " has more than three parts");
        const std::string piece(token.substr(start, i - start));
        if (!piece.empty()) {
            char* end = nullptr;
            errno = 0;
            parts[part] = std::strtol(piece.c_str(), &end, 10);
            if (*end != '\0' || errno == ERANGE) r.fail("face vertex " + quote(token) + " is not an index");
            if (parts[part] == 0) r.fail("face vertex " + quote(token) + ": index 0 is invalid (OBJ counts from 1)");
        } else if (part == 0) {
            r.fail("face vertex " + quote(token) + " has no vertex index");
        }
        ++part;
        start = i + 1;
    }
    const char* names[3] = {"vertex", "texture coordinate", "normal"};
    const long counts[3] = {0, texcoords, normals};
    for (int k = 1; k < 3; ++k) {
        const long idx = parts[k];
        if (idx == 0) continue;
        const long resolved = idx > 0 ? idx : counts[k] + idx + 1;
        if (resolved < 1 || resolved > counts[k])
            r.fail(std::string(names[k]) + " index " + std::to_string(idx) + " in " + quote(token) +
                   " is out of range (" + std::to_string(counts[k]) + " defined so far)");
    }
    return parts[0];
}

void readUnit(const TextReader& r, Scene& scene) {
    const auto& t = r.tokens();
    if (t.size() != 4) r.fail("'# hemirad unit' needs one length unit (m, cm, mm, in or ft)");
    try {
        metresPerUnit(std::string(t[3]));
    } catch (const Error&) {
        r.fail("unknown length unit " + quote(t[3]) + " (m, cm, mm, in or ft)");
    }
    scene.unit = std::string(t[3]);
}

void readUp(const TextReader& r, Scene& scene) {
    const auto& t = r.tokens();
    if (t.size() != 4 || (t[3] != "y" && t[3] != "z" && t[3] != "Y" && t[3] != "Z"))
        r.fail("'# hemirad up' needs the up axis, y or z" + (t.size() == 4 ? ", got " + quote(t[3]) : std::string()));
    scene.up = t[3] == "y" || t[3] == "Y" ? 1 : 2;
}

void readCamera(const TextReader& r, Scene& scene) {
    const auto& t = r.tokens();
    if (t.size() != 10) r.fail("'# hemirad camera' needs ex ey ez tx ty tz fov (7 numbers)");
    Camera c;
    for (int k = 0; k < 3; ++k) {
        c.eye[k] = r.number(3 + k, "camera eye");
        c.target[k] = r.number(6 + k, "camera target");
    }
    c.fovY = r.number(9, "camera field of view");
    try {
        checkCamera(c);
    } catch (const Error& e) {
        r.fail(e.what());
    }
    scene.camera = c;
}

}  // namespace

namespace {

/// Libraries beside the OBJ file.
class FileMaterials final : public MaterialSource {
public:
    explicit FileMaterials(const std::string& objPath) : m_dir(fs::path(objPath).parent_path()) {}
    bool find(const std::string& name, std::string& text, std::string& file) override {
        const fs::path path = m_dir / name;
        std::error_code ec;
        if (!fs::exists(path, ec)) return false;
        file = path.string();
        text = readTextFile(file);  // a directory or an unreadable file is an error naming it
        return true;
    }

private:
    fs::path m_dir;
};

}  // namespace

Material defaultMaterial() {
    Material grey;
    grey.name = kDefaultMaterialName;
    return grey;
}

Scene loadObj(const std::string& path, Warnings& warnings, bool materialsByObject) {
    FileMaterials libraries(path);
    return parseObj(path, readTextFile(path), libraries, warnings, materialsByObject);
}

Scene parseObj(const std::string& path, std::string_view text, MaterialSource& libraries, Warnings& warnings,
               bool materialsByObject) {
    rejectBinary(path, text);
    Scene scene;
    scene.path = path;
    TextReader r(path, text);
    std::vector<FaceRecord> faces;
    std::string material;
    int materialLine = 0;
    long texcoords = 0, normals = 0;
    std::map<std::string, std::uint32_t> objectIds;
    std::uint32_t object = 0;
    scene.objects.push_back("default");
    objectIds["default"] = 0;
    std::map<std::string, std::uint32_t> materialIds;
    std::size_t ignoredElements = 0;
    int firstIgnoredLine = 0;

    while (r.next()) {
        const auto& t = r.tokens();
        if (t.empty()) continue;
        const std::string_view key = t[0];
        if (key[0] == '#') {
            if (t.size() >= 3 && key == "#" && t[1] == "hemirad" && t[2] == "camera") readCamera(r, scene);
            if (t.size() >= 3 && key == "#" && t[1] == "hemirad" && t[2] == "unit") readUnit(r, scene);
            if (t.size() >= 3 && key == "#" && t[1] == "hemirad" && t[2] == "up") readUp(r, scene);
            continue;
        }
        if (key == "v") {
            if (t.size() != 4 && t.size() != 5 && t.size() != 7)
                r.fail("vertex needs x y z (optionally w, or r g b), found " + std::to_string(t.size() - 1) + " values");
            Vec3 v(r.number(1, "vertex x"), r.number(2, "vertex y"), r.number(3, "vertex z"));
            // Areas square the coordinates and rays run in float: keep far from overflow.
            if (v.cwiseAbs().maxCoeff() > 1e15)
                r.fail("vertex " + quote(r.rest(1)) + " is too far out: coordinates must stay within +-1e15");
            for (std::size_t k = 4; k < t.size(); ++k) r.number(k, "vertex value");
            scene.vertices.push_back(v);
        } else if (key == "vt") {
            for (std::size_t k = 1; k < t.size(); ++k) r.number(k, "texture coordinate");
            ++texcoords;
        } else if (key == "vn") {
            for (std::size_t k = 1; k < t.size(); ++k) r.number(k, "normal component");
            ++normals;
        } else if (key == "f") {
            FaceRecord face;
            face.line = r.line();
            face.material = material;
            face.materialLine = materialLine;
            face.object = object;
            for (std::size_t k = 1; k < t.size(); ++k) {
                const long idx = parseFaceVertex(r, t[k], texcoords, normals);
                // Relative (negative) indices are resolved now; positive ones once all vertices are known.
                if (idx < 0) {
                    const long resolved = static_cast<long>(scene.vertices.size()) + idx + 1;
                    if (resolved < 1)
                        r.fail("relative vertex index " + std::to_string(idx) + " reaches before the first vertex (" +
                               std::to_string(scene.vertices.size()) + " defined so far)");
                    face.vertexIndex.push_back(resolved);
                } else {
                    face.vertexIndex.push_back(idx);
                }
            }
            if (face.vertexIndex.size() < 3)
                r.fail("face has " + std::to_string(face.vertexIndex.size()) + " vertices; a patch needs at least 3");
            faces.push_back(std::move(face));
        } else if (key == "o" || key == "g") {
            const std::string name = t.size() > 1 ? r.rest(1) : "default";
            auto [it, added] = objectIds.emplace(name, static_cast<std::uint32_t>(scene.objects.size()));
            if (added) scene.objects.push_back(name);
            object = it->second;
        } else if (key == "usemtl") {
            if (t.size() < 2) r.fail("usemtl without a material name");
            material = r.rest(1);
            materialLine = r.line();
        } else if (key == "mtllib") {
            if (t.size() < 2) r.fail("mtllib without a file name");
            // File names may contain spaces: the whole rest if such a library exists, else each token.
            std::string libraryText, libraryFile;
            std::vector<std::pair<std::string, std::string>> found;  // (file, text)
            if (t.size() > 2 && libraries.find(r.rest(1), libraryText, libraryFile)) {
                found.emplace_back(libraryFile, std::move(libraryText));
            } else {
                for (std::size_t k = 1; k < t.size(); ++k) {
                    const std::string name(t[k]);
                    bool exists = false;
                    try {
                        exists = libraries.find(name, libraryText, libraryFile);
                    } catch (const Error& e) {
                        r.fail("material library " + quote(name) + ": " + e.what());
                    }
                    if (!exists)
                        r.fail("material library " + quote(name) + " not found (looked for " +
                               (fs::path(path).parent_path() / name).string() + ")");
                    found.emplace_back(libraryFile, std::move(libraryText));
                }
            }
            for (const auto& [file, library] : found) {
                const std::size_t before = scene.materials.size();
                parseMtl(file, library, scene.materials, warnings);
                for (std::size_t m = before; m < scene.materials.size(); ++m)
                    materialIds[scene.materials[m].name] = static_cast<std::uint32_t>(m);
            }
        } else if (key == "s") {
            continue;  // smoothing groups: radiosity shading uses the crease angle instead
        } else if (key == "l" || key == "p" || key == "vp" || key == "cstype" || key == "deg" || key == "curv" ||
                   key == "curv2" || key == "surf" || key == "parm" || key == "end" || key == "bmat" ||
                   key == "step" || key == "trim" || key == "hole" || key == "sp" || key == "con" ||
                   key == "mg" || key == "lod" || key == "usemap" || key == "maplib" || key == "shadow_obj" ||
                   key == "trace_obj" || key == "ctech" || key == "stech" || key == "bevel" ||
                   key == "c_interp" || key == "d_interp") {
            if (ignoredElements++ == 0) firstIgnoredLine = r.line();
        } else {
            r.fail("unknown OBJ statement " + quote(key));
        }
    }

    if (ignoredElements > 0)
        warnings.add("non-face OBJ elements ignored",
                     Error::locate(path, firstIgnoredLine) + std::to_string(ignoredElements) +
                         " line/point/curve elements ignored (radiosity needs faces)",
                     ignoredElements);
    if (faces.empty())
        throw Error(path, 0, ignoredElements ? "no faces: only lines, points or curves" : "no faces: nothing to compute");

    std::uint32_t defaultId = UINT32_MAX;
    std::size_t withoutMaterial = 0;
    std::size_t degenerate = 0, nonPlanar = 0, duplicates = 0;
    double worstDeviation = 0.0, worstEdge = 0.0;
    int worstLine = 0, firstDegenerateLine = 0, firstDuplicateLine = 0;
    std::set<std::vector<std::uint32_t>> faceKeys;
    std::vector<std::uint32_t> ids;
    std::vector<Vec3> points;
    const long vertexCount = static_cast<long>(scene.vertices.size());
    for (const FaceRecord& face : faces) {
        ids.clear();
        points.clear();
        for (long idx : face.vertexIndex) {
            if (idx > vertexCount)
                throw Error(path, face.line, "vertex index " + std::to_string(idx) + " is out of range (the file has " +
                                                 std::to_string(vertexCount) + " vertices)");
            ids.push_back(static_cast<std::uint32_t>(idx - 1));
            points.push_back(scene.vertices[ids.back()]);
        }
        const PolygonMeasures m = measurePolygon(points);
        if (m.area == 0.0) {
            if (degenerate++ == 0) firstDegenerateLine = face.line;
            continue;
        }
        if (!m.convex)
            throw Error(path, face.line, "face with " + std::to_string(ids.size()) +
                                             " vertices is not convex; split it into triangles or convex polygons");
        std::vector<std::uint32_t> key = ids;
        std::sort(key.begin(), key.end());
        if (!faceKeys.insert(key).second) {
            if (duplicates++ == 0) firstDuplicateLine = face.line;
        }
        if (m.planarDeviation > 1e-4 * m.maxEdge) {
            ++nonPlanar;
            if (m.planarDeviation > worstDeviation) {
                worstDeviation = m.planarDeviation;
                worstEdge = m.maxEdge;
                worstLine = face.line;
            }
        }
        std::uint32_t materialId;
        if (face.material.empty()) {
            if (defaultId == UINT32_MAX) {
                defaultId = static_cast<std::uint32_t>(scene.materials.size());
                scene.materials.push_back(defaultMaterial());
            }
            materialId = defaultId;
            ++withoutMaterial;
        } else {
            auto it = materialIds.find(face.material);
            if (it == materialIds.end())
                throw Error(path, face.materialLine, "usemtl " + quote(face.material) +
                                                          ": no such material in the file's material libraries");
            materialId = it->second;
        }
        scene.addPatch(ids, materialId, face.object, face.line);
    }
    if (degenerate)
        warnings.add("degenerate patches skipped",
                     Error::locate(path, firstDegenerateLine) + std::to_string(degenerate) +
                         " zero-area face(s) skipped; patch ids count the kept faces only",
                     degenerate);
    if (duplicates)
        warnings.add("duplicate patches",
                     Error::locate(path, firstDuplicateLine) + std::to_string(duplicates) +
                         " face(s) repeat the vertices of an earlier face",
                     duplicates);
    if (nonPlanar) {
        std::ostringstream msg;
        msg << Error::locate(path, worstLine) << nonPlanar << " non-planar patch(es); worst deviation " << worstDeviation
            << " from the plane (longest edge " << worstEdge << ")";
        warnings.add("non-planar patches", msg.str(), nonPlanar);
    }
    if (withoutMaterial && !materialsByObject)
        warnings.add("patches without a material",
                     path + ": " + std::to_string(withoutMaterial) +
                         " face(s) before any usemtl get the default material (Kd 0.5, no emission)",
                     withoutMaterial);
    if (scene.patches.empty()) throw Error(path, 0, "every face is degenerate: no patches");
    return scene;
}

}  // namespace hemirad
