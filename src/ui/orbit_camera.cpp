// Orbit camera.
#include "ui/orbit_camera.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad::ui {

void OrbitCamera::frame(const Scene& scene) {
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    target = 0.5 * (lo + hi);
    sceneRadius = std::max(0.5 * (hi - lo).norm(), 1e-9);
    fovY = 40.0;
    yaw = -0.35;
    pitch = 0.3;
    distance = sceneRadius / std::sin(0.5 * fovY * kPi / 180.0) * 1.1;
}

void OrbitCamera::set(const Camera& camera) {
    target = camera.target;
    const Vec3 d = camera.eye - camera.target;
    distance = std::max(d.norm(), 1e-9);
    pitch = std::asin(std::clamp(d.y() / distance, -1.0, 1.0));
    yaw = std::atan2(d.x(), d.z());
    fovY = camera.fovY;
}

void OrbitCamera::useSceneCamera(const Scene& scene) {
    frame(scene);
    if (scene.camera) set(*scene.camera);
}

void OrbitCamera::orbit(double dx, double dy) {
    yaw -= dx * 0.005;
    pitch = std::clamp(pitch + dy * 0.005, -1.55, 1.55);
}

void OrbitCamera::pan(double dx, double dy, int height) {
    const Eigen::Matrix4d v = view();
    const Vec3 right = v.block<1, 3>(0, 0).transpose();
    const Vec3 camUp = v.block<1, 3>(1, 0).transpose();
    const double perPixel = 2.0 * distance * std::tan(0.5 * fovY * kPi / 180.0) / std::max(height, 1);
    target += (-dx * right + dy * camUp) * perPixel;
}

void OrbitCamera::zoom(double steps) { distance = std::max(distance * std::pow(0.9, steps), 1e-6 * sceneRadius); }

Vec3 OrbitCamera::eye() const {
    return target + distance * Vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
}

Eigen::Matrix4d OrbitCamera::view() const {
    const Vec3 e = eye();
    const Vec3 f = (target - e).normalized();
    Vec3 u = up;
    if (std::abs(f.dot(u)) > 0.999) u = Vec3(0, 0, 1);
    const Vec3 r = f.cross(u).normalized();
    const Vec3 t = r.cross(f);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = r.transpose();
    m.block<1, 3>(1, 0) = t.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -r.dot(e);
    m(1, 3) = -t.dot(e);
    m(2, 3) = f.dot(e);
    return m;
}

Eigen::Matrix4d OrbitCamera::projection(double aspect) const {
    const double n = std::max(1e-4 * sceneRadius, 1e-3 * distance), f = distance + 4.0 * sceneRadius;
    const double t = 1.0 / std::tan(0.5 * fovY * kPi / 180.0);
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    p(0, 0) = t / aspect;
    p(1, 1) = t;
    p(2, 2) = -(f + n) / (f - n);
    p(2, 3) = -2.0 * f * n / (f - n);
    p(3, 2) = -1.0;
    return p;
}

}  // namespace hemirad::ui
