// Exact unoccluded form factor from a differential area to a polygon (Lambert's contour integral),
// and the clipping of a polygon to the hemisphere above a point.
#pragma once

#include "engine/math.hpp"

#include <cstddef>
#include <vector>

namespace hemirad {

/// Differential area at x with unit normal n to the planar polygon p[0..count) lying on or above
/// the plane through x (clip it first otherwise): Lambert's formula
///     F = 1/(2 pi) | sum_k gamma_k n . (R_k x R_k+1) / |R_k x R_k+1| |,  R_k = p_k - x,
/// gamma_k the angle between R_k and R_k+1 (Baum, Rushmeier & Winget 1989, after Lambert).
/// Exact for any planar simple polygon, convex or not.
double pointToPolygonFactor(const Vec3& x, const Vec3& n, const Vec3* p, std::size_t count);

/// The mean of the corners p[0..count): where shadow rays aim, and the middle of a convex polygon.
Vec3 vertexMean(const Vec3* p, std::size_t count);

/// The part of polygon p[0..count) with n . (y - x) >= 0 (Sutherland-Hodgman), written to `out`
/// (cleared first). Empty when nothing lies above the plane.
void clipAbovePlane(const Vec3& x, const Vec3& n, const Vec3* p, std::size_t count, std::vector<Vec3>& out);

/// An area-uniform map of the unit square onto the convex polygon p[0..count): bilinear for a
/// parallelogram (keeps stratification), else a fan triangle chosen by area with u, then folded.
Vec3 pointOnPolygon(const Vec3* p, std::size_t count, double u, double v);

/// Splits the convex polygon p[0..count) into `count` quads (corner k, the midpoint of edge k,
/// the vertex centroid, the midpoint of edge k - 1), appended to `out` as 4 corners each. For a
/// parallelogram this is its 2 x 2 grid; the pieces' factors add up to the polygon's.
void splitPolygon(const Vec3* p, std::size_t count, std::vector<Vec3>& out);

/// A product rule over the convex polygon p[0..count) built from a rule on [0, 1] (nodes,
/// weights): quads through their bilinear map weighted by its Jacobian, other polygons per fan
/// triangle through the collapsed square (Duffy) map. Points and weights (summing to 1) are
/// appended to `points` and `pointWeights`. Smooth maps keep Gauss-Legendre's high order. A
/// zero-area polygon gets its vertex centroid with weight 1.
void polygonQuadrature(const Vec3* p, std::size_t count, const std::vector<double>& nodes,
                       const std::vector<double>& weights, std::vector<Vec3>& points, std::vector<double>& pointWeights);

/// Gauss-Legendre rule of order n on [0, 1]: nodes and weights (summing to 1), by Newton's method.
void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace hemirad
