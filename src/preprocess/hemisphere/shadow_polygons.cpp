// Shadow polygons: blockers clipped to the cone from a point through a receiver, projected onto
// the receiver's plane and cut out of it; Lambert's factor of what stays clear.
#include "preprocess/hemisphere/shadow_polygons.hpp"

#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace hemirad {

namespace {

/// Twice the signed area of the 2D polygon xy[0..2k).
double doubleArea(const double* xy, std::size_t k) {
    double a = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
        const std::size_t j = (i + 1) % k;
        a += xy[2 * i] * xy[2 * j + 1] - xy[2 * j] * xy[2 * i + 1];
    }
    return a;
}

void reverse2D(double* xy, std::size_t k) {
    for (std::size_t i = 0, j = k - 1; i < j; ++i, --j) {
        std::swap(xy[2 * i], xy[2 * j]);
        std::swap(xy[2 * i + 1], xy[2 * j + 1]);
    }
}

/// Splits the convex 2D polygon xy[0..2k) by the line through a and b: the part on its left
/// (inside a counter-clockwise polygon whose edge a -> b is) into `in`, the rest into `out`.
void splitByLine(const double* xy, std::size_t k, const double* a, const double* b, std::vector<double>& in,
                 std::vector<double>& out) {
    in.clear();
    out.clear();
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    auto side = [&](const double* p) { return ex * (p[1] - a[1]) - ey * (p[0] - a[0]); };
    for (std::size_t i = 0; i < k; ++i) {
        const double* p = xy + 2 * i;
        const double* q = xy + 2 * ((i + 1) % k);
        const double sp = side(p), sq = side(q);
        if (sp >= 0.0) in.insert(in.end(), p, p + 2);
        if (sp <= 0.0) out.insert(out.end(), p, p + 2);
        if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) {
            const double t = sp / (sp - sq);
            const double cut[2] = {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])};
            in.insert(in.end(), cut, cut + 2);
            out.insert(out.end(), cut, cut + 2);
        }
    }
}

/// The part of polygon `poly` with m . y - d >= 0 into `out` (Sutherland-Hodgman).
void clipToPlane(const std::vector<Vec3>& poly, const Vec3& m, double d, std::vector<Vec3>& out) {
    out.clear();
    const std::size_t k = poly.size();
    for (std::size_t i = 0; i < k; ++i) {
        const Vec3& p = poly[i];
        const Vec3& q = poly[(i + 1) % k];
        const double sp = m.dot(p) - d, sq = m.dot(q) - d;
        if (sp >= 0.0) out.push_back(p);
        if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
    }
}

}  // namespace

void ShadowPolygons::build(const PatchGeometry& geometry, const std::vector<std::uint8_t>& blocks) {
    m_geometry = &geometry;
    m_items.clear();
    m_nodes.clear();
    for (PatchId j = 0; j < blocks.size(); ++j)
        if (blocks[j]) m_items.push_back(j);
    if (m_items.empty()) return;
    m_nodes.reserve(2 * m_items.size());
    buildNode(0, std::uint32_t(m_items.size()));
}

std::uint32_t ShadowPolygons::buildNode(std::uint32_t first, std::uint32_t count) {
    const std::uint32_t index = std::uint32_t(m_nodes.size());
    m_nodes.emplace_back();
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    Vec3 clo = lo, chi = hi;
    for (std::uint32_t k = first; k < first + count; ++k) {
        const PatchShape& s = m_geometry->shapes[m_items[k]];
        for (std::uint32_t c = 0; c < s.count; ++c) {
            lo = lo.cwiseMin(m_geometry->corners[s.first + c]);
            hi = hi.cwiseMax(m_geometry->corners[s.first + c]);
        }
        clo = clo.cwiseMin(s.centroid);
        chi = chi.cwiseMax(s.centroid);
    }
    m_nodes[index].lo = lo;
    m_nodes[index].hi = hi;
    if (count <= 4) {
        m_nodes[index].first = first;
        m_nodes[index].count = count;
        return index;
    }
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    const std::uint32_t half = count / 2;
    std::nth_element(m_items.begin() + first, m_items.begin() + first + half, m_items.begin() + first + count,
                     [&](PatchId a, PatchId b) {
                         return m_geometry->shapes[a].centroid[axis] < m_geometry->shapes[b].centroid[axis];
                     });
    buildNode(first, half);  // at index + 1
    const std::uint32_t right = buildNode(first + half, count - half);
    m_nodes[index].right = right;
    return index;
}

double ShadowPolygons::visibleFactor(const Vec3& x, const Vec3& n, const Vec3* p, std::size_t count, PatchId e,
                                     PatchId r, double whole, Scratch& s) const {
    s.shadows = 0;
    if (m_items.empty() || count < 3) return whole;
    const Vec3& normal = m_geometry->shapes[r].normal;
    const double offset = normal.dot(p[0]);
    const double height = normal.dot(x) - offset;  // x above the receiver's plane
    if (!(height > 0.0)) return whole;
    const Vec3 middle = vertexMean(p, count);
    const double tolerance = 1e-9 * ((middle - x).norm() + m_geometry->shapes[r].radius);

    // The cone from x through the polygon: a plane through x and each edge (normals inward), and
    // the receiver's plane, lifted by the tolerance so that nothing lying on it casts a shadow.
    constexpr std::size_t kMaxPlanes = 64;
    std::array<Vec3, kMaxPlanes> m;
    std::array<double, kMaxPlanes> d;
    std::size_t planes = 0;
    for (std::size_t k = 0; k < count && planes + 1 < kMaxPlanes; ++k) {
        Vec3 side = (p[k] - x).cross(p[(k + 1) % count] - x);
        const double length = side.norm();
        if (!(length > 0.0)) continue;
        side /= length;
        if (side.dot(middle - x) < 0.0) side = -side;
        m[planes] = side;
        d[planes++] = side.dot(x);
    }
    m[planes] = normal;
    d[planes++] = offset + tolerance;

    // The receiver in 2D coordinates of its plane (origin p[0]), counter-clockwise.
    const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    const Vec3 u = normal.cross(helper).normalized(), v = normal.cross(u);
    const Vec3 origin = p[0];
    s.pieces.assign(1, double(count));
    for (std::size_t k = 0; k < count; ++k) {
        s.pieces.push_back((p[k] - origin).dot(u));
        s.pieces.push_back((p[k] - origin).dot(v));
    }
    const double area = doubleArea(&s.pieces[1], count);
    if (area < 0.0) reverse2D(&s.pieces[1], count);
    const double smallest = 1e-12 * std::abs(area);
    if (!(smallest > 0.0)) return whole;

    s.stack.assign(1, 0);
    bool clear = true;  // some of the receiver still clear
    while (!s.stack.empty() && clear) {
        const Node& node = m_nodes[s.stack.back()];
        const std::uint32_t at = s.stack.back();
        s.stack.pop_back();
        const Vec3 centre = 0.5 * (node.lo + node.hi), half = 0.5 * (node.hi - node.lo);
        bool outside = false;
        for (std::size_t k = 0; k < planes && !outside; ++k)
            outside = m[k].dot(centre) - d[k] + m[k].cwiseAbs().dot(half) <= tolerance;
        if (outside) continue;
        if (node.count == 0) {
            s.stack.push_back(node.right);
            s.stack.push_back(at + 1);
            continue;
        }
        for (std::uint32_t item = node.first; item < node.first + node.count && clear; ++item) {
            const PatchId b = m_items[item];
            if (b == e || b == r) continue;
            const PatchShape& shape = m_geometry->shapes[b];
            const Vec3* corners = m_geometry->polygon(b);
            bool away = false;  // all corners outside one plane of the cone
            for (std::size_t k = 0; k < planes && !away; ++k) {
                away = true;
                for (std::uint32_t c = 0; c < shape.count && away; ++c) away = m[k].dot(corners[c]) - d[k] <= tolerance;
            }
            if (away) continue;
            // The blocker's part inside the cone, projected from x onto the receiver's plane.
            s.cut.assign(corners, corners + shape.count);
            for (std::size_t k = 0; k < planes && s.cut.size() >= 3; ++k) {
                clipToPlane(s.cut, m[k], d[k], s.cutNext);
                s.cut.swap(s.cutNext);
            }
            if (s.cut.size() < 3) continue;
            s.shadow.clear();
            double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
            for (const Vec3& y : s.cut) {
                const double gap = std::max(height - (normal.dot(y) - offset), 1e-12 * height);
                const Vec3 image = x + (y - x) * (height / gap) - origin;
                const double q[2] = {image.dot(u), image.dot(v)};
                for (int a = 0; a < 2; ++a) {
                    lo[a] = std::min(lo[a], q[a]);
                    hi[a] = std::max(hi[a], q[a]);
                }
                s.shadow.insert(s.shadow.end(), q, q + 2);
            }
            const std::size_t sides = s.shadow.size() / 2;
            const double shadowArea = doubleArea(s.shadow.data(), sides);
            if (std::abs(shadowArea) <= smallest) continue;
            if (shadowArea < 0.0) reverse2D(s.shadow.data(), sides);
            ++s.shadows;
            // Cut the shadow out of every clear piece it overlaps: each piece's parts outside the
            // shadow's edges, one edge after the other, stay clear.
            s.nextPieces.clear();
            for (std::size_t at2 = 0; at2 < s.pieces.size();) {
                const std::size_t k = std::size_t(s.pieces[at2]);
                const double* piece = &s.pieces[at2 + 1];
                double plo[2] = {1e300, 1e300}, phi[2] = {-1e300, -1e300};
                for (std::size_t c = 0; c < k; ++c)
                    for (int a = 0; a < 2; ++a) {
                        plo[a] = std::min(plo[a], piece[2 * c + a]);
                        phi[a] = std::max(phi[a], piece[2 * c + a]);
                    }
                if (phi[0] <= lo[0] || plo[0] >= hi[0] || phi[1] <= lo[1] || plo[1] >= hi[1]) {
                    s.nextPieces.insert(s.nextPieces.end(), s.pieces.begin() + std::ptrdiff_t(at2),
                                        s.pieces.begin() + std::ptrdiff_t(at2 + 1 + 2 * k));
                } else {
                    s.inside.assign(piece, piece + 2 * k);
                    for (std::size_t c = 0; c < sides && s.inside.size() >= 6; ++c) {
                        splitByLine(s.inside.data(), s.inside.size() / 2, &s.shadow[2 * c],
                                    &s.shadow[2 * ((c + 1) % sides)], s.rest, s.outside);
                        s.inside.swap(s.rest);
                        if (s.outside.size() >= 6 && std::abs(doubleArea(s.outside.data(), s.outside.size() / 2)) > smallest) {
                            s.nextPieces.push_back(double(s.outside.size() / 2));
                            s.nextPieces.insert(s.nextPieces.end(), s.outside.begin(), s.outside.end());
                        }
                    }
                }
                at2 += 1 + 2 * k;
            }
            s.pieces.swap(s.nextPieces);
            clear = !s.pieces.empty();
        }
    }
    if (s.shadows == 0) return whole;
    double factor = 0.0;
    for (std::size_t at = 0; at < s.pieces.size();) {
        const std::size_t k = std::size_t(s.pieces[at]);
        s.lifted.clear();
        for (std::size_t c = 0; c < k; ++c)
            s.lifted.push_back(origin + s.pieces[at + 1 + 2 * c] * u + s.pieces[at + 2 + 2 * c] * v);
        factor += pointToPolygonFactor(x, n, s.lifted.data(), k);
        at += 1 + 2 * k;
    }
    return factor;
}

}  // namespace hemirad
