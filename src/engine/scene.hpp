// The scene model: vertices, patches (one per OBJ face) with their materials, and subdivision parents.
#pragma once

#include "engine/math.hpp"

#include <optional>
#include <string>
#include <vector>

namespace hemirad {

/// An MTL material as read: diffuse reflectance (Kd), emission (Ke), mirror reflectance s.
struct Material {
    std::string name;
    Rgb rho = Rgb::Constant(0.5);
    Rgb emission = Rgb::Zero();
    double specular = 0.0;
    /// MTL fields kept for a faithful rewrite: Ks as read and illum.
    Rgb ks = Rgb::Zero();
    int illum = 1;
};

/// How an input polygon was split by subdivide(): not at all, a regular grid of quads or of triangles.
enum class GridKind : std::uint8_t { Single, Quad, Triangle };

/// An input polygon whose patches are contiguous: [firstPatch, firstPatch + patchCount).
/// Quad grid: patch (i, j) = firstPatch + j * nu + i, i along corner0->corner1, j along corner0->corner3.
/// Triangle grid of n = nu rows: see triangleCell(). An unsubdivided patch is its own Single parent.
/// Polygons of more than four corners are split into fan triangles first, each its own parent.
struct Parent {
    std::uint32_t firstCorner = 0;  ///< into Scene::parentCorners
    std::uint32_t cornerCount = 0;
    GridKind kind = GridKind::Single;
    std::uint32_t nu = 1, nv = 1;
    PatchId firstPatch = 0;
    std::uint32_t patchCount = 1;
    PatchId sourcePatch = 0;        ///< the input patch this parent polygon is (part of)
};

struct Patch {
    std::uint32_t firstCorner = 0;  ///< into Scene::corners (vertex indices), counter-clockwise
    std::uint32_t cornerCount = 0;
    std::uint32_t material = 0;     ///< into Scene::materials (name and MTL fields for saving)
    std::uint32_t object = 0;       ///< into Scene::objects (OBJ o/g name)
    Rgb emission = Rgb::Zero();     ///< E, W/m^2 radiant exitance, per channel
    Rgb rho = Rgb::Zero();          ///< diffuse reflectance, 0..1 per channel
    double specular = 0.0;          ///< mirror reflectance s, 0..1, wavelength independent
    double area = 0.0;
    Vec3 normal = Vec3::Zero();
    Vec3 centroid = Vec3::Zero();
    std::uint32_t parent = 0;       ///< into Scene::parents
    std::uint32_t cellI = 0, cellJ = 0;  ///< cell in the parent's grid
    int sourceLine = 0;             ///< OBJ line of the face this patch comes from (0 = generated)
};

/// A viewpoint: eye, target, up, vertical field of view in degrees.
struct Camera {
    Vec3 eye = Vec3(0, 0, 1), target = Vec3::Zero(), up = Vec3(0, 1, 0);
    double fovY = 40.0;
};

/// Throws hemirad::Error (a message "camera ..." naming the value) unless `camera` can make an image:
/// eye and target finite points whose difference is finite and non-zero, up a finite non-zero
/// direction, fovY in (0, 180) degrees. The one check behind the CLI's --camera, the OBJ's
/// "# hemirad camera" line and Python's render() (a NaN eye there failed an Embree assertion).
void checkCamera(const Camera& camera);

class Scene {
public:
    std::string path;                       ///< file it was loaded from, for messages
    std::vector<Vec3> vertices;
    std::vector<std::uint32_t> corners;     ///< patch corner vertex indices
    std::vector<Patch> patches;
    std::vector<Material> materials;
    std::vector<std::string> objects;
    std::vector<std::uint32_t> parentCorners;
    std::vector<Parent> parents;
    std::optional<Camera> camera;           ///< "# hemirad camera ex ey ez tx ty tz fov" in the OBJ
    std::string unit;                       ///< length unit, "# hemirad unit mm" in the OBJ ("": not stated)
    int up = 0;                             ///< up axis, "# hemirad up z" in the OBJ: 1 y, 2 z (0: not stated)

    std::size_t size() const { return patches.size(); }
    Vec3 corner(const Patch& p, std::uint32_t k) const { return vertices[corners[p.firstCorner + k]]; }
    std::vector<Vec3> polygon(PatchId id) const;

    /// Appends a patch on existing vertices, measuring it; returns its id. Its parent is itself.
    PatchId addPatch(const std::vector<std::uint32_t>& vertexIds, std::uint32_t material,
                     std::uint32_t object, int sourceLine = 0);
    /// Recomputes every patch's area, normal and centroid after vertices moved.
    void updateMeasures();
    /// Copies a material's E, rho, s into a patch.
    void applyMaterial(PatchId id, std::uint32_t material);

    bool hasMirrors() const;
    /// Axis-aligned bounds of the vertices used by patches.
    void bounds(Vec3& lo, Vec3& hi) const;
    /// Length of the bounds' diagonal (scene scale for offsets and cameras).
    double extent() const;
    double totalArea() const;
    /// Hash of what F depends on: patch geometry (corner positions) and specular reflectance.
    std::uint64_t geometryHash() const;
    /// Hash of the whole loaded scene: vertices, patches with their materials (E, rho, s), objects
    /// and grid cells, the materials and objects as read, the subdivision parents, camera and unit
    /// (not the path). The ranks of an MPI job must agree on it.
    std::uint64_t contentHash() const;
};

/// The length units a scene may state: "m", "cm", "mm", "in", "ft".
const std::vector<std::string>& lengthUnits();
/// Metres per `unit` (one of lengthUnits()); 0 for "" (not stated). Throws hemirad::Error otherwise.
double metresPerUnit(const std::string& unit);

/// Mirror patches grouped by plane and reflectance, so a whole (subdivided) mirror is handled as one
/// planar reflector: groupOfPatch[i] = group + 1 (0 for non-mirrors), representative[g] = a patch of
/// group g (its plane and s stand for the group).
struct MirrorGroups {
    std::vector<std::uint32_t> groupOfPatch;
    std::vector<PatchId> representative;
};
/// Coplanar within 1e-6 of the scene extent, normals within 1e-9, equal s.
MirrorGroups groupMirrors(const Scene& scene);

/// Index of cell (i, j) in a triangle grid of n rows: row j has 2 (n - j) - 1 cells, i = 0 .. 2 (n - j) - 2.
inline std::uint32_t triangleCell(std::uint32_t n, std::uint32_t i, std::uint32_t j) {
    return j * (2 * n - j) + i;
}

}  // namespace hemirad
