// Per-corner radiosity for Gouraud shading: crease-aware, area-weighted averages at shared positions.
#pragma once

#include "engine/scene.hpp"

#include <vector>

namespace hemirad {

/// Value at each patch corner (indexed like Scene::corners): the area-weighted mean of B over the
/// patches that share the corner's position, whose normals are within creaseDegrees of this patch's
/// normal (so light does not bleed around corners) and whose emission and reflectances equal this
/// patch's (B jumps at a light's or a material's edge: no halo, no smeared light). creaseDegrees in
/// [0, 180], default 45.
std::vector<Rgb> cornerRadiosity(const Scene& scene, const std::vector<Rgb>& B, double creaseDegrees = 45.0);

}  // namespace hemirad
