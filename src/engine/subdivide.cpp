// Regular-grid subdivision of patches with parent bookkeeping for the hemicube's parent-polygon drawing.
#include "engine/subdivide.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <utility>

namespace hemirad {
namespace {

/// Grid steps along an edge of this length so that none exceeds maxEdge.
std::uint32_t gridSteps(double length, double maxEdge) {
    const double n = std::ceil(length / maxEdge * (1.0 - 1e-12));
    if (n > 1e6) throw Error("subdivide: an edge of length " + std::to_string(length) + " would need " +
                             std::to_string(n) + " steps at --max-edge " + std::to_string(maxEdge));
    return std::max<std::uint32_t>(1, static_cast<std::uint32_t>(n));
}

class SubdivisionBuilder {
public:
    SubdivisionBuilder(const Scene& in, Scene& out) : m_in(in), m_out(out) {}

    /// Point at parameter t along the input edge (a, b), evaluated from the lower vertex index so
    /// that both patches sharing the edge produce bit-identical points.
    std::uint32_t edgePoint(std::uint32_t a, std::uint32_t b, std::uint32_t step, std::uint32_t steps) {
        if (a > b) {
            std::swap(a, b);
            step = steps - step;
        }
        if (step == 0) return inputVertex(a);
        if (step == steps) return inputVertex(b);
        const double t = static_cast<double>(step) / steps;
        return vertex(m_in.vertices[a] + t * (m_in.vertices[b] - m_in.vertices[a]));
    }

    std::uint32_t inputVertex(std::uint32_t v) {
        auto [it, added] = m_inputToOutput.emplace(v, 0u);
        if (added) it->second = vertex(m_in.vertices[v]);
        return it->second;
    }

    std::uint32_t vertex(const Vec3& p) {
        const std::array<double, 3> key{p.x(), p.y(), p.z()};
        auto [it, added] = m_positions.emplace(key, static_cast<std::uint32_t>(m_out.vertices.size()));
        if (added) m_out.vertices.push_back(p);
        return it->second;
    }

    void quad(const Patch& src, PatchId srcId, const std::uint32_t c[4], double maxEdge) {
        const Vec3 p[4] = {m_in.vertices[c[0]], m_in.vertices[c[1]], m_in.vertices[c[2]], m_in.vertices[c[3]]};
        const std::uint32_t nu = gridSteps(std::max((p[1] - p[0]).norm(), (p[2] - p[3]).norm()), maxEdge);
        const std::uint32_t nv = gridSteps(std::max((p[3] - p[0]).norm(), (p[2] - p[1]).norm()), maxEdge);
        std::vector<std::uint32_t> grid((nu + 1) * (nv + 1));
        for (std::uint32_t j = 0; j <= nv; ++j)
            for (std::uint32_t i = 0; i <= nu; ++i) {
                std::uint32_t& g = grid[j * (nu + 1) + i];
                if (j == 0) g = edgePoint(c[0], c[1], i, nu);
                else if (j == nv) g = edgePoint(c[3], c[2], i, nu);
                else if (i == 0) g = edgePoint(c[0], c[3], j, nv);
                else if (i == nu) g = edgePoint(c[1], c[2], j, nv);
                else {
                    const double u = static_cast<double>(i) / nu, v = static_cast<double>(j) / nv;
                    g = vertex((1 - u) * (1 - v) * p[0] + u * (1 - v) * p[1] + u * v * p[2] + (1 - u) * v * p[3]);
                }
            }
        const std::uint32_t parent = beginParent(src, srcId, c, 4, GridKind::Quad, nu, nv);
        for (std::uint32_t j = 0; j < nv; ++j)
            for (std::uint32_t i = 0; i < nu; ++i)
                emit(src, parent, i, j,
                     {grid[j * (nu + 1) + i], grid[j * (nu + 1) + i + 1], grid[(j + 1) * (nu + 1) + i + 1],
                      grid[(j + 1) * (nu + 1) + i]});
    }

    void triangle(const Patch& src, PatchId srcId, const std::uint32_t c[3], double maxEdge) {
        const Vec3 p[3] = {m_in.vertices[c[0]], m_in.vertices[c[1]], m_in.vertices[c[2]]};
        const std::uint32_t n = gridSteps(std::max({(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()}),
                                      maxEdge);
        // Barycentric grid: point (a, b) = p0 + a/n (p1 - p0) + b/n (p2 - p0), a + b <= n.
        auto index = [n](std::uint32_t a, std::uint32_t b) { return b * (n + 1) - b * (b - 1) / 2 + a; };
        std::vector<std::uint32_t> grid((n + 1) * (n + 2) / 2);
        for (std::uint32_t b = 0; b <= n; ++b)
            for (std::uint32_t a = 0; a + b <= n; ++a) {
                std::uint32_t& g = grid[index(a, b)];
                if (b == 0) g = edgePoint(c[0], c[1], a, n);
                else if (a == 0) g = edgePoint(c[0], c[2], b, n);
                else if (a + b == n) g = edgePoint(c[1], c[2], b, n);
                else g = vertex(p[0] + (double(a) / n) * (p[1] - p[0]) + (double(b) / n) * (p[2] - p[0]));
            }
        const std::uint32_t parent = beginParent(src, srcId, c, 3, GridKind::Triangle, n, n);
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i + j < n; ++i) {
                emit(src, parent, 2 * i, j, {grid[index(i, j)], grid[index(i + 1, j)], grid[index(i, j + 1)]});
                if (i + j + 1 < n)
                    emit(src, parent, 2 * i + 1, j,
                         {grid[index(i + 1, j)], grid[index(i + 1, j + 1)], grid[index(i, j + 1)]});
            }
    }

    void single(const Patch& src, PatchId srcId) {
        std::vector<std::uint32_t> ids(src.cornerCount);
        for (std::uint32_t k = 0; k < src.cornerCount; ++k) ids[k] = inputVertex(m_in.corners[src.firstCorner + k]);
        const std::uint32_t parent = beginParent(src, srcId, &m_in.corners[src.firstCorner], src.cornerCount,
                                                 GridKind::Single, 1, 1);
        emit(src, parent, 0, 0, ids);
    }

private:
    std::uint32_t beginParent(const Patch&, PatchId srcId, const std::uint32_t* c, std::uint32_t count,
                              GridKind kind, std::uint32_t nu, std::uint32_t nv) {
        Parent parent;
        parent.firstCorner = static_cast<std::uint32_t>(m_out.parentCorners.size());
        parent.cornerCount = count;
        for (std::uint32_t k = 0; k < count; ++k) m_out.parentCorners.push_back(inputVertex(c[k]));
        parent.kind = kind;
        parent.nu = nu;
        parent.nv = nv;
        parent.firstPatch = static_cast<PatchId>(m_out.patches.size());
        parent.patchCount = 0;
        parent.sourcePatch = srcId;
        m_out.parents.push_back(parent);
        return static_cast<std::uint32_t>(m_out.parents.size() - 1);
    }

    void emit(const Patch& src, std::uint32_t parent, std::uint32_t i, std::uint32_t j,
              const std::vector<std::uint32_t>& ids) {
        const PatchId id = m_out.addPatch(ids, src.material, src.object, src.sourceLine);
        // addPatch made the patch its own parent; this patch belongs to the grid parent instead.
        m_out.parents.pop_back();
        m_out.parentCorners.resize(m_out.parentCorners.size() - ids.size());
        Patch& p = m_out.patches[id];
        p.emission = src.emission;
        p.rho = src.rho;
        p.specular = src.specular;
        p.parent = parent;
        p.cellI = i;
        p.cellJ = j;
        ++m_out.parents[parent].patchCount;
    }

    const Scene& m_in;
    Scene& m_out;
    std::map<std::uint32_t, std::uint32_t> m_inputToOutput;
    std::map<std::array<double, 3>, std::uint32_t> m_positions;
};

}  // namespace

namespace {

void checkEdge(double maxEdge) {
    if (!(maxEdge > 0.0) || !std::isfinite(maxEdge))
        throw Error("subdivide: maximum edge length must be a positive number, got " + std::to_string(maxEdge));
}

/// The longest edge of a patch.
double longestEdge(const Scene& in, const Patch& p) {
    double longest = 0.0;
    for (std::uint32_t k = 0; k < p.cornerCount; ++k)
        longest = std::max(longest, (in.corner(p, (k + 1) % p.cornerCount) - in.corner(p, k)).norm());
    return longest;
}

/// Checks one edge length per object (each 0 or positive).
void checkEdges(const Scene& in, const std::vector<double>& maxEdgeByObject) {
    if (maxEdgeByObject.size() != std::max<std::size_t>(in.objects.size(), 1))
        throw Error("subdivide: " + std::to_string(maxEdgeByObject.size()) + " edge lengths for " +
                    std::to_string(in.objects.size()) + " objects");
    for (double edge : maxEdgeByObject)
        if (edge != 0.0) checkEdge(edge);
}

/// The edge length that applies to patch p (0: kept whole).
double edgeFor(const Patch& p, const std::vector<double>& maxEdgeByObject) {
    return maxEdgeByObject[std::min<std::size_t>(p.object, maxEdgeByObject.size() - 1)];
}

}  // namespace

Scene subdivide(const Scene& in, double maxEdge) {
    checkEdge(maxEdge);
    return subdivide(in, std::vector<double>(std::max<std::size_t>(in.objects.size(), 1), maxEdge));
}

Scene subdivide(const Scene& in, const std::vector<double>& maxEdgeByObject) {
    checkEdges(in, maxEdgeByObject);
    Scene out;
    out.path = in.path;
    out.materials = in.materials;
    out.objects = in.objects;
    out.camera = in.camera;
    out.unit = in.unit;
    out.up = in.up;
    SubdivisionBuilder b(in, out);
    for (PatchId id = 0; id < in.size(); ++id) {
        const Patch& p = in.patches[id];
        const double maxEdge = edgeFor(p, maxEdgeByObject);
        const std::uint32_t* c = &in.corners[p.firstCorner];
        if (maxEdge == 0.0 || longestEdge(in, p) <= maxEdge) b.single(p, id);
        else if (p.cornerCount == 4) b.quad(p, id, c, maxEdge);
        else if (p.cornerCount == 3) b.triangle(p, id, c, maxEdge);
        else
            for (std::uint32_t k = 1; k + 1 < p.cornerCount; ++k) {
                const std::uint32_t tri[3] = {c[0], c[k], c[k + 1]};
                b.triangle(p, id, tri, maxEdge);
            }
    }
    return out;
}

std::size_t subdividedSize(const Scene& in, const std::vector<double>& maxEdgeByObject) {
    checkEdges(in, maxEdgeByObject);
    std::size_t total = 0;
    for (const Patch& p : in.patches) {
        const double maxEdge = edgeFor(p, maxEdgeByObject);
        if (maxEdge == 0.0 || longestEdge(in, p) <= maxEdge) {
            ++total;
            continue;
        }
        const auto v = [&](std::uint32_t k) { return in.corner(p, k); };
        if (p.cornerCount == 4) {
            total += std::size_t(gridSteps(std::max((v(1) - v(0)).norm(), (v(2) - v(3)).norm()), maxEdge)) *
                     gridSteps(std::max((v(3) - v(0)).norm(), (v(2) - v(1)).norm()), maxEdge);
            continue;
        }
        for (std::uint32_t k = 1; k + 1 < p.cornerCount; ++k) {
            const std::size_t n = gridSteps(
                std::max({(v(k) - v(0)).norm(), (v(k + 1) - v(k)).norm(), (v(0) - v(k + 1)).norm()}), maxEdge);
            total += n * n;
        }
    }
    return total;
}

namespace {

/// The pieces of one source polygon in a mesh, binned on the polygon's plane so that finding the
/// piece under a point costs a few tests, not one per piece (a wall meshed into 10^4 patches).
class PieceFinder {
public:
    PieceFinder(const Scene& scene, std::vector<PatchId> pieces) : m_scene(scene), m_pieces(std::move(pieces)) {
        const Patch& first = scene.patches[m_pieces.front()];
        m_origin = first.centroid;
        m_u = first.normal.unitOrthogonal();
        m_v = first.normal.cross(m_u);
        double lo[2] = {kHuge, kHuge}, hi[2] = {-kHuge, -kHuge};
        std::vector<std::array<double, 4>> boxes;
        for (PatchId i : m_pieces) {
            const Patch& p = scene.patches[i];
            std::array<double, 4> box{kHuge, kHuge, -kHuge, -kHuge};
            for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
                const auto [x, y] = project(scene.corner(p, k));
                box = {std::min(box[0], x), std::min(box[1], y), std::max(box[2], x), std::max(box[3], y)};
            }
            lo[0] = std::min(lo[0], box[0]), lo[1] = std::min(lo[1], box[1]);
            hi[0] = std::max(hi[0], box[2]), hi[1] = std::max(hi[1], box[3]);
            boxes.push_back(box);
        }
        m_bins = std::max<std::uint32_t>(1, std::uint32_t(std::sqrt(double(m_pieces.size()))));
        for (int d = 0; d < 2; ++d) {
            m_lo[d] = lo[d];
            m_scale[d] = hi[d] > lo[d] ? m_bins / (hi[d] - lo[d]) : 0.0;
        }
        m_start.assign(std::size_t(m_bins) * m_bins + 1, 0);
        std::vector<std::pair<std::uint32_t, PatchId>> entries;  // (bin, piece)
        for (std::size_t n = 0; n < m_pieces.size(); ++n) {
            const std::uint32_t x0 = bin(0, boxes[n][0]), y0 = bin(1, boxes[n][1]), x1 = bin(0, boxes[n][2]), y1 = bin(1, boxes[n][3]);
            for (std::uint32_t y = y0; y <= y1; ++y)
                for (std::uint32_t x = x0; x <= x1; ++x) entries.emplace_back(y * m_bins + x, m_pieces[n]);
        }
        std::sort(entries.begin(), entries.end());
        for (const auto& e : entries) ++m_start[e.first + 1];
        for (std::size_t k = 1; k < m_start.size(); ++k) m_start[k] += m_start[k - 1];
        for (const auto& e : entries) m_members.push_back(e.second);
    }

    /// The piece whose polygon holds `point` (on the plane); else, at a rounding edge case, the one
    /// with the nearest centroid.
    PatchId find(const Vec3& point) const {
        const auto [x, y] = project(point);
        const std::uint32_t b = bin(1, y) * m_bins + bin(0, x);
        if (const auto hit = nearest(point, &m_members[m_start[b]], &m_members[m_start[b + 1]])) return *hit;
        return *nearest(point, m_pieces.data(), m_pieces.data() + m_pieces.size());
    }

private:
    static constexpr double kHuge = std::numeric_limits<double>::infinity();

    std::pair<double, double> project(const Vec3& p) const { return {(p - m_origin).dot(m_u), (p - m_origin).dot(m_v)}; }
    std::uint32_t bin(int d, double t) const {
        const double k = std::floor((t - m_lo[d]) * m_scale[d]);
        return std::uint32_t(std::clamp(k, 0.0, double(m_bins - 1)));
    }
    /// The candidate holding the point (first found), else the nearest centroid; none without candidates.
    std::optional<PatchId> nearest(const Vec3& point, const PatchId* begin, const PatchId* end) const {
        std::optional<PatchId> best;
        double bestDistance = kHuge;
        for (const PatchId* it = begin; it != end; ++it) {
            const Patch& p = m_scene.patches[*it];
            bool inside = true;
            for (std::uint32_t k = 0; k < p.cornerCount && inside; ++k) {
                const Vec3 a = m_scene.corner(p, k), b = m_scene.corner(p, (k + 1) % p.cornerCount);
                inside = (b - a).cross(point - a).dot(p.normal) >= -1e-12 * (b - a).squaredNorm();
            }
            if (inside) return *it;
            const double distance = (p.centroid - point).squaredNorm();
            if (distance < bestDistance) {
                bestDistance = distance;
                best = *it;
            }
        }
        return best;
    }

    const Scene& m_scene;
    std::vector<PatchId> m_pieces;
    Vec3 m_origin, m_u, m_v;
    std::uint32_t m_bins = 1;
    double m_lo[2] = {0, 0}, m_scale[2] = {0, 0};
    std::vector<std::uint32_t> m_start;  ///< CSR over bins into m_members
    std::vector<PatchId> m_members;
};

}  // namespace

std::vector<PatchId> coveringPatches(const Scene& from, const Scene& to) {
    // The patches of `from` by the source patch they were cut from.
    std::map<PatchId, std::vector<PatchId>> bySource;
    for (PatchId i = 0; i < from.size(); ++i) bySource[from.parents[from.patches[i].parent].sourcePatch].push_back(i);
    std::map<PatchId, PieceFinder> finders;
    for (auto& [source, pieces] : bySource) finders.emplace(source, PieceFinder(from, std::move(pieces)));
    std::vector<PatchId> covering(to.size());
    for (PatchId j = 0; j < to.size(); ++j) {
        const Patch& q = to.patches[j];
        const auto it = finders.find(to.parents[q.parent].sourcePatch);
        if (it == finders.end())
            throw Error("subdivide: patch " + std::to_string(j) + " comes from a source patch the other mesh lacks");
        covering[j] = it->second.find(q.centroid);
    }
    return covering;
}

}  // namespace hemirad
