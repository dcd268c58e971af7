// Balls around items (patches, reflectors) in a tree, and the cone of lines through two balls: how a
// chain of mirrors finds the patches and reflectors it can reach without testing each one.
#pragma once

#include "engine/math.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace hemirad {

/// Balls around items in a tree (median splits, preorder): a chain's receivers and next reflectors
/// are found by descending where a ball can be in front of the mirror and meet the chain's cone.
struct BallTree {
    struct Ball {
        Vec3 centre = Vec3::Zero();
        double radius = 0.0;
        std::uint32_t first = 0, count = 0;  ///< leaf: its items; inner: count 0
        std::uint32_t right = 0;             ///< inner: the second child (the first follows this ball)
    };
    std::vector<Ball> balls;
    std::vector<std::uint32_t> items;

    /// The tree of the balls (centres[k], radii[k]), item k for each.
    void build(const std::vector<Vec3>& centres, const std::vector<double>& radii);

    /// Calls visit(item) for every item in a leaf whose ball `keep(centre, radius)` accepts (and all
    /// its ancestors'), each item once; `stack` is scratch.
    template <class Keep, class Visit>
    void query(std::vector<std::uint32_t>& stack, Keep keep, Visit visit) const {
        if (balls.empty()) return;
        stack.assign(1, 0);
        while (!stack.empty()) {
            const std::uint32_t at = stack.back();
            const Ball& ball = balls[at];
            stack.pop_back();
            if (!keep(ball.centre, ball.radius)) continue;
            if (ball.count == 0) {
                stack.push_back(ball.right);
                stack.push_back(at + 1);
                continue;
            }
            for (std::uint32_t k = ball.first; k < ball.first + ball.count; ++k) visit(items[k]);
        }
    }

private:
    void split(const std::vector<Vec3>& centres, const std::vector<double>& radii, std::uint32_t first,
               std::uint32_t last);
};

/// Where lines through two balls (an emitter image and an aperture) can go beyond the second: the
/// cone from their inner homothety centre through the second ball. `all` when the balls overlap.
struct BallCone {
    bool all = false;
    Vec3 apex, axis;
    double sine = 0.0, cosine = 1.0;  ///< of the half-angle

    BallCone(const Vec3& c1, double r1, const Vec3& c2, double r2) {
        const Vec3 d = c2 - c1;
        const double length = d.norm();
        if (!(r1 + r2 < length)) {
            all = true;
            return;
        }
        axis = d / length;
        apex = c1 + d * (r1 / (r1 + r2));
        sine = (r1 + r2) / length;
        cosine = std::sqrt(std::max(0.0, 1.0 - sine * sine));
    }
    /// Whether the ball (c, r) can meet the cone: the angle between the axis and c is at most the
    /// half-angle plus the ball's angular radius asin(r / |c - apex|) (both below pi / 2, so the
    /// cosines compare; the 1e-12 keeps the test conservative under rounding).
    bool meets(const Vec3& c, double r) const {
        if (all) return true;
        const Vec3 d = c - apex;
        const double distance2 = d.squaredNorm();
        if (distance2 <= r * r) return true;
        const double distance = std::sqrt(distance2);
        return d.dot(axis) >= cosine * std::sqrt(distance2 - r * r) - sine * r - 1e-12 * distance;
    }
};

}  // namespace hemirad
