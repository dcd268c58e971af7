// The ball tree's build: median splits along the widest axis of the centres.
#include "preprocess/hemisphere/ball_tree.hpp"

#include <algorithm>
#include <limits>

namespace hemirad {

void BallTree::build(const std::vector<Vec3>& centres, const std::vector<double>& radii) {
    balls.clear();
    items.resize(centres.size());
    for (std::uint32_t k = 0; k < items.size(); ++k) items[k] = k;
    if (!items.empty()) split(centres, radii, 0, std::uint32_t(items.size()));
}

void BallTree::split(const std::vector<Vec3>& centres, const std::vector<double>& radii, std::uint32_t first,
                     std::uint32_t last) {
    constexpr std::uint32_t kLeaf = 8;
    Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (std::uint32_t k = first; k < last; ++k) {
        low = low.cwiseMin(centres[items[k]]);
        high = high.cwiseMax(centres[items[k]]);
    }
    const std::size_t index = balls.size();
    balls.emplace_back();
    Ball ball;
    ball.centre = 0.5 * (low + high);
    for (std::uint32_t k = first; k < last; ++k)
        ball.radius = std::max(ball.radius, (centres[items[k]] - ball.centre).norm() + radii[items[k]]);
    ball.radius *= 1.0 + 1e-12;
    if (last - first <= kLeaf) {
        ball.first = first;
        ball.count = last - first;
        balls[index] = ball;
        return;
    }
    int axis = 0;
    (high - low).maxCoeff(&axis);
    const std::uint32_t middle = first + (last - first) / 2;
    std::nth_element(items.begin() + first, items.begin() + middle, items.begin() + last,
                     [&](std::uint32_t a, std::uint32_t b) {
                         const double ca = centres[a][axis], cb = centres[b][axis];
                         return ca < cb || (ca == cb && a < b);
                     });
    split(centres, radii, first, middle);
    ball.right = std::uint32_t(balls.size());
    split(centres, radii, middle, last);
    balls[index] = ball;
}

}  // namespace hemirad
