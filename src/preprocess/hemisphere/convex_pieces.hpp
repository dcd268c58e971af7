// Convex pieces in a plane: the clear part of a polygon as a set of convex pieces, from which convex
// shadows are cut one after the other (shadow polygons: the analytic estimator's partial visibility
// and the sun's sunlit parts).
#pragma once

#include <array>
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

/// The convex hull of `points` into `hull`, counter-clockwise, collinear corners dropped (Andrew's
/// monotone chain on the points snapped to a grid of 2^-40 of their largest coordinate: the
/// corners are the points moved by 1e-12 of it at most); fewer than 3 corners where the points
/// span no area. False, `hull` empty, where a coordinate is not finite.
bool convexHull2D(const std::vector<std::array<double, 2>>& points, std::vector<std::array<double, 2>>& hull);

/// The part of the convex 2D polygon xy[0..2k) inside the counter-clockwise convex polygon
/// window[0..2w) into `out` (2 values a corner, Sutherland-Hodgman); `scratch` and `rest` are reused. Returns
/// its corner count (below 3: they do not meet). Window edges shorter than 1e-9 of the window's
/// size (two corners a rounding apart, where a receiver was cut at a plane) cut nothing: their
/// direction is rounding.
std::size_t clipToConvex(const double* xy, std::size_t k, const double* window, std::size_t w, std::vector<double>& out,
                         std::vector<double>& scratch, std::vector<double>& rest);

/// Cuts the counter-clockwise convex 2D polygon shadow[0..2n) out of every piece of s.pieces it
/// overlaps: each piece's parts outside the shadow's edges, one edge after the other, stay clear
/// (pieces below `smallest` in twice their area are dropped). Corners within 1e-9 of the shadow's
/// size of the one before count as one.
void subtractConvex(const double* shadow, std::size_t n, double smallest, ConvexPieces& s);

}  // namespace hemirad
