// Convex pieces in a plane: a convex polygon cut out of a set of convex pieces, as shadow polygons
// need it (the analytic estimator's partial visibility, the sun's sunlit parts).
#include "preprocess/hemisphere/convex_pieces.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hemirad {

/// Twice the signed area of the 2D polygon xy[0..2k).
double doubleArea(const double* xy, std::size_t k) {
    if (k == 0) return 0.0;
    double a = xy[2 * (k - 1)] * xy[1] - xy[0] * xy[2 * (k - 1) + 1];  // the closing edge, as the loop's last term was
    for (std::size_t i = 0; i + 1 < k; ++i) a += xy[2 * i] * xy[2 * i + 3] - xy[2 * i + 2] * xy[2 * i + 1];
    return a;
}

void reverse2D(double* xy, std::size_t k) {
    for (std::size_t i = 0, j = k - 1; i < j; ++i, --j) {
        std::swap(xy[2 * i], xy[2 * j]);
        std::swap(xy[2 * i + 1], xy[2 * j + 1]);
    }
}

namespace {

/// Splits the convex 2D polygon xy[0..2k) by the line through a and b: the part on its left
/// (inside a counter-clockwise polygon whose edge a -> b is) into `in`, the rest into `out`; their
/// corner counts into inCount and outCount. The buffers only grow (a resize that grows fills what it
/// adds with zeros, which took a tenth of the cuts' time when every call grew them).
void splitByLine(const double* xy, std::size_t k, const double* a, const double* b, std::vector<double>& in,
                 std::size_t& inCount, std::vector<double>& out, std::size_t& outCount) {
    // Each side gets at most k corners and k crossings (k + 1 for a convex polygon, but rounding may
    // bend a piece): sized once and written by index, as this is the inner loop of every shadow
    // after the first.
    if (in.size() < 4 * k) in.resize(4 * k);
    if (out.size() < 4 * k) out.resize(4 * k);
    double* inAt = in.data();
    double* outAt = out.data();
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    auto side = [&](const double* p) { return ex * (p[1] - a[1]) - ey * (p[0] - a[0]); };
    double sp = side(xy);
    for (std::size_t i = 0; i < k; ++i) {
        const double* p = xy + 2 * i;
        const double* q = xy + 2 * (i + 1 == k ? 0 : i + 1);
        const double sq = side(q);
        if (sp >= 0.0) {
            inAt[0] = p[0], inAt[1] = p[1];
            inAt += 2;
        }
        if (sp <= 0.0) {
            outAt[0] = p[0], outAt[1] = p[1];
            outAt += 2;
        }
        if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) {
            const double t = sp / (sp - sq);
            const double cx = p[0] + t * (q[0] - p[0]), cy = p[1] + t * (q[1] - p[1]);
            inAt[0] = cx, inAt[1] = cy;
            outAt[0] = cx, outAt[1] = cy;
            inAt += 2;
            outAt += 2;
        }
        sp = sq;
    }
    inCount = std::size_t(inAt - in.data()) / 2;
    outCount = std::size_t(outAt - out.data()) / 2;
}

}  // namespace

bool convexHull2D(const std::vector<std::array<double, 2>>& points, std::vector<std::array<double, 2>>& hull) {
    hull.clear();
    for (const auto& p : points)
        if (!std::isfinite(p[0]) || !std::isfinite(p[1])) return false;
    if (points.size() < 3) return true;
    // The points on a grid of 2^-40 of their largest coordinate (a power of two), as integers: the
    // turns are then exact (128-bit cross products). Points a rounding apart (a solid's corner
    // projected once for each of its faces, corners of merged tiles lifted back from their plane)
    // make edges of no length whose direction is their rounding: with floating-point turns the
    // chain kept both and bent the wrong way, or took a corner below a column of points for a
    // straight line and dropped it (hulls that lost most of a block's shadow).
    double largest = 0.0;
    for (const auto& p : points) largest = std::max({largest, std::abs(p[0]), std::abs(p[1])});
    if (!(largest > 0.0)) return true;
    const double step = std::ldexp(1.0, std::ilogb(largest) + 1 - 40);  // |k| <= 2^40
    using Grid = std::array<std::int64_t, 2>;
    std::vector<Grid> grid(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
        grid[i] = {std::llround(points[i][0] / step), std::llround(points[i][1] / step)};
    std::sort(grid.begin(), grid.end());
    grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
    if (grid.size() < 3) return true;
    std::vector<Grid> chain(2 * grid.size());
    std::size_t k = 0;
    const auto notLeft = [](const Grid& o, const Grid& a, const Grid& b) {
        return __int128(a[0] - o[0]) * (b[1] - o[1]) - __int128(a[1] - o[1]) * (b[0] - o[0]) <= 0;
    };
    for (std::size_t i = 0; i < grid.size(); ++i) {  // the lower chain
        while (k >= 2 && notLeft(chain[k - 2], chain[k - 1], grid[i])) --k;
        chain[k++] = grid[i];
    }
    for (std::size_t i = grid.size() - 1, lower = k + 1; i-- > 0;) {  // the upper chain
        while (k >= lower && notLeft(chain[k - 2], chain[k - 1], grid[i])) --k;
        chain[k++] = grid[i];
    }
    if (k < 4) return true;  // collinear: no area
    hull.resize(k - 1);  // the last corner is the first
    for (std::size_t i = 0; i + 1 < k; ++i) hull[i] = {double(chain[i][0]) * step, double(chain[i][1]) * step};
    return true;
}

std::size_t clipToConvex(const double* xy, std::size_t k, const double* window, std::size_t w, std::vector<double>& out,
                         std::vector<double>& scratch, std::vector<double>& rest) {
    out.assign(xy, xy + 2 * k);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (std::size_t c = 0; c < w; ++c)
        for (int a = 0; a < 2; ++a) {
            lo[a] = std::min(lo[a], window[2 * c + a]);
            hi[a] = std::max(hi[a], window[2 * c + a]);
        }
    const double shortest = 1e-9 * std::hypot(hi[0] - lo[0], hi[1] - lo[1]);
    std::size_t corners = k, outside = 0;
    for (std::size_t c = 0; c < w && corners >= 3; ++c) {
        // The part left of the window's edge a -> b (inside, counter-clockwise).
        const double* a = &window[2 * c];
        const double* b = &window[2 * (c + 1 == w ? 0 : c + 1)];
        if (!(std::hypot(b[0] - a[0], b[1] - a[1]) > shortest)) continue;
        splitByLine(out.data(), corners, a, b, scratch, corners, rest, outside);
        out.swap(scratch);
    }
    out.resize(2 * corners);
    return corners;
}

/// Cuts the counter-clockwise 2D polygon given[0..2 n) out of every clear piece of s.pieces that it
/// overlaps: each piece's parts outside the shadow's edges, one edge after the other, stay clear;
/// pieces below `smallest` in (twice the) area are dropped.
void subtractConvex(const double* given, std::size_t n, double smallest, ConvexPieces& s) {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (std::size_t c = 0; c < n; ++c)
        for (int a = 0; a < 2; ++a) {
            lo[a] = std::min(lo[a], given[2 * c + a]);
            hi[a] = std::max(hi[a], given[2 * c + a]);
        }
    // Corners within rounding of the one before are one corner: an edge of no length has no line,
    // and splitting by it would leave a whole piece clear (a clipped blocker repeats a corner where
    // it meets the region's edge).
    // (and of its coordinates, which carry their rounding: a shadow far smaller than its distance
    // from the origin has edges of rounding length sooner)
    const double scale = std::max({std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1])),
                                   std::abs(lo[0]), std::abs(lo[1]), std::abs(hi[0]), std::abs(hi[1])});
    const double merge = 1e-9 * scale;
    const auto apart = [merge](const double* a, const double* b) {
        const double dx = a[0] - b[0], dy = a[1] - b[1];
        return dx * dx + dy * dy > merge * merge;
    };
    s.corners.clear();
    for (std::size_t c = 0; c < n; ++c)
        if (s.corners.empty() || apart(&given[2 * c], &s.corners[s.corners.size() - 2])) s.corners.insert(s.corners.end(), &given[2 * c], &given[2 * c + 2]);
    while (s.corners.size() >= 4 && !apart(s.corners.data(), &s.corners[s.corners.size() - 2])) s.corners.resize(s.corners.size() - 2);
    if (s.corners.size() < 6) return;  // no area left: nothing to cut
    const double* shadow = s.corners.data();
    const std::size_t sides = s.corners.size() / 2;
    s.next.clear();
    for (std::size_t at = 0; at < s.pieces.size();) {
        const std::size_t k = std::size_t(s.pieces[at]);
        const double* piece = &s.pieces[at + 1];
        double plo[2] = {1e300, 1e300}, phi[2] = {-1e300, -1e300};
        for (std::size_t c = 0; c < k; ++c)
            for (int a = 0; a < 2; ++a) {
                plo[a] = std::min(plo[a], piece[2 * c + a]);
                phi[a] = std::max(phi[a], piece[2 * c + a]);
            }
        if (phi[0] <= lo[0] || plo[0] >= hi[0] || phi[1] <= lo[1] || plo[1] >= hi[1]) {
            s.next.insert(s.next.end(), piece - 1, piece + 2 * k);
        } else {
            if (s.inside.size() < 2 * k) s.inside.resize(2 * k);
            std::copy(piece, piece + 2 * k, s.inside.begin());
            std::size_t inside = k, rest = 0, outside = 0;  // corners in s.inside, s.rest, s.outside
            for (std::size_t c = 0; c < sides && inside >= 3; ++c) {
                splitByLine(s.inside.data(), inside, &shadow[2 * c], &shadow[2 * ((c + 1) % sides)], s.rest, rest,
                            s.outside, outside);
                s.inside.swap(s.rest);
                inside = rest;
                if (outside >= 3 && std::abs(doubleArea(s.outside.data(), outside)) > smallest) {
                    s.next.push_back(double(outside));
                    s.next.insert(s.next.end(), s.outside.begin(), s.outside.begin() + std::ptrdiff_t(2 * outside));
                }
            }
        }
        at += 1 + 2 * k;
    }
    s.pieces.swap(s.next);
}

}  // namespace hemirad
