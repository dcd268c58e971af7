// Sunlit fractions by shadow polygons: for a receiver patch, each blocker in the prism it sweeps
// towards the sun is clipped to that prism and to the half-space in front of the receiver's plane,
// projected along the sun's rays onto that plane (parallel projection keeps it convex), and cut out
// of the receiver's clear convex pieces (preprocess/hemisphere/shadow_polygons.hpp).
#include "environment/sunlit.hpp"

#include "engine/error.hpp"
#include "engine/parallel_failure.hpp"
#include "preprocess/hemisphere/convex_pieces.hpp"

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

BeamShadows::BeamShadows(const Scene& scene) : m_scene(scene) {
    m_geometry.build(scene);
    m_geometry.buildNeighbours(scene);
    m_shadows.build(m_geometry, std::vector<std::uint8_t>(scene.size(), 1));
    if (scene.hasMirrors()) m_patches.build(m_geometry, std::vector<std::uint8_t>(scene.size(), 1), false);
    m_tolerance = 1e-9 * std::max(scene.extent(), 1e-300);
}

std::vector<double> BeamShadows::sunlitFractions(const Vec3& toSunGiven) const {
    if (!toSunGiven.allFinite() || !(toSunGiven.norm() > 0.0)) throw Error("sun: the direction to the sun must be a finite non-zero vector");
    const Vec3 d = toSunGiven.normalized();
    const std::size_t n = m_scene.size();
    std::vector<double> fraction(n, 0.0);
    ParallelFailure failure;  // a receiver whose pieces run away: rethrown after the region
#pragma omp parallel
    {
        ShadowPolygons::Scratch scratch;
#pragma omp for schedule(dynamic, 64)
        for (std::int64_t ii = 0; ii < std::int64_t(n); ++ii) {
            const PatchId i = PatchId(ii);
            const PatchShape& shape = m_geometry.shapes[i];
            if (!(shape.normal.dot(d) > 0.0) || failure.failed()) continue;
            failure.run([&] {
                fraction[i] = m_shadows.litFraction(m_geometry.polygon(i), shape.count, shape.normal, i, d, m_tolerance, scratch);
            });
        }
    }
    failure.rethrowIfFailed();
    return fraction;
}

std::vector<double> sunlitFractions(const Scene& scene, const Vec3& toSun) { return BeamShadows(scene).sunlitFractions(toSun); }

std::vector<double> directIrradiance(const Scene& scene, const Vec3& toSun, double dni, const std::vector<double>& sunlit) {
    const Vec3 d = toSun.normalized();
    std::vector<double> E(scene.size(), 0.0);
    for (PatchId i = 0; i < scene.size(); ++i) E[i] = dni * std::max(0.0, scene.patches[i].normal.dot(d)) * sunlit[i];
    return E;
}

}  // namespace hemirad
