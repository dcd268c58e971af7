// Crease-aware corner averaging of patch radiosity.
#include "engine/vertex_radiosity.hpp"

#include "engine/error.hpp"

#include <array>
#include <cmath>
#include <map>

namespace hemirad {
namespace {

/// Emission and reflectances equal: B is continuous across the edge. Where they differ B jumps (a
/// light in a ceiling, a red patch on a white wall), and averaging would smear it: a crease.
bool sameMaterial(const Patch& a, const Patch& b) {
    return (a.emission == b.emission).all() && (a.rho == b.rho).all() && a.specular == b.specular;
}

}  // namespace

std::vector<Rgb> cornerRadiosity(const Scene& scene, const std::vector<Rgb>& B, double creaseDegrees) {
    if (B.size() != scene.size()) throw Error("cornerRadiosity: B has the wrong size");
    if (!(creaseDegrees >= 0.0 && creaseDegrees <= 180.0))
        throw Error("crease angle must be in [0, 180] degrees, got " + std::to_string(creaseDegrees));
    const double cosCrease = std::cos(creaseDegrees * kPi / 180.0) - 1e-12;

    // Weld by exact position: duplicated vertices (OBJ exporters, subdivision) share values too.
    std::map<std::array<double, 3>, std::uint32_t> positionIds;
    std::vector<std::uint32_t> positionOfVertex(scene.vertices.size());
    for (std::size_t v = 0; v < scene.vertices.size(); ++v) {
        const Vec3& p = scene.vertices[v];
        positionOfVertex[v] = positionIds.emplace(std::array<double, 3>{p.x(), p.y(), p.z()},
                                                  static_cast<std::uint32_t>(positionIds.size()))
                                  .first->second;
    }
    // Corners grouped by position: CSR of (patch, corner slot).
    std::vector<std::uint32_t> start(positionIds.size() + 1, 0);
    for (std::size_t c = 0; c < scene.corners.size(); ++c) ++start[positionOfVertex[scene.corners[c]] + 1];
    for (std::size_t g = 0; g < positionIds.size(); ++g) start[g + 1] += start[g];
    std::vector<std::uint32_t> members(scene.corners.size());
    std::vector<PatchId> patchOfCorner(scene.corners.size());
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (PatchId p = 0; p < scene.size(); ++p) {
            const Patch& patch = scene.patches[p];
            for (std::uint32_t k = 0; k < patch.cornerCount; ++k) {
                const std::uint32_t c = patch.firstCorner + k;
                patchOfCorner[c] = p;
                members[fill[positionOfVertex[scene.corners[c]]]++] = c;
            }
        }
    }
    std::vector<Rgb> out(scene.corners.size(), Rgb::Zero());
    for (std::size_t g = 0; g + 1 < start.size(); ++g)
        for (std::uint32_t a = start[g]; a < start[g + 1]; ++a) {
            const Patch& self = scene.patches[patchOfCorner[members[a]]];
            Rgb sum = Rgb::Zero();
            double weight = 0.0;
            PatchId previous = UINT32_MAX;
            for (std::uint32_t b = start[g]; b < start[g + 1]; ++b) {
                const PatchId q = patchOfCorner[members[b]];
                if (q == previous) continue;  // a patch listing the same position twice counts once
                previous = q;
                const Patch& other = scene.patches[q];
                if (self.normal.dot(other.normal) < cosCrease || !sameMaterial(self, other)) continue;
                sum += other.area * B[q];
                weight += other.area;
            }
            out[members[a]] = weight > 0 ? Rgb(sum / weight) : B[patchOfCorner[members[a]]];
        }
    return out;
}

}  // namespace hemirad
