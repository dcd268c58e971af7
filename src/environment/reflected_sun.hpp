// The sun reflected by planar mirrors: each mirror's sunlit part sends a parallel beam along the
// sun's direction reflected about its plane, weighted by its reflectance s; where that beam lands on
// a patch, past every patch between them, is the reflected footprint (reflected-glare hot spots).
// Exact by shadow polygons, as the direct sun's sunlit fractions are. First reflections only.
#pragma once

#include "engine/math.hpp"
#include "engine/scene.hpp"
#include "environment/sunlit.hpp"

#include <string>
#include <vector>

namespace hemirad {

struct ReflectedSun {
    /// Per patch, W/m^2 averaged over it: the sun reflected onto it by every mirror, s DNI cos x the
    /// share of its area in the beams.
    std::vector<double> irradiance;
    /// Each (mirror, receiver) pair that the beam reaches.
    struct Spot {
        PatchId mirror = 0, receiver = 0;
        double irradiance = 0.0;  ///< W/m^2 averaged over the receiver, from this mirror
        double peak = 0.0;        ///< W/m^2 where the beam lands: s DNI cos(theta)
        double litArea = 0.0;     ///< the footprint's area (scene units^2)
    };
    std::vector<Spot> spots;
    std::size_t mirrorsLit = 0;  ///< mirrors with a sunlit part
};

/// The first reflections of the sun (direction `toSun`, any length > 0; direct-normal irradiance
/// `dni` W/m^2) by the scene's mirror patches (s > 0, the sun on their front). A receiver facing the
/// reflected beam gets the part of it that reaches its front past every other patch between the
/// mirror's plane and its own (front or back), within the mirror's sunlit part. Mirrors' parts
/// behind a receiver's plane send it nothing. Throws hemirad::Error for a direction that is zero or
/// not finite, or a dni that is negative or not finite.
ReflectedSun reflectedSun(const Scene& scene, const Vec3& toSun, double dni);
/// The same with the scene's shadow set-up kept for many suns (a year's hours, a sky's cells):
/// receivers and blockers come from its trees, mirrors run in parallel (OpenMP).
ReflectedSun reflectedSun(const BeamShadows& beams, const Vec3& toSun, double dni);

/// mirror,mirror_object,receiver,receiver_object,irradiance (W/m^2),peak (W/m^2),lit_area (CSV,
/// atomic), the spots by falling irradiance.
void writeGlareCsv(const std::string& path, const Scene& scene, const ReflectedSun& sun);

}  // namespace hemirad
