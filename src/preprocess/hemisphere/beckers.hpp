// Beckers & Beckers (2012) equal-area partitions of the unit disk, lifted to the hemisphere (Nusselt analog).
#pragma once

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

/// Cumulative counts of the equal-solid-angle hemisphere partition (cells of 2 pi / N steradians),
/// cap boundaries cos(theta_j) = 1 - S[j] / N. Used for sky domes of equal-area patches.
std::vector<std::uint32_t> beckersHemisphereCounts(std::uint32_t N);

}  // namespace hemirad
