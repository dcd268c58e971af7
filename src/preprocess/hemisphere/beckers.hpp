// Beckers & Beckers (2012) equal-area partitions of the unit disk, lifted to the hemisphere (Nusselt analog).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace hemirad {

/// Cumulative cell counts S[0] = 1 < S[1] < ... < S[n] = N of the disk partition into N cells of
/// area pi / N: ring j holds S[j] - S[j-1] cells between radii sqrt(S[j-1]/N) and sqrt(S[j]/N).
/// N >= 1. (Beckers & Beckers, "A general rule for disk and hemisphere partition into equal-area
/// cells", Computational Geometry 45, 2012.)
std::vector<std::uint32_t> beckersDiskCounts(std::uint32_t N);

/// One direction per cell in the patch frame (z = normal), each carrying projected solid angle
/// pi / N, i.e. exactly 1/N of the form factor. The representative is the cell's area-median
/// radius sqrt((r0^2 + r1^2) / 2) at the mid azimuth; the central cell uses the normal.
/// Layout: x0 y0 z0 x1 y1 z1 ... (3 N floats).
std::vector<float> beckersDirections(std::uint32_t N);

/// Like beckersDirections but one random direction per cell, area-uniform within the cell on the
/// disk (r = sqrt(r0^2 + u (r1^2 - r0^2)), phi uniform in the cell): stratified and unbiased.
/// `S` = beckersDiskCounts(N); `uniform` draws from [0, 1); writes 3 N floats to `out`.
template <class Uniform>
void beckersJitteredDirections(const std::vector<std::uint32_t>& S, Uniform&& uniform, float* out) {
    const double N = S.back();
    std::size_t k = 0;
    auto put = [&](double r, double phi) {
        out[k++] = static_cast<float>(r * std::cos(phi));
        out[k++] = static_cast<float>(r * std::sin(phi));
        out[k++] = static_cast<float>(std::sqrt(std::max(0.0, 1.0 - r * r)));
    };
    put(std::sqrt(uniform() / N), 2.0 * 3.14159265358979323846 * uniform());  // the central cell
    for (std::size_t j = 1; j < S.size(); ++j) {
        const double r0sq = double(S[j - 1]) / N, r1sq = double(S[j]) / N;
        const std::uint32_t cells = S[j] - S[j - 1];
        for (std::uint32_t m = 0; m < cells; ++m)
            put(std::sqrt(r0sq + uniform() * (r1sq - r0sq)), 2.0 * 3.14159265358979323846 * (m + uniform()) / cells);
    }
}

/// Cumulative counts of the equal-solid-angle hemisphere partition (cells of 2 pi / N steradians),
/// cap boundaries cos(theta_j) = 1 - S[j] / N. Used for sky domes of equal-area patches.
std::vector<std::uint32_t> beckersHemisphereCounts(std::uint32_t N);

}  // namespace hemirad
