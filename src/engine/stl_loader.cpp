// STL reader: binary (80-byte header, uint32 count, 50 bytes per triangle, little-endian) and ASCII
// (solid / facet normal / outer loop / vertex x3 / endloop / endfacet / endsolid), told apart by size.
#include "engine/stl_loader.hpp"

#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "engine/polygon.hpp"
#include "engine/text_reader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>
#include <sstream>
#include <unordered_map>

namespace hemirad {
namespace {

constexpr std::size_t kHeaderBytes = 84;    // 80 bytes of header text + the uint32 triangle count
constexpr std::size_t kTriangleBytes = 50;  // normal, 3 vertices (12 float32), uint16 attribute
constexpr double kMaxCoordinate = 1e15;     // as the OBJ reader: areas square coordinates, rays run in float
constexpr std::size_t kListed = 5;          // triangles named in a warning

const char* const kVertexNames[3] = {"first", "second", "third"};
const char kAxes[3] = {'x', 'y', 'z'};

struct Triangle {
    Vec3 normal = Vec3::Zero();
    std::array<Vec3, 3> vertices;
    std::uint32_t object = 0;
    int line = 0;  // ASCII: the line of its `facet`; binary: 0
};

/// Exact vertex merging: one vertex per distinct (x, y, z) bit pattern, -0 counted as +0, so that
/// triangles sharing an edge share its vertex ids (watertightness and mesh neighbours see them).
class VertexMerger {
public:
    explicit VertexMerger(std::vector<Vec3>& vertices) : m_vertices(vertices) {}
    std::uint32_t id(Vec3 v) {
        Key key;
        for (int k = 0; k < 3; ++k) {
            if (v[k] == 0.0) v[k] = 0.0;  // -0.0 == 0.0: store and key both as +0
            std::memcpy(&key[k], &v[k], sizeof(double));
        }
        const auto [it, added] = m_ids.emplace(key, static_cast<std::uint32_t>(m_vertices.size()));
        if (added) m_vertices.push_back(v);
        return it->second;
    }

private:
    using Key = std::array<std::uint64_t, 3>;
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = 0xcbf29ce484222325ULL;
            for (std::uint64_t word : k) h = (h ^ word) * 0x100000001b3ULL ^ (word >> 29);
            return static_cast<std::size_t>(h);
        }
    };
    std::vector<Vec3>& m_vertices;
    std::unordered_map<Key, std::uint32_t, KeyHash> m_ids;
};

/// "triangle 3" plus the ASCII line where there is one.
std::string where(std::size_t index, int line) {
    return "triangle " + std::to_string(index) + (line > 0 ? " (line " + std::to_string(line) + ")" : "");
}

/// The first kListed triangles of `indices`, and how many more.
std::string listed(const std::vector<std::pair<std::size_t, int>>& indices, std::size_t total) {
    std::string text;
    for (std::size_t k = 0; k < indices.size(); ++k) text += (k ? ", " : "") + where(indices[k].first, indices[k].second);
    if (total > indices.size()) text += " and " + std::to_string(total - indices.size()) + " more";
    return text;
}

/// Triangles to patches: zero-area ones skipped and counted (as the OBJ reader skips zero-area
/// faces), duplicates and facet normals against the vertex order counted.
Scene assemble(const std::string& path, std::vector<std::string> objects, const std::vector<Triangle>& triangles,
               Warnings& warnings) {
    if (triangles.empty()) throw Error(path, 0, "no triangles: nothing to compute");
    Scene scene;
    scene.path = path;
    scene.objects = std::move(objects);
    scene.materials.push_back(defaultMaterial());
    VertexMerger merger(scene.vertices);
    std::set<std::array<std::uint32_t, 3>> seen;
    std::size_t degenerate = 0, duplicates = 0, againstOrder = 0;
    std::size_t firstDegenerate = 0, firstDuplicate = 0;
    std::vector<std::pair<std::size_t, int>> againstList;
    std::vector<std::uint32_t> ids(3);
    std::vector<Vec3> points(3);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Triangle& triangle = triangles[t];
        for (int k = 0; k < 3; ++k) points[k] = triangle.vertices[k];
        const PolygonMeasures m = measurePolygon(points);
        if (m.area == 0.0) {
            if (degenerate++ == 0) firstDegenerate = t;
            continue;
        }
        for (int k = 0; k < 3; ++k) ids[k] = merger.id(points[k]);
        std::array<std::uint32_t, 3> key = {ids[0], ids[1], ids[2]};
        std::sort(key.begin(), key.end());
        if (!seen.insert(key).second && duplicates++ == 0) firstDuplicate = t;
        // A zero normal is "let the reader compute it": accepted without a word.
        if (triangle.normal.dot(m.normal) < 0.0 && againstOrder++ < kListed) againstList.emplace_back(t, triangle.line);
        scene.addPatch(ids, 0, triangle.object, triangle.line);
    }
    if (degenerate)
        warnings.add("degenerate patches skipped",
                     Error::locate(path, triangles[firstDegenerate].line) + where(firstDegenerate, 0) + ": " +
                         std::to_string(degenerate) +
                         " zero-area triangle(s) skipped; patch ids count the kept triangles only",
                     degenerate);
    if (duplicates)
        warnings.add("duplicate patches",
                     Error::locate(path, triangles[firstDuplicate].line) + where(firstDuplicate, 0) + ": " +
                         std::to_string(duplicates) + " triangle(s) repeat the vertices of an earlier triangle",
                     duplicates);
    if (againstOrder)
        warnings.add("facet normals against the vertex order",
                     path + ": " + std::to_string(againstOrder) +
                         " facet normal(s) point against their vertex order (" + listed(againstList, againstOrder) +
                         "); the vertex order (right-hand rule) decides the emitting side",
                     againstOrder);
    if (scene.patches.empty()) throw Error(path, 0, "every triangle has zero area: no patches");
    return scene;
}

// --- Binary ----------------------------------------------------------------------------------------

std::uint32_t readUint32(const char* p) {
    const auto* b = reinterpret_cast<const unsigned char*>(p);
    return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
}

float readFloat(const char* p) {
    const std::uint32_t bits = readUint32(p);
    float value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
}

std::string formatValue(double v) {
    std::ostringstream text;
    text << v;
    return text.str();
}

Scene parseBinary(const std::string& path, std::string_view bytes, const std::string& stem, Warnings& warnings) {
    if (bytes.size() < kHeaderBytes)
        throw Error(path, 0, "truncated: " + std::to_string(bytes.size()) + " bytes, shorter than a binary STL's " +
                                 std::to_string(kHeaderBytes) + "-byte header (and not an ASCII STL, which starts with 'solid')");
    const std::uint64_t count = readUint32(bytes.data() + 80);
    const std::uint64_t expected = kHeaderBytes + kTriangleBytes * count;
    if (bytes.size() != expected) {
        const std::string announced = "the header announces " + std::to_string(count) + " triangles (" +
                                      std::to_string(expected) + " bytes), the file has " + std::to_string(bytes.size());
        if (bytes.size() < expected)
            throw Error(path, 0, "truncated in triangle " + std::to_string((bytes.size() - kHeaderBytes) / kTriangleBytes) +
                                     ": " + announced);
        throw Error(path, 0, "triangle count does not match the file size: " + announced + " (" +
                                 std::to_string((bytes.size() - kHeaderBytes) / kTriangleBytes) + " triangles and " +
                                 std::to_string((bytes.size() - kHeaderBytes) % kTriangleBytes) + " bytes)");
    }
    std::vector<Triangle> triangles(count);
    std::size_t attributed = 0, firstAttributed = 0;
    for (std::size_t t = 0; t < count; ++t) {
        const char* p = bytes.data() + kHeaderBytes + kTriangleBytes * t;
        Triangle& triangle = triangles[t];
        for (int c = 0; c < 3; ++c) triangle.normal[c] = readFloat(p + 4 * c);
        if (!triangle.normal.allFinite())
            throw Error(path, 0, where(t, 0) + ": facet normal (" + formatValue(triangle.normal.x()) + ", " +
                                     formatValue(triangle.normal.y()) + ", " + formatValue(triangle.normal.z()) +
                                     ") is not finite");
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) {
                const double v = readFloat(p + 12 + 12 * k + 4 * c);
                const std::string name = std::string(kVertexNames[k]) + " vertex " + kAxes[c] + " = " + formatValue(v);
                if (!std::isfinite(v)) throw Error(path, 0, where(t, 0) + ": " + name + " is not a finite number");
                if (std::abs(v) > kMaxCoordinate)
                    throw Error(path, 0, where(t, 0) + ": " + name + " is too far out: coordinates must stay within +-1e15");
                triangle.vertices[k][c] = v;
            }
        if ((p[48] || p[49]) && attributed++ == 0) firstAttributed = t;
    }
    if (attributed)
        warnings.add("STL attribute bytes ignored",
                     path + ": " + where(firstAttributed, 0) + ": " + std::to_string(attributed) +
                         " triangle(s) carry attribute bytes (a colour extension?); Hemirad ignores them",
                     attributed);
    return assemble(path, {stem}, triangles, warnings);
}

// --- ASCII -----------------------------------------------------------------------------------------

bool keyword(std::string_view token, std::string_view word) {
    if (token.size() != word.size()) return false;
    for (std::size_t i = 0; i < token.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(token[i])) != word[i]) return false;
    return true;
}

/// The tokens after the keyword must number exactly `n`.
void expectValues(const TextReader& r, std::size_t n, const std::string& what) {
    const std::size_t found = r.tokens().size() - 1;
    if (found != n)
        r.fail(what + " needs " + (n ? std::to_string(n) + " values" : std::string("nothing after it")) + ", found " +
               quote(r.rest(1)));
}

Scene parseAscii(const std::string& path, std::string_view text, const std::string& stem, Warnings& warnings) {
    enum class State { Outside, Solid, Facet, Loop, LoopClosed };
    TextReader r(path, text);
    State state = State::Outside;
    std::vector<std::string> objects;
    std::vector<std::size_t> unnamed;  // objects named after the file once their number is known
    std::unordered_map<std::string, std::uint32_t> objectIds;
    std::vector<Triangle> triangles;
    Triangle current;
    int vertices = 0, solidLine = 0;
    std::string solidName;
    while (r.next()) {
        const auto& t = r.tokens();
        if (t.empty()) continue;
        const std::string_view key = t[0];
        switch (state) {
        case State::Outside:
            if (!keyword(key, "solid"))
                r.fail((triangles.empty() && objects.empty() ? "not an STL file: expected 'solid', found "
                                                             : "expected 'solid' or the end of the file, found ") +
                       quote(key));
            solidLine = r.line();
            solidName = r.rest(1);
            if (solidName.empty()) {
                unnamed.push_back(objects.size());
                current.object = static_cast<std::uint32_t>(objects.size());
                objects.emplace_back();
            } else {
                const auto [it, added] = objectIds.emplace(solidName, static_cast<std::uint32_t>(objects.size()));
                if (added) objects.push_back(solidName);
                current.object = it->second;
            }
            state = State::Solid;
            break;
        case State::Solid:
            if (keyword(key, "endsolid")) {
                state = State::Outside;
            } else if (keyword(key, "facet")) {
                if (t.size() < 2 || !keyword(t[1], "normal")) r.fail("'facet' must be followed by 'normal nx ny nz'");
                if (t.size() != 5) r.fail("facet normal needs 3 values, found " + quote(r.rest(2)));
                for (int c = 0; c < 3; ++c) current.normal[c] = r.number(2 + c, "facet normal component");
                current.line = r.line();
                state = State::Facet;
            } else {
                r.fail(std::string("expected 'facet' or 'endsolid' in solid ") + quote(solidName) + " (line " +
                       std::to_string(solidLine) + "), found " + quote(key));
            }
            break;
        case State::Facet:
            if (!(keyword(key, "outer") && t.size() == 2 && keyword(t[1], "loop")))
                r.fail("expected 'outer loop' after the facet of line " + std::to_string(current.line) + ", found " +
                       quote(r.rest(0)));
            vertices = 0;
            state = State::Loop;
            break;
        case State::Loop:
            if (keyword(key, "vertex")) {
                if (vertices == 3) r.fail("a 4th vertex in the loop of the facet of line " + std::to_string(current.line) +
                                          ": an STL facet is a triangle (3 vertices)");
                expectValues(r, 3, "vertex");
                Vec3& v = current.vertices[vertices++];
                for (int c = 0; c < 3; ++c) {
                    const std::string what = std::string("vertex ") + kAxes[c];
                    v[c] = r.number(1 + c, what.c_str());
                }
                if (v.cwiseAbs().maxCoeff() > kMaxCoordinate)
                    r.fail("vertex " + quote(r.rest(1)) + " is too far out: coordinates must stay within +-1e15");
            } else if (keyword(key, "endloop")) {
                expectValues(r, 0, "endloop");
                if (vertices != 3)
                    r.fail("the loop of the facet of line " + std::to_string(current.line) + " has " +
                           std::to_string(vertices) + " vertices; an STL facet needs exactly 3");
                state = State::LoopClosed;
            } else {
                r.fail("expected 'vertex' or 'endloop', found " + quote(key));
            }
            break;
        case State::LoopClosed:
            if (!keyword(key, "endfacet"))
                r.fail("the facet of line " + std::to_string(current.line) + " is not closed: expected 'endfacet', found " +
                       quote(key));
            expectValues(r, 0, "endfacet");
            triangles.push_back(current);
            state = State::Solid;
            break;
        }
    }
    if (state == State::Facet || state == State::Loop || state == State::LoopClosed)
        throw Error(path, r.line(), "the file ends inside the facet of line " + std::to_string(current.line) +
                                        " (no 'endfacet'): truncated?");
    if (state == State::Solid)
        throw Error(path, r.line(), "the file ends inside solid " + quote(solidName) + " of line " +
                                        std::to_string(solidLine) + " (no 'endsolid'): truncated?");
    for (std::size_t k = 0; k < unnamed.size(); ++k)
        objects[unnamed[k]] = unnamed.size() == 1 ? stem : stem + "_" + std::to_string(k + 1);
    return assemble(path, std::move(objects), triangles, warnings);
}

/// ASCII STL starts with "solid" (after optional blanks) and is text; binary headers may start with
/// "solid" too, which is why the size test comes first.
bool looksAscii(std::string_view bytes) {
    const std::size_t start = bytes.find_first_not_of(" \t\r\n");
    if (start == std::string_view::npos || bytes.size() - start < 5) return false;
    return keyword(bytes.substr(start, 5), "solid") && bytes.find('\0') == std::string_view::npos;
}

}  // namespace

Scene loadStl(const std::string& path, Warnings& warnings) { return parseStl(path, readTextFile(path), warnings); }

Scene parseStl(const std::string& path, std::string_view bytes, Warnings& warnings) {
    if (bytes.empty()) throw Error(path, 0, "empty file: no triangles");
    const std::string stem = std::filesystem::path(path).stem().string();
    if (bytes.size() >= kHeaderBytes &&
        kHeaderBytes + kTriangleBytes * std::uint64_t(readUint32(bytes.data() + 80)) == bytes.size())
        return parseBinary(path, bytes, stem, warnings);
    if (looksAscii(bytes)) return parseAscii(path, bytes, stem, warnings);
    return parseBinary(path, bytes, stem, warnings);
}

}  // namespace hemirad
