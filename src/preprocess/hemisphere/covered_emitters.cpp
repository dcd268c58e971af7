#include "preprocess/hemisphere/covered_emitters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hemirad {

namespace {

/// Whether x on a patch with normal n lies inside a closed solid: the rays along n and tilted 60
/// and 85 degrees towards four sides all meet the back of a patch first.
bool insideSolid(const Vec3& x, const Vec3& n, const PatchGeometry& geometry, const RayScene& rays) {
    const Vec3 origin = x + rays.originOffset() * n;
    auto backHit = [&](const Vec3& dir) {
        const RayScene::Hit hit = rays.intersect(origin, dir);
        return hit.patch != RayScene::kNoHit && geometry.shapes[hit.patch].normal.dot(dir) > 0.0;
    };
    if (!backHit(n)) return false;
    const Vec3 t1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
    const Vec3 t2 = n.cross(t1);
    for (const double tilt : {60.0, 85.0}) {
        const double c = std::cos(tilt * kPi / 180.0), s = std::sin(tilt * kPi / 180.0);
        for (const Vec3& t : {t1, Vec3(-t1), t2, Vec3(-t2)})
            if (!backHit(c * n + s * t)) return false;
    }
    return true;
}

/// polygonQuadrature's map of (u, v) in [0, 1]^2 onto part `part` of polygon p (a quad's bilinear
/// square, else fan triangle part + 1's collapsed square), and its area element.
Vec3 mapPoint(const Vec3* p, std::size_t count, std::uint32_t part, double u, double v, double& jacobian) {
    if (count == 4) {
        const Vec3 du = (1 - v) * (p[1] - p[0]) + v * (p[2] - p[3]);
        const Vec3 dv = (1 - u) * (p[3] - p[0]) + u * (p[2] - p[1]);
        jacobian = du.cross(dv).norm();
        return (1 - u) * (1 - v) * p[0] + u * (1 - v) * p[1] + u * v * p[2] + (1 - u) * v * p[3];
    }
    const std::size_t t = part + 1;
    jacobian = u * (p[t] - p[0]).cross(p[t + 1] - p[0]).norm();
    return p[0] + u * (p[t] - p[0]) + u * v * (p[t + 1] - p[t]);
}

}  // namespace

void CoveredEmitters::build(const PatchGeometry& geometry, const RayScene& rays) {
    m_index.assign(geometry.shapes.size(), kNone);
    m_cells.clear();
    const int K = kCells, S = kSubcells;
    for (PatchId e = 0; e < geometry.shapes.size(); ++e) {
        const PatchShape& shape = geometry.shapes[e];
        const Vec3* corner = geometry.polygon(e);
        const std::uint32_t parts = shape.count == 4 ? 1u : shape.count - 2;
        auto inside = [&](const Vec3& x) { return insideSolid(x, shape.normal, geometry, rays); };
        std::vector<std::uint8_t> corners(shape.count, 0);
        bool any = false;
        for (std::uint32_t k = 0; k < shape.count; ++k) {
            corners[k] = inside(geometry.insetCorner(e, k));  // where PairRules::cornerProbe starts
            any = any || corners[k];
        }
        double jacobian = 0.0;
        for (std::uint32_t part = 0; part < parts && !any; ++part)
            for (int a = 0; a < kFirstLook && !any; ++a)
                for (int b = 0; b < kFirstLook && !any; ++b)
                    any = inside(mapPoint(corner, shape.count, part, (a + 0.5) / kFirstLook, (b + 0.5) / kFirstLook, jacobian));
        if (!any) continue;
        // Each cell's centre says whether it is covered; a cell whose status differs from a
        // neighbour's in its part holds the solid's edge and takes S x S points instead.
        Cells cells;
        cells.parts = parts;
        const std::size_t per = std::size_t(K * K);
        cells.centres.resize(parts * per);
        cells.weights.resize(parts * per);
        cells.whole.assign(parts * per, 1);
        std::vector<std::uint8_t> status(parts * per);
        double total = 0.0;
        for (std::uint32_t part = 0; part < parts; ++part)
            for (int a = 0; a < K; ++a)
                for (int b = 0; b < K; ++b) {
                    const std::size_t q = part * per + std::size_t(a * K + b);
                    cells.centres[q] = mapPoint(corner, shape.count, part, (a + 0.5) / K, (b + 0.5) / K, jacobian);
                    cells.weights[q] = jacobian;  // the midpoint rule is exact for these linear and bilinear maps' areas
                    total += jacobian;
                    status[q] = inside(cells.centres[q]);
                }
        if (!(total > 0.0)) continue;  // degenerate: no area to cover
        bool some = false;  // of its area covered
        for (std::uint32_t part = 0; part < parts; ++part)
            for (int a = 0; a < K; ++a)
                for (int b = 0; b < K; ++b) {
                    const std::size_t q = part * per + std::size_t(a * K + b);
                    bool edge = false;
                    for (const auto& [da, db] : {std::pair{-1, 0}, std::pair{1, 0}, std::pair{0, -1}, std::pair{0, 1}}) {
                        const int na = a + da, nb = b + db;
                        if (na >= 0 && na < K && nb >= 0 && nb < K && status[part * per + std::size_t(na * K + nb)] != status[q])
                            edge = true;
                    }
                    if (!edge) {
                        if (status[q]) {
                            cells.weights[q] = 0.0;
                            cells.whole[q] = 0;
                            some = true;
                        }
                        continue;
                    }
                    Vec3 sum = Vec3::Zero();
                    double weight = 0.0;
                    for (int s = 0; s < S; ++s)
                        for (int t = 0; t < S; ++t) {
                            const Vec3 x = mapPoint(corner, shape.count, part, (a + (s + 0.5) / S) / K,
                                                    (b + (t + 0.5) / S) / K, jacobian);
                            if (inside(x)) continue;
                            sum += jacobian * x;
                            weight += jacobian;
                        }
                    const double full = cells.weights[q];
                    cells.weights[q] = weight / (S * S);
                    if (weight > 0.0) cells.centres[q] = sum / weight;
                    if (cells.weights[q] < full * (1.0 - 1e-12)) {
                        cells.whole[q] = 0;
                        some = true;
                    }
                }
        if (!some) continue;  // its corner or first look hit the solid's rim: nothing of it is covered
        for (double& w : cells.weights) w /= total;
        cells.cornerCovered = std::move(corners);
        m_index[e] = std::uint32_t(m_cells.size());
        m_cells.push_back(std::move(cells));
    }
}

namespace {

/// Cells [a0, a1) x [b0, b1) of one part (per = kCells^2 cells from `first`): their free area and
/// its centroid; `whole` whether all of them are free.
struct Block {
    Vec3 point = Vec3::Zero();
    double weight = 0.0;
    bool whole = true;
};

}  // namespace

void CoveredEmitters::freeRule(PatchId e, int m, std::vector<Vec3>& points, std::vector<double>& weights) const {
    const Cells& cells = m_cells[m_index[e]];
    const std::size_t per = std::size_t(kCells * kCells);
    for (std::uint32_t part = 0; part < cells.parts; ++part) {
        auto block = [&](int a0, int a1, int b0, int b1) {
            Block k;
            for (int a = a0; a < a1; ++a)
                for (int b = b0; b < b1; ++b) {
                    const std::size_t q = part * per + std::size_t(a * kCells + b);
                    k.point += cells.weights[q] * cells.centres[q];
                    k.weight += cells.weights[q];
                    k.whole = k.whole && cells.whole[q];
                }
            if (k.weight > 0.0) k.point /= k.weight;
            return k;
        };
        // The free cell of [a0, a1) x [b0, b1) nearest to `point`, a whole one first.
        auto nearestFree = [&](int a0, int a1, int b0, int b1, const Vec3& point) {
            double best = std::numeric_limits<double>::infinity();
            bool bestWhole = false;
            Vec3 chosen = point;
            for (int a = a0; a < a1; ++a)
                for (int b = b0; b < b1; ++b) {
                    const std::size_t q = part * per + std::size_t(a * kCells + b);
                    if (!(cells.weights[q] > 0.0)) continue;
                    const bool whole = cells.whole[q] != 0;
                    const double d = (cells.centres[q] - point).squaredNorm();
                    if ((whole && !bestWhole) || (whole == bestWhole && d < best)) {
                        best = d;
                        bestWhole = whole;
                        chosen = cells.centres[q];
                    }
                }
            return chosen;
        };
        for (int A = 0; A < m; ++A)
            for (int B = 0; B < m; ++B) {
                const int a0 = A * kCells / m, a1 = (A + 1) * kCells / m, b0 = B * kCells / m, b1 = (B + 1) * kCells / m;
                const Block k = block(a0, a1, b0, b1);
                if (!(k.weight > 0.0)) continue;
                if (k.whole) {
                    points.push_back(k.point);
                    weights.push_back(k.weight);
                    continue;
                }
                // The solid's edge crosses the block: its free part (an L-shaped strip's centroid
                // lies under the solid) in tiles of kTile x kTile cells, each at its free centroid
                // if whole, else at the free cell nearest to it.
                for (int a = a0; a < a1; a += kTile)
                    for (int b = b0; b < b1; b += kTile) {
                        const int ta = std::min(a1, a + kTile), tb = std::min(b1, b + kTile);
                        const Block t = block(a, ta, b, tb);
                        if (!(t.weight > 0.0)) continue;
                        points.push_back(t.whole ? t.point : nearestFree(a, ta, b, tb, t.point));
                        weights.push_back(t.weight);
                    }
            }
    }
}

bool CoveredEmitters::cornerCovered(PatchId e, std::uint32_t k) const {
    return covered(e) && m_cells[m_index[e]].cornerCovered[k] != 0;
}


}  // namespace hemirad
