// Orbit camera for the viewer: orbit, pan and zoom like MeshLab/Blender; framing and scene cameras.
#pragma once

#include "engine/scene.hpp"

#include <Eigen/Core>

namespace hemirad::ui {

class OrbitCamera {
public:
    Vec3 target = Vec3::Zero();
    double distance = 1.0;
    double yaw = 0.0;    ///< radians about the up axis
    double pitch = 0.0;  ///< radians, clamped short of the poles
    double fovY = 40.0;  ///< degrees
    Vec3 up = Vec3(0, 1, 0);

    /// Fits the scene's bounds in view from the front-right, slightly above.
    void frame(const Scene& scene);
    /// Takes the scene's own camera (the Cornell camera for the bundled box); frames otherwise.
    void useSceneCamera(const Scene& scene);
    void set(const Camera& camera);

    /// Mouse drags in pixels of a viewport `height` pixels tall.
    void orbit(double dx, double dy);
    void pan(double dx, double dy, int height);
    /// Positive steps move closer.
    void zoom(double steps);

    Vec3 eye() const;
    Eigen::Matrix4d view() const;
    /// OpenGL projection (depth -1..1), near/far from the scene size.
    Eigen::Matrix4d projection(double aspect) const;
    double sceneRadius = 1.0;
};

}  // namespace hemirad::ui
