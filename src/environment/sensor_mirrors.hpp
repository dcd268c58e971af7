// What a sensor point sees through the scene's planar mirrors, by virtual images (as the analytic
// estimator's mirror terms for a patch, mirror_images.hpp, from one point): the patches seen in the
// mirrors, weighted by the reflectances met, and the sky seen in them.
#pragma once

#include "environment/sensors.hpp"
#include "environment/sunlit.hpp"
#include "preprocess/hemisphere/ball_tree.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/reflectors.hpp"
#include "rays/mirror_chain.hpp"
#include "rays/ray_scene.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hemirad {

/// Whether the sensors' factors can follow the scene's mirrors by images: "followed" with the
/// reflectors in `reflectors`, empty without mirrors, else "not followed: " and why (a build without
/// ray casting, a mirror that is not planar and convex) with `reflectors` empty.
std::string sensorMirrorsNote(const Scene& scene, std::vector<Reflector>& reflectors);

/// The sensor x (unit normal n) and each reflector m in front of it: x and n are reflected about m's
/// plane; a patch seen through m's aperture gets Lambert's factor from the image to its part inside
/// the aperture's cone, times the product of the s met, where a shadow ray along the reflected path
/// (leg by leg) is free; patches on a silhouette (a mesh neighbour's ray disagrees), and those whose
/// factor exceeds 1e-3, are split into pieces with a ray each (large ones again, 4 levels deep). The part of m's aperture that no patch fills is sky seen in m. Chains go on
/// to the reflectors seen through an aperture, to `limits` (what a cut-off chain carries counts as
/// sky and is reported).
class SensorMirrors {
public:
    /// `geometry`: the two-sided scene of sensorFactors (patch j, its reversed twin n + j behind it),
    /// with neighbours; `rays` over the scene. All must outlive this.
    SensorMirrors(const Scene& scene, const PatchGeometry& geometry, std::vector<Reflector> reflectors, const RayScene& rays,
                  const MirrorChainLimits& limits);

    struct Node {
        std::int32_t parent;
        std::uint32_t reflector, depth;
        double weight;   ///< the product of the s met, this reflector's included
        double reach;    ///< the factor with which the source sees this reflector (past the chain before it)
        Vec3 image, axis;
    };
    /// Per thread.
    struct Workspace {
        std::vector<Node> nodes;
        std::vector<std::vector<Vec3>> apertures;
        std::vector<std::uint32_t> stack;
        std::vector<double> childReach;       // per reflector
        std::vector<std::uint32_t> children;  // reflectors reached through the node at hand
        std::vector<PatchId> batch;           // two-sided ids
        std::vector<double> factors;
        std::vector<std::uint32_t> legStart;
        std::vector<float> legFrom, legTo;
        std::vector<std::uint8_t> legBlocked, blocked, status;
        std::vector<Vec3> clipped, scratch, pieces;
        std::vector<int> levels;  // per piece in `pieces`: how many splits made it
    };
    Workspace workspace() const;

    /// The reflector a patch belongs to, or -1.
    std::int32_t reflectorOf(PatchId j) const { return m_reflectorOf[j]; }
    std::size_t reflectorCount() const { return m_reflectors.size(); }

    struct Totals {
        double sky = 0.0;     ///< the sky seen in mirrors, weighted by the s met
        double cutoff = 0.0;  ///< what chains past the limits carry (counted in `sky`)
        std::uint64_t terms = 0, rays = 0;
    };
    /// Appends (j, value) to `terms` for every patch front j seen from x through mirrors (a patch
    /// may come more than once). `reach[k]`: the factor with which x sees reflector k's front directly
    /// (its patches' visible factors summed).
    Totals sees(const Vec3& x, const Vec3& n, const std::vector<double>& reach, Workspace& ws,
                std::vector<std::pair<PatchId, double>>& terms) const;

private:
    /// Receiver r's (two-sided id) part seen through node q's aperture, into ws.clipped; false when empty.
    bool clip(std::size_t q, PatchId r, Workspace& ws) const;
    /// Receiver r's part seen through node q, in pieces with a ray each (inPieces' comment).
    double inPieces(std::size_t q, const Vec3& x, const Vec3& n, PatchId r, Workspace& ws, Totals& totals) const;
    /// A receiver's part above this factor, or on a silhouette, is seen in pieces; a piece above it
    /// is split again, to kPieceLevels splits (4^4 quads of a quad at most): as the direct factors
    /// compute the visible part exactly above 1e-3, so that one ray does not decide a large term.
    static constexpr double kPiecesAbove = 1e-3;
    static constexpr int kPieceLevels = 4;
    /// Casts the legs in ws.legFrom / ws.legTo into ws.legBlocked and clears them.
    void castLegs(Workspace& ws, Totals& totals) const;
    bool pathFree(std::size_t q, const Vec3& x, const Vec3& n, const Vec3& target, const Vec3& targetNormal, Workspace& ws,
                  Totals& totals) const;
    void appendPath(std::size_t q, const Vec3& x, const Vec3& n, const Vec3& target, const Vec3& targetNormal, Workspace& ws) const;

    const Scene& m_scene;
    const PatchGeometry& m_geometry;
    std::vector<Reflector> m_reflectors;
    const RayScene& m_rays;
    MirrorChainLimits m_limits;
    BallTree m_patchTree;
    std::vector<std::int32_t> m_reflectorOf;
    double m_flat;
};

/// The sun reflected onto sensor points by the scene's planar mirrors (first reflections, as
/// reflectedSun for patches), set up once for many suns.
class SensorReflections {
public:
    /// Keeps no reference to `scene`; `threads` for the ray scene and the sensors (0: every core).
    explicit SensorReflections(const Scene& scene, int threads = 0);
    ~SensorReflections();
    /// Whether the scene's mirrors are followed (mirrors, a build that casts rays, planar convex mirrors).
    bool active() const { return m_rays != nullptr; }
    /// sensorMirrorsNote's words.
    const std::string& note() const { return m_note; }

    /// Per sensor, W/m^2: for each mirror with the sun (direction `toSun`, direct-normal irradiance
    /// `dni`) on its front, where the line from the sensor against the reflected beam meets the
    /// mirror inside its polygon, the sun reaches that point (past every patch, as sensorSunlit) and
    /// a shadow ray from the sensor to it is free, s dni cos(theta) at the sensor (0 where it faces
    /// away). A point is in a beam or not: exact up to the rays' rounding. Zeros when !active().
    std::vector<double> sun(const BeamShadows& beams, const Sensors& sensors, const Vec3& toSun, double dni) const;

private:
    std::vector<Reflector> m_reflectors;
    std::unique_ptr<RayScene> m_rays;
    std::string m_note;
    int m_threads = 0;
};

}  // namespace hemirad
