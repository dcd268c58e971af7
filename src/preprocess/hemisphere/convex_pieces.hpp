// Convex pieces in a plane: the clear part of a polygon as a set of convex pieces, from which convex
// shadows are cut one after the other (shadow polygons: the analytic estimator's partial visibility
// and the sun's sunlit parts).
#pragma once

#include <cstddef>
#include <vector>

namespace hemirad {

/// Clear convex pieces, 2D, packed as (count, x0, y0, x1, y1, ...) one after the other, and the
/// scratch the cuts reuse.
struct ConvexPieces {
    std::vector<double> pieces;
    std::vector<double> next, inside, outside, rest, corners;  // scratch
};

/// Twice the signed area of the 2D polygon xy[0..2k) (positive counter-clockwise).
double doubleArea(const double* xy, std::size_t k);

/// Reverses the order of the 2D polygon xy[0..2k)'s corners.
void reverse2D(double* xy, std::size_t k);

/// Cuts the counter-clockwise convex 2D polygon shadow[0..2n) out of every piece of s.pieces it
/// overlaps: each piece's parts outside the shadow's edges, one edge after the other, stay clear
/// (pieces below `smallest` in twice their area are dropped). Corners within 1e-9 of the shadow's
/// size of the one before count as one.
void subtractConvex(const double* shadow, std::size_t n, double smallest, ConvexPieces& s);

}  // namespace hemirad
