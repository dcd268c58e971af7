// Test support: STL files (binary and ASCII) and OBJ text written from triangles, so that the
// readers can be checked on round trips and on damaged copies.
#pragma once

#include "engine/scene.hpp"

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace hemirad::test {

struct StlTriangle {
    Vec3 normal = Vec3::Zero();
    std::array<Vec3, 3> vertices;
    std::uint16_t attribute = 0;
};

/// The patches of `scene` as fan triangles, each with its patch's normal (all patches, or those of
/// `object`).
inline std::vector<StlTriangle> stlTriangles(const Scene& scene, std::optional<std::uint32_t> object = {}) {
    std::vector<StlTriangle> out;
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        if (object && p.object != *object) continue;
        for (std::uint32_t k = 1; k + 1 < p.cornerCount; ++k)
            out.push_back({p.normal, {scene.corner(p, 0), scene.corner(p, k), scene.corner(p, k + 1)}, 0});
    }
    return out;
}

/// The closed box [lo, hi] as 6 inward-facing quads (one object), like unitCube().
inline Scene boxScene(const Vec3& lo, const Vec3& hi) {
    Scene s;
    s.objects.push_back("box");
    Material m;
    m.name = "box";
    s.materials.push_back(m);
    for (int axis = 0; axis < 3; ++axis) {
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            auto point = [&](double u, double v) {
                Vec3 p;
                p[axis] = side ? hi[axis] : lo[axis];
                p[a] = u;
                p[b] = v;
                return p;
            };
            std::vector<Vec3> pts = {point(lo[a], lo[b]), point(hi[a], lo[b]), point(hi[a], hi[b]), point(lo[a], hi[b])};
            if (side) std::swap(pts[1], pts[3]);  // the far side faces back into the box
            std::vector<std::uint32_t> ids;
            for (const Vec3& p : pts) {
                ids.push_back(static_cast<std::uint32_t>(s.vertices.size()));
                s.vertices.push_back(p);
            }
            s.addPatch(ids, 0, 0);
        }
    }
    return s;
}

/// A binary STL: 80-byte header, the count (`count` overrides the true one), 50 bytes per triangle.
inline std::string binaryStl(const std::vector<StlTriangle>& triangles, const std::string& header = "hemirad test",
                             std::optional<std::uint32_t> count = {}) {
    std::string out(80, ' ');
    out.replace(0, std::min<std::size_t>(header.size(), 80), header.substr(0, 80));
    auto put32 = [&out](std::uint32_t v) {
        for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xff));
    };
    auto putFloat = [&put32](double v) {
        const float f = static_cast<float>(v);
        std::uint32_t bits;
        std::memcpy(&bits, &f, 4);
        put32(bits);
    };
    put32(count ? *count : static_cast<std::uint32_t>(triangles.size()));
    for (const StlTriangle& t : triangles) {
        for (int c = 0; c < 3; ++c) putFloat(t.normal[c]);
        for (const Vec3& v : t.vertices)
            for (int c = 0; c < 3; ++c) putFloat(v[c]);
        out.push_back(static_cast<char>(t.attribute & 0xff));
        out.push_back(static_cast<char>(t.attribute >> 8));
    }
    return out;
}

/// Shortest-enough text for a double that reads back to the same bits.
inline std::string exactNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

struct StlSolid {
    std::string name;  ///< "" writes an unnamed `solid`
    std::vector<StlTriangle> triangles;
};

/// An ASCII STL of one or more solids, numbers written exactly.
inline std::string asciiStl(const std::vector<StlSolid>& solids) {
    std::string out;
    auto vec = [](const Vec3& v) { return exactNumber(v.x()) + " " + exactNumber(v.y()) + " " + exactNumber(v.z()); };
    for (const StlSolid& solid : solids) {
        out += "solid" + (solid.name.empty() ? std::string() : " " + solid.name) + "\n";
        for (const StlTriangle& t : solid.triangles) {
            out += "  facet normal " + vec(t.normal) + "\n    outer loop\n";
            for (const Vec3& v : t.vertices) out += "      vertex " + vec(v) + "\n";
            out += "    endloop\n  endfacet\n";
        }
        out += "endsolid" + (solid.name.empty() ? std::string() : " " + solid.name) + "\n";
    }
    return out;
}

/// An OBJ of the same triangles: vertices in first-seen order (bitwise-equal ones shared), one
/// `o NAME` and `usemtl NAME` per solid, `mtllib` naming `library` when it is given.
inline std::string objText(const std::vector<StlSolid>& solids, const std::string& library = "") {
    std::string head = library.empty() ? "" : "mtllib " + library + "\n", body;
    std::vector<Vec3> seen;
    auto id = [&](const Vec3& v) {
        for (std::size_t k = 0; k < seen.size(); ++k)
            if (seen[k] == v) return k + 1;
        seen.push_back(v);
        head += "v " + exactNumber(v.x()) + " " + exactNumber(v.y()) + " " + exactNumber(v.z()) + "\n";
        return seen.size();
    };
    for (const StlSolid& solid : solids) {
        body += "o " + solid.name + "\n";
        if (!library.empty()) body += "usemtl " + solid.name + "\n";
        for (const StlTriangle& t : solid.triangles) {
            std::string face = "f";
            for (const Vec3& v : t.vertices) face += " " + std::to_string(id(v));
            body += face + "\n";
        }
    }
    return head + body;
}

}  // namespace hemirad::test
