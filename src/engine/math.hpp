// Small vector types shared by every module: Vec3 (double positions/normals) and Rgb (per-channel values).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace hemirad {

using Vec3 = Eigen::Vector3d;
using Rgb = Eigen::Array3d;
using PatchId = std::uint32_t;

constexpr double kPi = 3.14159265358979323846;

/// Any unit vector orthogonal to the unit vector n (Duff et al. 2017, branchless ONB).
inline void orthonormalBasis(const Vec3& n, Vec3& t, Vec3& b) {
    const double sign = n.z() >= 0.0 ? 1.0 : -1.0;
    const double a = -1.0 / (sign + n.z());
    const double c = n.x() * n.y() * a;
    t = Vec3(1.0 + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
    b = Vec3(c, sign + n.y() * n.y() * a, -n.y());
}

/// Reflection about the plane n . x + d = 0 (n unit) as a 4 x 4 transform of points.
inline Eigen::Matrix4d reflectionMatrix(const Vec3& n, double d) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<3, 3>(0, 0) -= 2.0 * n * n.transpose();
    m.block<3, 1>(0, 3) = -2.0 * d * n;
    return m;
}

}  // namespace hemirad
