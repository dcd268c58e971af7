// Orbit camera.
#include "ui/orbit_camera.hpp"

#include "ui/up_axis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hemirad::ui {

namespace {

/// The outward direction of the vertical bounding-box face (+-x, and +-z for y up or +-y for z up)
/// that patches lying on it cover least, when it is covered less than half as much as the best
/// covered one (an open side); else zero.
Vec3 openSide(const Scene& scene, const Vec3& lo, const Vec3& hi, int up) {
    const Vec3 size = hi - lo;
    Vec3 best = Vec3::Zero();
    double least = 2.0, most = 0.0;
    for (int axis : {0, 3 - up}) {
        const int other = 3 - up - axis;  // the other horizontal axis
        const double faceArea = size[other] * size[up];
        if (!(faceArea > 0.0)) continue;
        for (int side = 0; side < 2; ++side) {
            // Patches facing across the face within 2 % of the box from it (walls of modelled rooms,
            // as the Cornell box's, are seldom exactly axis-aligned).
            const double plane = side ? hi[axis] : lo[axis], slab = 0.02 * size[axis];
            double covered = 0.0;
            for (const Patch& p : scene.patches)
                if (std::abs(p.normal[axis]) > 0.95 && std::abs(p.centroid[axis] - plane) <= slab) covered += p.area;
            const double fraction = covered / faceArea;
            most = std::max(most, fraction);
            if (fraction < least) {
                least = fraction;
                best = Vec3::Zero();
                best[axis] = side ? 1.0 : -1.0;
            }
        }
    }
    return least < 0.5 * most ? best : Vec3::Zero();
}

}  // namespace

void OrbitCamera::fit(const Vec3& lo, const Vec3& hi) {
    target = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * (hi - lo).norm(), 1e-9);
    distance = radius / std::sin(0.5 * fovY * kPi / 180.0) * 1.1;
}

Vec3 OrbitCamera::toLocal(const Vec3& d) const { return upAxis == 2 ? Vec3(d.x(), d.z(), -d.y()) : d; }

Vec3 OrbitCamera::toScene(const Vec3& d) const { return upAxis == 2 ? Vec3(d.x(), -d.z(), d.y()) : d; }

Vec3 OrbitCamera::upVector() const { return upAxis == 2 ? Vec3(0, 0, 1) : Vec3(0, 1, 0); }

void OrbitCamera::setDirection(const Vec3& direction) {
    const Vec3 d = toLocal(direction);
    const double length = std::max(d.norm(), 1e-300);
    pitch = std::clamp(std::asin(std::clamp(d.y() / length, -1.0, 1.0)), -1.55, 1.55);
    yaw = std::atan2(d.x(), d.z());
}

void OrbitCamera::frame(const Scene& scene) {
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    sceneRadius = std::max(0.5 * (hi - lo).norm(), 1e-9);
    upAxis = upAxisOf(scene);
    fovY = 40.0;
    yaw = -0.35;
    pitch = 0.3;
    if (scene.camera) {
        setDirection(scene.camera->eye - scene.camera->target);
    } else if (const Vec3 open = openSide(scene, lo, hi, upAxis); open != Vec3::Zero()) {
        setDirection(open + 0.3 * upVector());  // from outside the open side, slightly above
    }
    fit(lo, hi);
}

void OrbitCamera::frameSelection(const Scene& scene, const std::vector<PatchId>& patches) {
    if (patches.empty()) return;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (PatchId id : patches) {
        const Patch& p = scene.patches[id];
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const Vec3& v = scene.vertices[scene.corners[p.firstCorner + k]];
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
    }
    fit(lo, hi);
}

void OrbitCamera::lookAlong(const Scene& scene, int axis, bool positive) {
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    sceneRadius = std::max(0.5 * (hi - lo).norm(), 1e-9);
    upAxis = upAxisOf(scene);
    Vec3 d = Vec3::Zero();
    d[axis] = positive ? 1.0 : -1.0;
    setDirection(d);
    fit(lo, hi);
}

void OrbitCamera::set(const Camera& camera) {
    target = camera.target;
    const Vec3 d = camera.eye - camera.target;
    distance = std::max(d.norm(), 1e-9);
    setDirection(d);
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
    return target + distance * toScene(Vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw)));
}

Eigen::Matrix4d OrbitCamera::view() const {
    const Vec3 e = eye();
    const Vec3 f = (target - e).normalized();
    Vec3 u = upVector();
    if (std::abs(f.dot(u)) > 0.999) u = toScene(Vec3(0, 0, 1));
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
