// Sunlit fractions by shadow polygons: for a receiver patch, each candidate blocker is clipped to
// the half-space in front of the receiver's plane, projected along the sun's rays onto that plane
// (parallel projection keeps it convex), and subtracted from the receiver's clear convex pieces.
#include "environment/sunlit.hpp"

#include "engine/box_grid.hpp"
#include "engine/error.hpp"
#include "preprocess/hemisphere/convex_pieces.hpp"
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

}  // namespace

std::vector<std::vector<Vec2>> subtractConvex(const std::vector<std::vector<Vec2>>& pieces, std::vector<Vec2> shadow, double minArea) {
    // The packed pieces of preprocess/hemisphere/convex_pieces.hpp, the shadow counter-clockwise.
    if (shadow.size() < 3) return pieces;
    std::vector<double> corners;
    for (const Vec2& c : shadow) corners.insert(corners.end(), {c.x(), c.y()});
    const double signedArea = doubleArea(corners.data(), shadow.size());
    if (signedArea == 0.0) return pieces;
    if (signedArea < 0.0) reverse2D(corners.data(), shadow.size());
    ConvexPieces clear;
    for (const std::vector<Vec2>& piece : pieces) {
        clear.pieces.push_back(double(piece.size()));
        for (const Vec2& c : piece) clear.pieces.insert(clear.pieces.end(), {c.x(), c.y()});
    }
    subtractConvex(corners.data(), shadow.size(), 2.0 * minArea, clear);
    std::vector<std::vector<Vec2>> out;
    for (std::size_t at = 0; at < clear.pieces.size();) {
        const std::size_t k = std::size_t(clear.pieces[at]);
        std::vector<Vec2>& piece = out.emplace_back();
        for (std::size_t c = 0; c < k; ++c) piece.emplace_back(clear.pieces[at + 1 + 2 * c], clear.pieces[at + 2 + 2 * c]);
        at += 1 + 2 * k;
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

BeamShadows::BeamShadows(const Scene& scene) : m_scene(scene) {
    m_geometry.build(scene);
    m_geometry.buildNeighbours(scene);
    m_shadows.build(m_geometry, std::vector<std::uint8_t>(scene.size(), 1));
    m_tolerance = 1e-9 * std::max(scene.extent(), 1e-300);
}

std::vector<double> BeamShadows::sunlitFractions(const Vec3& toSunGiven) const {
    if (!toSunGiven.allFinite() || !(toSunGiven.norm() > 0.0)) throw Error("sun: the direction to the sun must be a finite non-zero vector");
    const Vec3 d = toSunGiven.normalized();
    const std::size_t n = m_scene.size();
    std::vector<double> fraction(n, 0.0);
#pragma omp parallel
    {
        ShadowPolygons::Scratch scratch;
#pragma omp for schedule(dynamic, 64)
        for (std::int64_t ii = 0; ii < std::int64_t(n); ++ii) {
            const PatchId i = PatchId(ii);
            const PatchShape& shape = m_geometry.shapes[i];
            if (!(shape.normal.dot(d) > 0.0)) continue;
            fraction[i] = m_shadows.litFraction(m_geometry.polygon(i), shape.count, shape.normal, i, d, m_tolerance, scratch);
        }
    }
    return fraction;
}

std::vector<double> sunlitFractions(const Scene& scene, const Vec3& toSun) { return BeamShadows(scene).sunlitFractions(toSun); }

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
