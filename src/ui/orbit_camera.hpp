// Orbit camera for the viewer: orbit, pan and zoom like MeshLab/Blender; framing and scene cameras.
#pragma once

#include "engine/scene.hpp"

#include <Eigen/Core>

#include <vector>

namespace hemirad::ui {

class OrbitCamera {
public:
    Vec3 target = Vec3::Zero();
    double distance = 1.0;
    double yaw = 0.0;    ///< radians about the up axis
    double pitch = 0.0;  ///< radians, clamped short of the poles
    double fovY = 40.0;  ///< degrees
    int upAxis = 1;      ///< 1 y, 2 z: yaw turns about it, pitch rises towards it (frame() sets it)

    /// Takes the scene's up axis (upAxisOf) and fits the scene's bounds in view, seen from the scene
    /// camera's side when the scene has one, else from its open side (the vertical bounding-box face
    /// that patches cover least, as the open front of a Cornell box), else (a closed scene) from the
    /// front-right, slightly above.
    void frame(const Scene& scene);
    /// Fits the selected patches in view, keeping the direction of view.
    void frameSelection(const Scene& scene, const std::vector<PatchId>& patches);
    /// Looks at the scene's centre from outside along `axis` (0 x, 1 y, 2 z) on its `positive` side,
    /// fitting the whole scene: the standard views (top is along the scene's up axis).
    void lookAlong(const Scene& scene, int axis, bool positive);
    /// Takes the scene's own camera (the Cornell camera for the bundled box); frames otherwise.
    void useSceneCamera(const Scene& scene);
    void set(const Camera& camera);
    /// Points the view along the scene direction `fromTargetToEye` (need not be unit).
    void setDirection(const Vec3& fromTargetToEye);

    /// Mouse drags in pixels of a viewport `height` pixels tall.
    void orbit(double dx, double dy);
    void pan(double dx, double dy, int height);
    /// Positive steps move closer.
    void zoom(double steps);

    Vec3 eye() const;
    /// The unit vector of upAxis.
    Vec3 upVector() const;
    Eigen::Matrix4d view() const;
    /// OpenGL projection (depth -1..1), near/far from the scene size.
    Eigen::Matrix4d projection(double aspect) const;
    double sceneRadius = 1.0;

private:
    /// Centres the view on the box [lo, hi] at a distance that fits it; keeps the direction.
    void fit(const Vec3& lo, const Vec3& hi);
    /// Scene directions to the camera's frame, where y is up, and back (a rotation about x for z-up).
    Vec3 toLocal(const Vec3& d) const;
    Vec3 toScene(const Vec3& d) const;
};

}  // namespace hemirad::ui
