// The Embree adapter (the only file that includes rtcore): patches as triangles, hits as patch ids.
#pragma once

#include "engine/scene.hpp"

#include <memory>
#include <string>

namespace hemirad {

/// Empty when this build casts rays (Embree); else why not and how to get it ("not built: configure
/// with -DHEMIRAD_WITH_EMBREE=ON ..."). Front ends check it before loading a scene; a RayScene made
/// anyway throws hemirad::Error with this text.
const std::string& rayCastingNotBuilt();

/// Ray-casting view of a Scene. Triangles are the patches' fans (0, k, k+1); coordinates are
/// shifted by the scene's centre before conversion to float so that large offsets keep precision.
/// Thread-safe for concurrent queries after construction.
class RayScene {
public:
    struct Hit {
        PatchId patch;     ///< kNoHit when the ray escaped
        float t;           ///< distance along the (unit) direction
        float u, v;        ///< barycentrics on the fan triangle (corner 0, fanCorner, fanCorner + 1)
        std::uint32_t fanCorner;  ///< k of the fan triangle (0, k, k+1) that was hit
    };
    static constexpr PatchId kNoHit = 0xffffffffu;

    /// Builds the BVH. `threads` = 0 lets Embree use every core. Throws hemirad::Error on Embree errors
    /// and in a build without Embree.
    explicit RayScene(const Scene& scene, int threads = 0);
    ~RayScene();
    RayScene(const RayScene&) = delete;
    RayScene& operator=(const RayScene&) = delete;

    /// Closest hit of the ray origin + t dir, t in (0, tfar]; origin in scene coordinates.
    Hit intersect(const Vec3& origin, const Vec3& dir, float tfar = 3.0e38f) const;

    /// Casts `count` rays from one origin (local float coordinates from toLocal()) along unit
    /// directions dirs[3 k .. 3 k + 2]; writes the patch hit (or kNoHit) to patches[k] and, if
    /// `distances` is given, the hit distance (for mirror bounces). Hits nearer than `tnear` are
    /// passed over (a surface through the origin). The hemisphere back end's fast path.
    void intersectFan(const float origin[3], const float* dirs, std::size_t count, PatchId* patches,
                      float* distances = nullptr, float tnear = 0.0f) const;

    /// Shadow rays: blocked[k] = 1 when something lies on the segment from `origin` to target k
    /// (both in local float coordinates, both already lifted off their surfaces), else 0.
    void occludedSegments(const float origin[3], const float* targets, std::size_t count, std::uint8_t* blocked) const;
    /// The same for segments with origins of their own (origin k at origins[3 k]). Both go through one
    /// packet routine, so a segment gets the same answer from either.
    void occludedSegmentPairs(const float* origins, const float* targets, std::size_t count, std::uint8_t* blocked) const;

    /// Scene coordinates -> the float frame used by the BVH (centre subtracted).
    void toLocal(const Vec3& p, float out[3]) const;
    /// Offset that lifts ray origins off a surface, relative to the scene scale and float precision.
    double originOffset() const { return m_offset; }
    std::size_t triangleCount() const { return m_triangles; }

    struct Impl;  ///< Embree handles (opaque; public only for the C error callback)

private:
    std::unique_ptr<Impl> m_impl;
    Vec3 m_centre = Vec3::Zero();
    double m_offset = 0.0;
    std::size_t m_triangles = 0;
};

}  // namespace hemirad
