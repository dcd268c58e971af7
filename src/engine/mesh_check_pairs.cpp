// Pairwise mesh checks: vertex-on-edge contacts, coinciding patches (convex clipping in the plane)
// and collinear open edges, over the pairs a loose grid finds.
#include "engine/mesh_check_pairs.hpp"

#include "engine/box_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hemirad {
namespace {

using Vec2 = Eigen::Vector2d;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double signedArea(const std::vector<Vec2>& p) {
    double twice = 0.0;
    for (std::size_t k = 0; k < p.size(); ++k) twice += cross2(p[k], p[(k + 1) % p.size()]);
    return 0.5 * twice;
}

/// Area of subject ∩ clipper, clipper convex and counter-clockwise (Sutherland & Hodgman 1974);
/// `subject` and `kept` are work space.
double clippedArea(const std::vector<Vec2>& clipper, std::vector<Vec2>& subject, std::vector<Vec2>& kept) {
    for (std::size_t e = 0; e < clipper.size() && !subject.empty(); ++e) {
        const Vec2 a = clipper[e], d = clipper[(e + 1) % clipper.size()] - a;
        kept.clear();
        for (std::size_t k = 0; k < subject.size(); ++k) {
            const Vec2& p = subject[k];
            const Vec2& q = subject[(k + 1) % subject.size()];
            const double sp = cross2(d, p - a), sq = cross2(d, q - a);
            if (sp >= 0.0) kept.push_back(p);
            if ((sp >= 0.0) != (sq >= 0.0)) kept.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        subject.swap(kept);
    }
    return subject.size() < 3 ? 0.0 : std::abs(signedArea(subject));
}

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
    return std::uint64_t(std::min(a, b)) << 32 | std::max(a, b);
}

class PairTester {
public:
    PairTester(const Scene& scene, const WeldedMesh& mesh, PairFindings& out)
        : m_scene(scene), m_mesh(mesh), m_out(out), m_tol(mesh.tolerance) {
        m_sorted.assign(mesh.corner.begin(), mesh.corner.end());
        m_perimeter.assign(scene.size(), 0.0);
        for (PatchId i = 0; i < scene.size(); ++i) {
            const Patch& p = scene.patches[i];
            std::sort(m_sorted.begin() + p.firstCorner, m_sorted.begin() + p.firstCorner + p.cornerCount);
            for (std::uint32_t k = 0; k < p.cornerCount; ++k)
                m_perimeter[i] += (at(p, (k + 1) % p.cornerCount) - at(p, k)).norm();
        }
    }

    void test(PatchId i, PatchId j) {
        coincide(i, j);
        vertexOnEdges(i, j);
        vertexOnEdges(j, i);
        covers(i, j);
        covers(j, i);
    }

private:
    std::uint32_t id(const Patch& p, std::uint32_t k) const { return m_mesh.corner[p.firstCorner + k]; }
    const Vec3& at(const Patch& p, std::uint32_t k) const { return m_mesh.position[id(p, k)]; }

    bool withinPlane(const Patch& p, const Patch& q) const {
        for (std::uint32_t k = 0; k < q.cornerCount; ++k)
            if (std::abs((at(q, k) - p.centroid).dot(p.normal)) > m_tol) return false;
        return true;
    }

    void project(const Patch& p, const Vec3& origin, const Vec3& t, const Vec3& b, std::vector<Vec2>& points) const {
        points.clear();
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const Vec3 d = at(p, k) - origin;
            points.emplace_back(d.dot(t), d.dot(b));
        }
        if (signedArea(points) < 0.0) std::reverse(points.begin(), points.end());
    }

    void coincide(PatchId i, PatchId j) {
        const Patch& p = m_scene.patches[i];
        const Patch& q = m_scene.patches[j];
        const bool same = p.cornerCount == q.cornerCount &&
                          std::equal(m_sorted.begin() + p.firstCorner, m_sorted.begin() + p.firstCorner + p.cornerCount,
                                     m_sorted.begin() + q.firstCorner);
        const double cosine = p.normal.dot(q.normal);
        if (!same && (std::abs(cosine) < 0.99 || !withinPlane(p, q) || !withinPlane(q, p))) return;
        Vec3 t, b;
        orthonormalBasis(p.normal, t, b);
        project(p, p.centroid, t, b, m_clipper);
        project(q, p.centroid, t, b, m_subject);
        const double overlap = clippedArea(m_clipper, m_subject, m_kept);
        // Neighbours sharing an edge overlap by rounding only: at most a band of the tolerance's width.
        if (!same && !(overlap > m_tol * std::min(m_perimeter[i], m_perimeter[j]))) return;
        m_out.coinciding.push_back({i, j, same, cosine < 0.0, overlap});
    }

    /// Corners of patch `j` strictly inside an edge of patch `i`.
    void vertexOnEdges(PatchId i, PatchId j) {
        const Patch& p = m_scene.patches[i];
        const Patch& q = m_scene.patches[j];
        const auto own = m_sorted.begin() + p.firstCorner, ownEnd = own + p.cornerCount;
        for (std::uint32_t m = 0; m < q.cornerCount; ++m) {
            const std::uint32_t v = id(q, m);
            if (std::binary_search(own, ownEnd, v)) continue;
            const Vec3& x = m_mesh.position[v];
            for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
                const std::uint32_t a = id(p, k), b = id(p, (k + 1) % p.cornerCount);
                if (a == b) continue;
                const Vec3& A = m_mesh.position[a];
                const Vec3 d = m_mesh.position[b] - A;
                const double length = d.norm();
                const double s = (x - A).dot(d) / length;  // distance along the edge
                if (s <= m_tol || s >= length - m_tol) continue;
                if ((x - A - d * (s / length)).norm() > m_tol) continue;
                m_out.vertexOnEdge.push_back({edgeKey(a, b), v, i, j, k});
            }
        }
    }

    /// Open edges of patch `j` collinear with an open edge of patch `i`: the part of i's edge they cover.
    void covers(PatchId i, PatchId j) {
        const Patch& p = m_scene.patches[i];
        const Patch& q = m_scene.patches[j];
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            if (!m_mesh.openEdge[p.firstCorner + k]) continue;
            const Vec3& A = at(p, k);
            const Vec3 d = at(p, (k + 1) % p.cornerCount) - A;
            const double length = d.norm();
            if (!(length > m_tol)) continue;
            auto along = [&](const Vec3& x, double& s) {
                s = (x - A).dot(d) / length;
                return (x - A - d * (s / length)).norm() <= m_tol;
            };
            for (std::uint32_t m = 0; m < q.cornerCount; ++m) {
                if (!m_mesh.openEdge[q.firstCorner + m]) continue;
                double s0, s1;
                if (!along(at(q, m), s0) || !along(at(q, (m + 1) % q.cornerCount), s1)) continue;
                const double lo = std::max(0.0, std::min(s0, s1)), hi = std::min(length, std::max(s0, s1));
                if (hi - lo > m_tol) m_out.covers.push_back({p.firstCorner + k, lo / length, hi / length});
            }
        }
    }

    const Scene& m_scene;
    const WeldedMesh& m_mesh;
    PairFindings& m_out;
    double m_tol;
    std::vector<std::uint32_t> m_sorted;  // per patch, its welded corners in increasing order
    std::vector<double> m_perimeter;
    std::vector<Vec2> m_clipper, m_subject, m_kept;  // clipping work space
};

}  // namespace

PairFindings findPairIssues(const Scene& scene, const WeldedMesh& mesh) {
    std::vector<Box> boxes(scene.size());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (PatchId i = 0; i < scene.size(); ++i) {
        Box& box = boxes[i];
        if (!mesh.usable[i]) {
            box.lo = box.hi = Vec3::Constant(nan);  // left out of the grid
            continue;
        }
        const Patch& p = scene.patches[i];
        box.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
        box.hi = -box.lo;
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const Vec3& x = mesh.position[mesh.corner[p.firstCorner + k]];
            box.lo = box.lo.cwiseMin(x);
            box.hi = box.hi.cwiseMax(x);
        }
        box.lo.array() -= mesh.tolerance;
        box.hi.array() += mesh.tolerance;
    }
    PairFindings out;
    PairTester tester(scene, mesh, out);
    forEachOverlappingPair(boxes, [&](std::uint32_t i, std::uint32_t j) { tester.test(i, j); });
    return out;
}

}  // namespace hemirad
