// How many points of the emitter the analytic estimator integrates Lambert's point-to-polygon factor
// over, per receiver: a Gauss-Legendre product rule whose order follows from the pair's geometry.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace hemirad {

/// A receiver whose nearest possible point lies within this many emitter radii sees F(x -> j) vary
/// strongly over the emitter: it gets the near-field rule (nearOrder).
constexpr double kNearDistance = 3.0;

/// The near-field order: 6 x 6 points for one to four origins, more for the many-origin runs that
/// serve as references.
inline int nearOrder(std::uint32_t origins) {
    return std::min(16, std::max(6, 3 * int(std::ceil(std::sqrt(double(origins))))));
}

/// The far-field order --origins K asks for: 1 (the centroid) or ceil(sqrt(K)).
inline int farOrder(std::uint32_t origins) {
    return origins <= 1 ? 1 : int(std::ceil(std::sqrt(double(origins)) - 1e-9));
}

/// The points of the m x m rule --origins K asks for (m = farOrder(K)): the analytic estimator's
/// emitter points and the hemicube's hemicubes per patch.
inline std::uint32_t originPoints(std::uint32_t origins) {
    const auto m = static_cast<std::uint32_t>(farOrder(origins));
    return m * m;
}

/// The lowest order m >= `lowest` whose estimated relative error for a receiver at `ratio` =
/// (distance to its nearest possible point) / (emitter radius) is at most a tolerance; `near`
/// within kNearDistance or when no lower order is good enough. The m x m product rule's error
/// behaves like C rho^(-2m): measured on parallel, perpendicular and offset plates (rho = 1.5..90)
/// C stays below 1.5 for m = 1, 2 for m = 2 and 1 above. The thresholds are computed once, so an
/// order costs a few comparisons (one per pair of patches in the direct factors).
class EmitterOrders {
public:
    EmitterOrders(double tolerance, int lowest, int near) : m_lowest(lowest), m_near(std::max(lowest, near)) {
        for (int m = lowest; m < near; ++m) {
            const double c = m == 1 ? 1.5 : m == 2 ? 2.0 : 1.0;
            m_threshold.push_back(std::max(kNearDistance, std::pow(c / tolerance, 1.0 / (2.0 * m))));
        }
    }
    int operator()(double ratio) const {
        if (!(ratio >= kNearDistance)) return m_near;
        for (std::size_t k = 0; k < m_threshold.size(); ++k)
            if (ratio >= m_threshold[k]) return m_lowest + int(k);
        return m_near;
    }
    int lowest() const { return m_lowest; }
    int highest() const { return m_near; }

private:
    int m_lowest, m_near;
    std::vector<double> m_threshold;  ///< the smallest ratio order lowest + k is good for
};

}  // namespace hemirad
