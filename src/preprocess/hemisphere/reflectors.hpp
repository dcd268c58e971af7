// Planar convex mirrors as reflectors: found among the scene's patches, and the reflection and
// aperture geometry the virtual images are built from.
#pragma once

#include "engine/scene.hpp"

#include <string>
#include <vector>

namespace hemirad {

/// A planar convex mirror seen as an aperture: an input polygon all of whose patches are mirrors
/// with one s (a subdivided mirror is one reflector), or else a single mirror patch.
struct Reflector {
    std::vector<Vec3> polygon;  ///< convex, counter-clockwise seen from the front
    Vec3 normal = Vec3::Zero(), centre = Vec3::Zero();
    double offset = 0.0;        ///< normal . y for every y on the plane
    double radius = 0.0;        ///< largest centre-to-corner distance
    double specular = 0.0;
    std::vector<PatchId> patches;  ///< the mirror patches that tile it
};

/// The scene's mirrors as reflectors, in `out`. Returns why the image method cannot serve them (a
/// mirror patch that is not planar or not convex, named by its OBJ line), or an empty string.
std::string findReflectors(const Scene& scene, std::vector<Reflector>& out);

/// The point p mirrored about r's plane.
inline Vec3 reflectPoint(const Reflector& r, const Vec3& p) { return p - 2.0 * (r.normal.dot(p) - r.offset) * r.normal; }
/// The direction d mirrored about r's plane.
inline Vec3 reflectDirection(const Reflector& r, const Vec3& d) { return d - 2.0 * r.normal.dot(d) * r.normal; }

/// Clips `polygon` to the cone from `apex` through the convex `aperture`, in place; `scratch` is
/// scratch.
void clipToCone(const Vec3& apex, const std::vector<Vec3>& aperture, std::vector<Vec3>& polygon,
                std::vector<Vec3>& scratch);

/// Whether some corner of `polygon` lies in front of m's plane (not on it: a coplanar mirror is
/// never reached after this one).
bool partlyInFront(const Reflector& m, const std::vector<Vec3>& polygon);

}  // namespace hemirad
