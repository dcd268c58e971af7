// Beckers & Beckers (2012) partitions.
#include "preprocess/hemisphere/beckers.hpp"

#include "engine/error.hpp"
#include "engine/math.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

std::vector<std::uint32_t> beckersDiskCounts(std::uint32_t N) {
    if (N == 0) throw Error("Beckers partition: the number of cells must be at least 1");
    // Rings of (about) equal radial width w = sqrt(pi/N), working inwards from the rim.
    const double w = std::sqrt(kPi / N);
    std::vector<std::uint32_t> k{N};
    double r = 1.0;
    for (;;) {
        const double r1 = r - w;
        const double k1 = r1 > 0.0 ? std::floor(k.back() * (r1 / r) * (r1 / r) + 0.5) : 0.0;
        if (k1 < 6.0) {
            k.push_back(1);
            break;
        }
        k.push_back(static_cast<std::uint32_t>(k1));
        r = r1;
    }
    std::reverse(k.begin(), k.end());
    // A single cell (N < 6) leaves S = {1, 1}: collapse the repeated entry.
    k.erase(std::unique(k.begin(), k.end()), k.end());
    return k;
}

std::vector<float> beckersDirections(std::uint32_t N) {
    const std::vector<std::uint32_t> S = beckersDiskCounts(N);
    std::vector<float> dirs;
    dirs.reserve(3 * static_cast<std::size_t>(N));
    dirs.insert(dirs.end(), {0.0f, 0.0f, 1.0f});
    for (std::size_t j = 1; j < S.size(); ++j) {
        const double r0sq = double(S[j - 1]) / N, r1sq = double(S[j]) / N;
        const double r = std::sqrt(0.5 * (r0sq + r1sq));
        const std::uint32_t cells = S[j] - S[j - 1];
        for (std::uint32_t m = 0; m < cells; ++m) {
            const double phi = 2.0 * kPi * (m + 0.5) / cells;
            dirs.push_back(static_cast<float>(r * std::cos(phi)));
            dirs.push_back(static_cast<float>(r * std::sin(phi)));
            dirs.push_back(static_cast<float>(std::sqrt(std::max(0.0, 1.0 - r * r))));
        }
    }
    return dirs;
}

std::vector<std::uint32_t> beckersHemisphereCounts(std::uint32_t N) {
    if (N == 0) throw Error("Beckers hemisphere partition: the number of cells must be at least 1");
    const double w = std::sqrt(2.0 * kPi / N);
    std::vector<std::uint32_t> k{N};
    double t = kPi / 2.0;
    for (;;) {
        const double t1 = t - w;
        const double ratio = std::sin(t1 / 2.0) / std::sin(t / 2.0);
        const double k1 = t1 > 0.0 ? std::floor(k.back() * ratio * ratio + 0.5) : 0.0;
        if (k1 < 7.0) {
            k.push_back(1);
            break;
        }
        // Re-snap the ring boundary so that the cap keeps exactly k1 cells of equal area.
        t = 2.0 * std::asin(std::sin(t / 2.0) * std::sqrt(k1 / k.back()));
        k.push_back(static_cast<std::uint32_t>(k1));
    }
    std::reverse(k.begin(), k.end());
    k.erase(std::unique(k.begin(), k.end()), k.end());
    return k;
}

}  // namespace hemirad
