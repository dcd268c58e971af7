// Sunlit fractions by shadow polygons: for a receiver patch, each candidate blocker is clipped to
// the half-space in front of the receiver's plane, projected along the sun's rays onto that plane
// (parallel projection keeps it convex), and subtracted from the receiver's clear convex pieces.
#include "environment/sunlit.hpp"

#include "engine/box_grid.hpp"
#include "engine/error.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace hemirad {

double polygonArea2d(const std::vector<Vec2>& p) {
    double a = 0.0;
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec2& u = p[k];
        const Vec2& v = p[(k + 1) % p.size()];
        a += u.x() * v.y() - v.x() * u.y();
    }
    return 0.5 * std::abs(a);
}

namespace {

/// Pieces of one patch's lit part beyond which the exact subtraction gives up with an error (a bound
/// on memory: each piece is a few corners).
constexpr std::size_t kMaxPieces = 200000;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Splits convex `poly` by the line through a, b: the part left of a->b (inside) and right (outside).
void splitByLine(const std::vector<Vec2>& poly, const Vec2& a, const Vec2& b, std::vector<Vec2>& inside,
                 std::vector<Vec2>& outside) {
    inside.clear();
    outside.clear();
    const Vec2 d = b - a;
    for (std::size_t k = 0; k < poly.size(); ++k) {
        const Vec2& p = poly[k];
        const Vec2& q = poly[(k + 1) % poly.size()];
        const double sp = cross2(d, p - a), sq = cross2(d, q - a);
        if (sp >= 0.0) inside.push_back(p);
        if (sp <= 0.0) outside.push_back(p);  // a corner on the line belongs to both sides
        if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) {
            const Vec2 x = p + (q - p) * (sp / (sp - sq));
            inside.push_back(x);
            outside.push_back(x);
        }
    }
    // A side reduced to points on the line (no area) is no piece.
    if (inside.size() < 3 || polygonArea2d(inside) == 0.0) inside.clear();
    if (outside.size() < 3 || polygonArea2d(outside) == 0.0) outside.clear();
}

}  // namespace

std::vector<std::vector<Vec2>> subtractConvex(const std::vector<std::vector<Vec2>>& pieces, std::vector<Vec2> shadow, double minArea) {
    // Counter-clockwise shadow: its interior is left of every edge.
    double signedArea = 0.0;
    for (std::size_t k = 0; k < shadow.size(); ++k) signedArea += cross2(shadow[k], shadow[(k + 1) % shadow.size()]);
    if (signedArea < 0.0) std::reverse(shadow.begin(), shadow.end());
    if (shadow.size() < 3 || std::abs(signedArea) == 0.0) return pieces;
    std::vector<std::vector<Vec2>> out;
    std::vector<Vec2> inside, outside;
    for (const std::vector<Vec2>& piece : pieces) {
        std::vector<Vec2> rest = piece;
        for (std::size_t k = 0; k < shadow.size() && !rest.empty(); ++k) {
            splitByLine(rest, shadow[k], shadow[(k + 1) % shadow.size()], inside, outside);
            if (!outside.empty() && (minArea == 0.0 || polygonArea2d(outside) > minArea)) out.push_back(outside);
            rest = inside;
        }
        // What is left of `rest` lies inside the shadow: dropped.
    }
    return out;
}

std::vector<std::vector<PatchId>> beamCandidates(const Scene& scene, const Vec3& direction) {
    // Patches whose boxes overlap as the beam sees them (coordinates across its rays).
    const std::size_t n = scene.size();
    Vec3 a, b;
    orthonormalBasis(direction.normalized(), a, b);
    std::vector<Box> boxes(n);
    for (PatchId i = 0; i < n; ++i) {
        const Patch& p = scene.patches[i];
        Box& box = boxes[i];
        box.lo = Vec3::Constant(INFINITY);
        box.hi = Vec3::Constant(-INFINITY);
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const Vec3 c = scene.corner(p, k);
            const Vec3 s(c.dot(a), c.dot(b), 0.0);
            box.lo = box.lo.cwiseMin(s);
            box.hi = box.hi.cwiseMax(s);
        }
    }
    std::vector<std::vector<PatchId>> candidates(n);
    forEachOverlappingPair(boxes, [&](std::uint32_t i, std::uint32_t j) {
        candidates[i].push_back(j);
        candidates[j].push_back(i);
    });
    return candidates;
}

std::vector<double> sunlitFractions(const Scene& scene, const Vec3& toSunGiven) {
    if (!toSunGiven.allFinite() || !(toSunGiven.norm() > 0.0)) throw Error("sun: the direction to the sun must be a finite non-zero vector");
    const Vec3 d = toSunGiven.normalized();
    const std::size_t n = scene.size();
    const double tolerance = 1e-9 * std::max(scene.extent(), 1e-300);

    const std::vector<std::vector<PatchId>> candidates = beamCandidates(scene, d);

    std::vector<double> fraction(n, 0.0);
    std::string failure;  // an error inside the parallel loop, thrown after it
#pragma omp parallel for schedule(dynamic, 64)
    for (std::int64_t ii = 0; ii < std::int64_t(n); ++ii) {
        const PatchId i = PatchId(ii);
        const Patch& p = scene.patches[i];
        if (!(p.normal.dot(d) > 0.0)) continue;
        try {
            Vec3 u, v;
            orthonormalBasis(p.normal, u, v);
            const double whole = polygonArea2d(planeCoordinates(scene.polygon(i), scene.corner(p, 0), u, v));
            if (!(whole > 0.0)) continue;
            double clear = 0.0;
            for (const std::vector<Vec2>& piece : sunlitPieces(scene, i, d, candidates[i], u, v, tolerance)) clear += polygonArea2d(piece);
            fraction[i] = std::clamp(clear / whole, 0.0, 1.0);
        } catch (const std::exception& e) {
#pragma omp critical(hemirad_sunlit_failure)
            if (failure.empty()) failure = e.what();
        }
    }
    if (!failure.empty()) throw Error(failure);
    return fraction;
}

std::vector<Vec2> planeCoordinates(const std::vector<Vec3>& points, const Vec3& origin, const Vec3& u, const Vec3& v) {
    std::vector<Vec2> out;
    out.reserve(points.size());
    for (const Vec3& c : points) out.emplace_back((c - origin).dot(u), (c - origin).dot(v));
    return out;
}

std::vector<std::vector<Vec2>> shadowedPieces(const Scene& scene, std::vector<std::vector<Vec2>> pieces, const Vec3& origin,
                                              const Vec3& normal, const Vec3& u, const Vec3& v, const Vec3& toSource,
                                              const std::vector<PatchId>& blockers, PatchId self, const Plane* slab,
                                              double tolerance) {
    const double facing = normal.dot(toSource);
    std::vector<Vec3> cut, next;
    std::vector<Vec2> shadow;
    // Slivers of rounding size are dropped as they appear: shadows whose edges run along the pieces'
    // (a grid-aligned district under a sun along the grid) would otherwise multiply them without end.
    double area = 0.0;
    for (const std::vector<Vec2>& piece : pieces) area += polygonArea2d(piece);
    const double sliver = 1e-13 * area;
    for (const PatchId j : blockers) {
        if (pieces.empty()) break;
        if (j == self) continue;
        // The blocker's part in front of the plane (height h = normal . (x - origin) >= 0), and of
        // the slab's plane where one is given.
        cut = scene.polygon(j);
        bool ahead = false;
        for (const Vec3& c : cut) ahead = ahead || normal.dot(c - origin) > tolerance;
        if (!ahead) continue;
        clipAbovePlane(origin, normal, cut.data(), cut.size(), next);
        cut.swap(next);
        if (slab && cut.size() >= 3) {
            clipAbovePlane(slab->offset * slab->normal, slab->normal, cut.data(), cut.size(), next);
            cut.swap(next);
        }
        if (cut.size() < 3) continue;
        shadow.clear();
        for (const Vec3& c : cut) {
            const Vec3 x = c - toSource * (normal.dot(c - origin) / facing) - origin;
            shadow.emplace_back(x.dot(u), x.dot(v));
        }
        pieces = subtractConvex(pieces, shadow, sliver);
        if (pieces.size() > kMaxPieces)
            throw Error("sun: patch " + std::to_string(self) + "'s lit part splits into more than " + std::to_string(kMaxPieces) +
                        " pieces under the shadows of " + std::to_string(blockers.size()) + " candidate patches");
    }
    return pieces;
}

std::vector<std::vector<Vec2>> sunlitPieces(const Scene& scene, PatchId i, const Vec3& toSun, const std::vector<PatchId>& blockers,
                                            const Vec3& u, const Vec3& v, double tolerance) {
    const Patch& p = scene.patches[i];
    const Vec3 origin = scene.corner(p, 0);
    return shadowedPieces(scene, {planeCoordinates(scene.polygon(i), origin, u, v)}, origin, p.normal, u, v, toSun.normalized(),
                          blockers, i, nullptr, tolerance);
}

std::vector<double> directIrradiance(const Scene& scene, const Vec3& toSun, double dni, const std::vector<double>& sunlit) {
    const Vec3 d = toSun.normalized();
    std::vector<double> E(scene.size(), 0.0);
    for (PatchId i = 0; i < scene.size(); ++i) E[i] = dni * std::max(0.0, scene.patches[i].normal.dot(d)) * sunlit[i];
    return E;
}

}  // namespace hemirad
