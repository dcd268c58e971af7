// Shadow polygons: blockers clipped to the cone from a point through a receiver, projected onto
// the receiver's plane and cut out of it; Lambert's factor of what stays clear.
#include "preprocess/hemisphere/shadow_polygons.hpp"

#include "engine/error.hpp"

#include "preprocess/hemisphere/convex_pieces.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace hemirad {

namespace {

/// A visible part below this fraction of the whole factor is the rounding of the cuts (pieces of
/// shadows that meet edge to edge), not a view: 0.
constexpr double kDust = 1e-9;

/// The clear pieces' packed values (a triangle piece is 7) beyond which the cuts give up with an
/// error: a bound on memory (80 MB a thread) where shadows along a receiver's edges would split it
/// without end.
constexpr std::size_t kMaxClearValues = 10000000;

/// The part of polygon `poly` with m . y - d >= 0 into `out` (Sutherland-Hodgman); `side` is
/// scratch. Returns false, leaving `out` alone, when every corner is on that side: the polygon is
/// its own part (most planes of a cone cut nothing of a blocker that reaches into it).
bool clipToPlane(const std::vector<Vec3>& poly, const Vec3& m, double d, std::vector<Vec3>& out,
                 std::vector<double>& side) {
    const std::size_t k = poly.size();
    side.resize(k);
    bool cuts = false;
    for (std::size_t i = 0; i < k; ++i) {
        side[i] = m.dot(poly[i]) - d;
        cuts |= side[i] < 0.0;
    }
    if (!cuts) return false;
    out.resize(2 * k);  // k corners and k crossings at most
    std::size_t at = 0;
    for (std::size_t i = 0; i < k; ++i) {
        const std::size_t j = i + 1 == k ? 0 : i + 1;
        const double sp = side[i], sq = side[j];
        if (sp >= 0.0) out[at++] = poly[i];
        if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) out[at++] = poly[i] + (poly[j] - poly[i]) * (sp / (sp - sq));
    }
    out.resize(at);
    return true;
}

}  // namespace

void ShadowPolygons::addBlocker(const Vec3* corners, std::size_t count, PatchId owner, PatchId face, std::uint32_t solid) {
    m_corners.insert(m_corners.end(), corners, corners + count);
    m_first.push_back(std::uint32_t(m_corners.size()));
    m_owner.push_back(owner);
    m_centre.push_back(vertexMean(corners, count));
    const PatchShape& shape = m_geometry->shapes[face];
    m_plane.push_back({shape.normal, shape.normal.dot(shape.centroid)});
    m_solid.push_back(solid);
}

void ShadowPolygons::build(const PatchGeometry& geometry, const std::vector<std::uint8_t>& blocks, bool merge,
                           bool solids) {
    m_geometry = &geometry;
    m_corners.clear();
    m_first.assign(1, 0);
    m_owner.clear();
    m_centre.clear();
    m_items.clear();
    m_nodes.clear();
    m_plane.clear();
    m_solid.clear();
    m_solids = ConvexSolids();
    if (merge && solids) m_solids.build(geometry, blocks);
    // Components of blockers that share a corner position and a plane (union-find).
    const std::size_t n = blocks.size();
    std::vector<PatchId> root(n);
    for (PatchId j = 0; j < n; ++j) root[j] = j;
    auto find = [&](PatchId j) {
        while (root[j] != j) j = root[j] = root[root[j]];
        return j;
    };
    auto coplanar = [&](PatchId a, PatchId b) {
        const PatchShape& p = geometry.shapes[a];
        const PatchShape& q = geometry.shapes[b];
        return p.normal.dot(q.normal) > 1.0 - 1e-12 &&
               std::abs(p.normal.dot(q.centroid - p.centroid)) <= 1e-9 * (p.radius + q.radius);
    };
    for (PatchId j = 0; j < n; ++j) {
        if (!blocks[j]) continue;
        for (std::uint32_t e = geometry.neighbourStart[j]; e < geometry.neighbourStart[j + 1]; ++e) {
            const PatchId k = geometry.neighbours[e];
            if (merge && blocks[k] && coplanar(j, k)) root[find(j)] = find(k);
        }
    }
    std::vector<std::vector<PatchId>> groups(n);
    for (PatchId j = 0; j < n; ++j)
        if (blocks[j]) groups[find(j)].push_back(j);
    // A group whose convex hull has the area of its tiles is that hull; else its tiles stay.
    std::vector<std::array<double, 2>> points, hull;
    std::vector<Vec3> lifted;
    for (const std::vector<PatchId>& group : groups) {
        if (group.empty()) continue;
        if (group.size() > 1) {
            const Vec3& normal = geometry.shapes[group[0]].normal;
            const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
            const Vec3 u = normal.cross(helper).normalized(), v = normal.cross(u);
            const Vec3 origin = geometry.shapes[group[0]].centroid;
            points.clear();
            double tiles = 0.0;
            for (const PatchId j : group) {
                const PatchShape& t = geometry.shapes[j];
                const std::size_t before = points.size();
                for (std::uint32_t c = 0; c < t.count; ++c) {
                    const Vec3 d = geometry.corners[t.first + c] - origin;
                    points.push_back({d.dot(u), d.dot(v)});
                }
                for (std::size_t c = before; c < points.size(); ++c) {
                    const auto& a = points[c];
                    const auto& b = points[c + 1 < points.size() ? c + 1 : before];
                    tiles += a[0] * b[1] - b[0] * a[1];
                }
            }
            convexHull2D(points, hull);
            double area = 0.0;
            for (std::size_t c = 0; c < hull.size(); ++c) {
                const auto& a = hull[c];
                const auto& b = hull[(c + 1) % hull.size()];
                area += a[0] * b[1] - b[0] * a[1];
            }
            if (hull.size() >= 3 && std::abs(area - std::abs(tiles)) <= 1e-9 * std::abs(tiles)) {
                lifted.clear();
                for (const auto& h : hull) lifted.push_back(origin + h[0] * u + h[1] * v);
                // A face of a solid only if every tile is one of its faces (a coplanar neighbour
                // touching it at a corner joins the union too).
                std::uint32_t solid = m_solids.solidOf(group[0]);
                for (const PatchId j : group)
                    if (m_solids.solidOf(j) != solid) solid = ConvexSolids::kNone;
                addBlocker(lifted.data(), lifted.size(), kMerged, group[0], solid);
                continue;
            }
        }
        for (const PatchId j : group) addBlocker(geometry.polygon(j), geometry.shapes[j].count, j, j, m_solids.solidOf(j));
    }
    m_solidBlockers.assign(m_solids.size(), 0);
    for (const std::uint32_t solid : m_solid)
        if (solid != ConvexSolids::kNone) ++m_solidBlockers[solid];
    if (m_owner.empty()) return;
    m_items.resize(m_owner.size());
    for (std::uint32_t b = 0; b < m_items.size(); ++b) m_items[b] = b;
    m_nodes.reserve(2 * m_items.size());
    buildNode(0, std::uint32_t(m_items.size()));
}

std::uint32_t ShadowPolygons::buildNode(std::uint32_t first, std::uint32_t count) {
    const std::uint32_t index = std::uint32_t(m_nodes.size());
    m_nodes.emplace_back();
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    Vec3 clo = lo, chi = hi;
    for (std::uint32_t k = first; k < first + count; ++k) {
        const std::uint32_t b = m_items[k];
        for (std::uint32_t c = m_first[b]; c < m_first[b + 1]; ++c) {
            lo = lo.cwiseMin(m_corners[c]);
            hi = hi.cwiseMax(m_corners[c]);
        }
        clo = clo.cwiseMin(m_centre[b]);
        chi = chi.cwiseMax(m_centre[b]);
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
                     [&](std::uint32_t a, std::uint32_t b) { return m_centre[a][axis] < m_centre[b][axis]; });
    buildNode(first, half);  // at index + 1
    const std::uint32_t right = buildNode(first + half, count - half);
    m_nodes[index].right = right;
    return index;
}

bool ShadowPolygons::outsideSomePlane(std::uint32_t b, const Vec3* m, const double* d, std::size_t planes,
                                      double tolerance) const {
    const Vec3* corners = &m_corners[m_first[b]];
    const std::uint32_t cornerCount = m_first[b + 1] - m_first[b];
    for (std::size_t k = 0; k < planes; ++k) {
        bool away = true;  // all corners outside plane k
        for (std::uint32_t c = 0; c < cornerCount && away; ++c) away = m[k].dot(corners[c]) - d[k] <= tolerance;
        if (away) return true;
    }
    return false;
}

template <class Visit>
void ShadowPolygons::traverse(const Vec3* m, const double* d, std::size_t planes, double tolerance, PatchId e, PatchId r,
                              Scratch& s, Visit visit, const Vec3* nearFirst, const Vec3* box) const {
    s.stack.assign(1, 0);
    while (!s.stack.empty()) {
        const std::uint32_t at = s.stack.back();
        const Node& node = m_nodes[at];
        s.stack.pop_back();
        if (box && ((node.hi.array() < box[0].array()).any() || (node.lo.array() > box[1].array()).any())) continue;
        const Vec3 centre = 0.5 * (node.lo + node.hi), half = 0.5 * (node.hi - node.lo);
        bool outside = false;
        for (std::size_t k = 0; k < planes && !outside; ++k)
            outside = m[k].dot(centre) - d[k] + m[k].cwiseAbs().dot(half) <= tolerance;
        if (outside) continue;
        if (node.count == 0) {
            std::uint32_t first = at + 1, second = node.right;
            if (nearFirst) {
                const Node& a = m_nodes[first];
                const Node& b = m_nodes[second];
                if (nearFirst->dot(b.lo + b.hi) < nearFirst->dot(a.lo + a.hi)) std::swap(first, second);
            }
            s.stack.push_back(second);
            s.stack.push_back(first);
            continue;
        }
        for (std::uint32_t item = node.first; item < node.first + node.count; ++item) {
            const std::uint32_t b = m_items[item];
            if (m_owner[b] == e || m_owner[b] == r) continue;
            if (!outsideSomePlane(b, m, d, planes, tolerance) && !visit(b)) return;
        }
    }
}

bool ShadowPolygons::reaches(const Vec3* m, const double* d, std::size_t planes, double tolerance, PatchId e, PatchId r,
                             Scratch& s) const {
    if (m_items.empty()) return false;
    bool found = false;
    traverse(m, d, planes, tolerance, e, r, s, [&found](std::uint32_t) {
        found = true;
        return false;
    });
    return found;
}

void ShadowPolygons::collect(const Vec3* m, const double* d, std::size_t planes, double tolerance, PatchId e, PatchId r,
                             std::vector<std::uint32_t>& blockers, Scratch& s) const {
    blockers.clear();
    if (m_items.empty()) return;
    traverse(m, d, planes, tolerance, e, r, s, [&blockers](std::uint32_t b) {
        blockers.push_back(b);
        return true;
    });
}

template <class Project>
void ShadowPolygons::castShadows(const Vec3* p, std::size_t count, const Vec3& normal, double base, std::size_t planes,
                                 double tolerance, PatchId e, PatchId r, Scratch& s, const std::vector<std::uint32_t>* within,
                                 Project project, const Vec3* nearFirst, const Vec3* box, bool given, const Vec3* eye,
                                 const Vec3* beam) const {
    s.shadows = 0;
    s.solidsSeen.clear();
    s.hullFits.clear();
    s.deferred.clear();
    const std::vector<Vec3>& m = s.planeNormals;
    const std::vector<double>& d = s.planeOffsets;
    // 2D coordinates in the receiver's plane (origin p[0]); the receiver itself, counter-clockwise,
    // becomes the first clear piece when the second shadow falls (most regions hold no blocker),
    // unless the clear pieces are `given`.
    planeAxes(normal, s.u, s.v);
    const Vec3 origin = p[0];
    const double offset = normal.dot(origin);
    double smallest = 0.0;  // pieces below this area are dropped; 0 until the receiver is set up
    const auto toPlane = [&](const Vec3& y) { return std::array<double, 2>{(y - origin).dot(s.u), (y - origin).dot(s.v)}; };

    // The receiver in 2D (the clear part, or its outline with given pieces) and the smallest
    // piece's area; false for a receiver without area (no shadow counts).
    const auto setUp = [&] {
        if (smallest > 0.0) return true;
        std::vector<double>& whole = given ? s.clear.rest : s.clear.pieces;
        whole.assign(1, double(count));
        for (std::size_t k = 0; k < count; ++k) {
            const std::array<double, 2> xy = toPlane(p[k]);
            whole.push_back(xy[0]);
            whole.push_back(xy[1]);
        }
        const double area = doubleArea(&whole[1], count);
        if (area < 0.0) reverse2D(&whole[1], count);
        s.outline.assign(whole.begin() + 1, whole.end());
        smallest = 1e-12 * std::abs(area);
        if (smallest > 0.0) return true;
        s.shadows = 0;
        return false;
    };
    // The shadow in s.shadow (2D) and s.image (its corners on the receiver) cut out; false when
    // nothing is left clear (no need to look further).
    const auto cast = [&] {
        const std::size_t sides = s.shadow.size() / 2;
        const double shadowArea = doubleArea(s.shadow.data(), sides);
        if (std::abs(shadowArea) <= smallest) return true;
        if (shadowArea < 0.0) reverse2D(s.shadow.data(), sides);
        // One shadow (the usual case): kept whole. From the second on, the clear part is kept as
        // pieces, each shadow cut out of them.
        if (++s.shadows == 1 && !given) {
            s.first.swap(s.image);
            s.firstShadow.swap(s.shadow);
            // Cut to the receiver's region, a shadow as large as the receiver covers it all.
            return std::abs(shadowArea) < (1.0 - 1e-12) * std::abs(doubleArea(&s.clear.pieces[1], count));
        }
        if (s.shadows == 2 && !given) subtractConvex(s.firstShadow.data(), s.firstShadow.size() / 2, smallest, s.clear);
        subtractConvex(s.shadow.data(), sides, smallest, s.clear);
        if (s.clear.pieces.size() > kMaxClearValues)
            throw Error("shadow polygons: patch " + std::to_string(r) + "'s clear part splits into more than " +
                        std::to_string(kMaxClearValues / 7) + " pieces under " + std::to_string(s.shadows) + " shadows");
        return !s.clear.pieces.empty();
    };
    // Blocker b's part inside the region into s.cut (fewer than 3 corners: none).
    const auto cutToRegion = [&](std::uint32_t b) {
        s.cut.assign(&m_corners[m_first[b]], &m_corners[m_first[b + 1]]);
        for (std::size_t k = 0; k < planes && s.cut.size() >= 3; ++k)
            if (clipToPlane(s.cut, m[k], d[k], s.cutNext, s.sides)) s.cut.swap(s.cutNext);
    };
    // Blocker b's part inside the region, projected onto the receiver's plane.
    const auto castFace = [&](std::uint32_t b) {
        cutToRegion(b);
        if (s.cut.size() < 3) return true;
        const std::size_t cutCorners = s.cut.size();
        s.image.resize(cutCorners);
        s.shadow.resize(2 * cutCorners);
        for (std::size_t c = 0; c < cutCorners; ++c) {
            s.image[c] = project(s.cut[c]);
            const std::array<double, 2> xy = toPlane(s.image[c]);
            s.shadow[2 * c] = xy[0];
            s.shadow[2 * c + 1] = xy[1];
        }
        return setUp() && cast();
    };
    // Whether a convex solid's shadow may be cast as one (hullShadow): it has kHullBlockers blocker
    // polygons or more (a block's faces, merged, are 5 or 6: cast one by one, the first shadow that
    // covers the receiver ends the search, which a deferred hull cannot; a district's buildings
    // deferred took 1.45x the time), neither e nor r is a face of it, and every line into it from
    // the eye (along the beam) enters by a face it meets first (the eye outside it, and its open
    // side, if any, turned away). The cache holds 0 (no), 1 (yes) or 2 (yes, and the solid lies
    // nearer the receiver's plane than the eye by a hundredth of the eye's height at least: its
    // faces then need no cut but the receiver's plane, their projection's magnification bounded;
    // a parallel beam's where it meets the receiver at cos 0.1 or more).
    const double eyeHeight = eye ? normal.dot(*eye) - offset : 0.0;
    const auto hullFits = [&](std::uint32_t solid) -> int {
        for (const auto& [known, fits] : s.hullFits)
            if (known == solid) return fits;
        bool fits = (eye || beam) && m_solidBlockers[solid] >= kHullBlockers && m_solids.solidOf(e) != solid &&
                    m_solids.solidOf(r) != solid;
        if (fits) fits = eye ? entered(solid, *eye, s) : m_solids.beamEntersByFrontFace(solid, *beam);
        bool low = fits && !eye && normal.dot(*beam) >= 0.1;  // a grazing beam's projection stretches 1/cos
        if (fits && eye) {
            const Vec3 centre = 0.5 * (m_solids.lo(solid) + m_solids.hi(solid));
            const Vec3 half = 0.5 * (m_solids.hi(solid) - m_solids.lo(solid));
            const double top = std::min(normal.cwiseAbs().dot(half), m_solids.radius(solid));  // box or ball
            low = normal.dot(centre) - offset + top <= 0.99 * eyeHeight;
        }
        const int answer = fits ? (low ? 2 : 1) : 0;
        s.hullFits.push_back({solid, answer});
        return answer;
    };
    // A convex solid's faces within the region (s.deferred[first, last)) as one shadow: the convex
    // hull of their projected corners, cut to the region (or only to the receiver's plane, `base`,
    // where hullFits allows), within the receiver. Every line from the eye through a point of that
    // hull's part on the receiver meets the solid's part in the region, which it enters by a face
    // (hullFits): so the hull, cut to the receiver, is the union of the faces' shadows, one cut
    // instead of one for each face. A faceted sphere's dozens of facets in a cone split the clear
    // part into as many pieces, where its hull is one.
    const auto hullShadow = [&](std::size_t first, std::size_t last, bool low) {
        s.hullPoints.clear();
        for (std::size_t k = first; k < last; ++k) {
            const std::uint32_t b = s.deferred[k];
            if (low) {
                s.cut.assign(&m_corners[m_first[b]], &m_corners[m_first[b + 1]]);
                if (clipToPlane(s.cut, normal, base, s.cutNext, s.sides)) s.cut.swap(s.cutNext);
            } else {
                cutToRegion(b);
            }
            if (s.cut.size() < 3) continue;  // nothing of it in the region (its corners left unclipped)
            for (const Vec3& y : s.cut) s.hullPoints.push_back(toPlane(project(y)));
        }
        if (!convexHull2D(s.hullPoints, s.hull)) {  // a corner projected out of range: face by face
            for (std::size_t k = first; k < last; ++k)
                if (!castFace(s.deferred[k])) return false;
            return true;
        }
        if (s.hull.size() < 3) return true;
        if (!setUp()) return false;
        const std::size_t corners =
            clipToConvex(s.hull[0].data(), s.hull.size(), s.outline.data(), count, s.shadow, s.hullScratch, s.hullRest);
        if (corners < 3) return true;
        s.image.resize(corners);
        for (std::size_t c = 0; c < corners; ++c) s.image[c] = origin + s.shadow[2 * c] * s.u + s.shadow[2 * c + 1] * s.v;
        return cast();
    };

    const auto shade = [&](std::uint32_t b) {
        if (eye && turnedAway(b, *eye, s)) return true;
        if (beam && beamTurnedAway(b, *beam)) return true;
        if (m_solid[b] != ConvexSolids::kNone && hullFits(m_solid[b]) > 0) {
            s.deferred.push_back(b);  // cast with the solid's other faces, after the search
            return true;
        }
        return castFace(b);
    };
    bool going = true;
    if (!within) {
        traverse(m.data(), d.data(), planes, tolerance, e, r, s, [&](std::uint32_t b) { return going = shade(b); },
                 nearFirst, box);
    } else {
        for (const std::uint32_t b : *within)
            if (!outsideSomePlane(b, m.data(), d.data(), planes, tolerance) && !(going = shade(b))) break;
    }
    if (!going || s.deferred.empty()) return;
    // Each solid's faces together (in the order met: the same shadows whatever the search's order
    // within a solid); a solid with one face in the region casts it as any blocker.
    std::stable_sort(s.deferred.begin(), s.deferred.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return m_solid[a] < m_solid[b]; });
    for (std::size_t first = 0; first < s.deferred.size();) {
        std::size_t last = first + 1;
        while (last < s.deferred.size() && m_solid[s.deferred[last]] == m_solid[s.deferred[first]]) ++last;
        if (!(last == first + 1 ? castFace(s.deferred[first])
                                : hullShadow(first, last, hullFits(m_solid[s.deferred[first]]) == 2)))
            return;
        first = last;
    }
}

double ShadowPolygons::visibleFactor(const Vec3& x, const Vec3& n, const Vec3* p, std::size_t count, PatchId e,
                                     PatchId r, double whole, Scratch& s, const std::vector<std::uint32_t>* within) const {
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
    // As many planes as the polygon has edges (a fixed array dropped planes past 62 corners).
    std::vector<Vec3>& m = s.planeNormals;
    std::vector<double>& d = s.planeOffsets;
    m.clear();
    d.clear();
    for (std::size_t k = 0; k < count; ++k) {
        Vec3 side = (p[k] - x).cross(p[(k + 1) % count] - x);
        const double length = side.norm();
        if (!(length > 0.0)) continue;
        side /= length;
        if (side.dot(middle - x) < 0.0) side = -side;
        m.push_back(side);
        d.push_back(side.dot(x));
    }
    m.push_back(normal);
    d.push_back(offset + tolerance);
    m.push_back(n);  // and the emitter's: what lies in x's own plane casts no shadow either
    d.push_back(n.dot(x) + tolerance);

    // The cone lies in the box of x and the polygon; blockers nearer x first (their shadows are the
    // larger), so that a hidden receiver is usually covered by the first few.
    Vec3 box[2] = {x, x};
    for (std::size_t k = 0; k < count; ++k) {
        box[0] = box[0].cwiseMin(p[k]);
        box[1] = box[1].cwiseMax(p[k]);
    }
    box[0].array() -= tolerance;
    box[1].array() += tolerance;
    const Vec3 axis = middle - x;
    // Central projection from x onto the receiver's plane.
    castShadows(
        p, count, normal, offset + tolerance, m.size(), tolerance, e, r, s, within,
        [&](const Vec3& y) {
            const double gap = std::max(height - (normal.dot(y) - offset), 1e-12 * height);
            return Vec3(x + (y - x) * (height / gap));
        },
        &axis, box, false, &x);
    if (s.shadows == 0) return whole;
    if (s.shadows == 1) {
        const double visible = whole - pointToPolygonFactor(x, n, s.first.data(), s.first.size());
        return visible > kDust * whole ? visible : 0.0;
    }
    const Vec3 origin = p[0];
    double factor = 0.0;
    for (std::size_t at = 0; at < s.clear.pieces.size();) {
        const std::size_t k = std::size_t(s.clear.pieces[at]);
        s.lifted.clear();
        for (std::size_t c = 0; c < k; ++c)
            s.lifted.push_back(origin + s.clear.pieces[at + 1 + 2 * c] * s.u + s.clear.pieces[at + 2 + 2 * c] * s.v);
        factor += pointToPolygonFactor(x, n, s.lifted.data(), k);
        at += 1 + 2 * k;
    }
    return factor > kDust * whole ? factor : 0.0;
}

bool ShadowPolygons::turnedAway(std::uint32_t b, const Vec3& x, Scratch& s) const {
    const std::uint32_t solid = m_solid[b];
    return solid != ConvexSolids::kNone && m_plane[b].first.dot(x) - m_plane[b].second < 0.0 && entered(solid, x, s);
}

bool ShadowPolygons::entered(std::uint32_t solid, const Vec3& x, Scratch& s) const {
    for (const auto& [known, enters] : s.solidsSeen)
        if (known == solid) return enters;
    const bool enters = m_solids.entersByFrontFace(solid, x, s.solidHint);
    s.solidsSeen.push_back({solid, enters});
    return enters;
}

bool ShadowPolygons::beamTurnedAway(std::uint32_t b, const Vec3& toSource) const {
    const std::uint32_t solid = m_solid[b];
    return solid != ConvexSolids::kNone && m_plane[b].first.dot(toSource) < 0.0 && m_solids.beamEntersByFrontFace(solid, toSource);
}

bool ShadowPolygons::blocksRay(const Vec3& x, const Vec3& d, double tolerance, Scratch& s) const {
    if (m_items.empty()) return false;
    const Vec3 inverse(1.0 / d.x(), 1.0 / d.y(), 1.0 / d.z());
    s.stack.assign(1, 0);
    while (!s.stack.empty()) {
        const Node& node = m_nodes[s.stack.back()];
        const std::uint32_t at = s.stack.back();
        s.stack.pop_back();
        // The ray's stretch inside the node's box (slabs); a box it misses is passed over.
        double near = 0.0, far = INFINITY;
        for (int a = 0; a < 3; ++a) {
            if (d[a] == 0.0) {
                if (x[a] < node.lo[a] - tolerance || x[a] > node.hi[a] + tolerance) far = -1.0;
                continue;
            }
            double t0 = (node.lo[a] - tolerance - x[a]) * inverse[a], t1 = (node.hi[a] + tolerance - x[a]) * inverse[a];
            if (t0 > t1) std::swap(t0, t1);
            near = std::max(near, t0);
            far = std::min(far, t1);
        }
        if (far < near) continue;
        if (node.count == 0) {
            s.stack.push_back(node.right);
            s.stack.push_back(at + 1);
            continue;
        }
        for (std::uint32_t item = node.first; item < node.first + node.count; ++item) {
            const std::uint32_t b = m_items[item];
            const Vec3* c = &m_corners[m_first[b]];
            const std::uint32_t k = m_first[b + 1] - m_first[b];
            Vec3 normal = Vec3::Zero();  // Newell's: the polygon's orientation, whatever its corners
            for (std::uint32_t i = 0; i < k; ++i) normal += c[i].cross(c[(i + 1) % k]);
            const double denominator = normal.dot(d);
            if (denominator == 0.0) continue;  // the ray runs in the polygon's plane
            const double t = normal.dot(c[0] - x) / denominator;
            if (!(t > tolerance)) continue;  // behind x, or the polygon x lies on
            const Vec3 y = x + t * d;
            bool inside = true;
            for (std::uint32_t i = 0; i < k && inside; ++i) inside = (c[(i + 1) % k] - c[i]).cross(y - c[i]).dot(normal) >= 0.0;
            if (inside) return true;
        }
    }
    return false;
}

void ShadowPolygons::planeAxes(const Vec3& normal, Vec3& u, Vec3& v) {
    const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    u = normal.cross(helper).normalized();
    v = normal.cross(u);
}

void ShadowPolygons::prismSides(const Vec3* p, std::size_t count, const Vec3& along, std::vector<Vec3>& normals,
                                std::vector<double>& offsets) {
    const Vec3 middle = vertexMean(p, count);
    for (std::size_t k = 0; k < count; ++k) {
        Vec3 side = (p[(k + 1) % count] - p[k]).cross(along);
        const double length = side.norm();
        if (!(length > 0.0)) continue;  // an edge along the direction bounds nothing
        side /= length;
        if (side.dot(middle - p[k]) < 0.0) side = -side;
        normals.push_back(side);
        offsets.push_back(side.dot(p[k]));
    }
}

bool ShadowPolygons::beamRegion(const Vec3* p, std::size_t count, const Vec3& normal, const Vec3& toSource, double tolerance,
                                const Vec3* slabNormal, double slabOffset, Scratch& s, Vec3* box) const {
    // The prism swept from the polygon towards the source: a plane through each edge along the beam
    // (normals inward), and the receiver's plane. A blocker within the tolerance of it (or behind)
    // is left out; one reaching further is cut at the plane itself, so that a wall standing on the
    // receiver casts its whole shadow.
    std::vector<Vec3>& m = s.planeNormals;
    std::vector<double>& d = s.planeOffsets;
    m.clear();
    d.clear();
    prismSides(p, count, toSource, m, d);
    m.push_back(normal);
    d.push_back(normal.dot(p[0]));
    if (slabNormal) {
        m.push_back(*slabNormal);
        d.push_back(slabOffset);
    }
    // The prism's part within the blockers' box lies in the box around the receiver and the
    // receiver moved along the beam to where its last corner leaves the blockers' box: a tree node
    // outside that box is passed over without its planes (a long thin prism crosses many).
    // A point y of p leaves the root's box along the beam at min over the axes of (bound - y_a) /
    // toSource_a; each term is linear in y, so its largest over p is at a corner, and the least of
    // those largest bounds every point's exit (the corners' own exits do not: they may leave by
    // other faces than the points between them).
    const Node& root = m_nodes[0];
    double far = INFINITY;
    for (int a = 0; a < 3; ++a) {
        if (toSource[a] == 0.0) continue;
        const double bound = toSource[a] > 0.0 ? root.hi[a] : root.lo[a];
        double furthest = -INFINITY;
        for (std::size_t k = 0; k < count; ++k) furthest = std::max(furthest, (bound - p[k][a]) / toSource[a]);
        far = std::min(far, furthest);
    }
    far = std::max(far, 0.0);
    if (!std::isfinite(far)) return false;
    box[0] = Vec3::Constant(INFINITY);
    box[1] = Vec3::Constant(-INFINITY);
    for (std::size_t k = 0; k < count; ++k) {
        box[0] = box[0].cwiseMin(p[k]).cwiseMin(p[k] + far * toSource);
        box[1] = box[1].cwiseMax(p[k]).cwiseMax(p[k] + far * toSource);
    }
    box[0] -= Vec3::Constant(tolerance);
    box[1] += Vec3::Constant(tolerance);
    return true;
}

double ShadowPolygons::litFraction(const Vec3* p, std::size_t count, const Vec3& normal, PatchId r, const Vec3& toSource,
                                   double tolerance, Scratch& s) const {
    s.shadows = 0;
    const double facing = normal.dot(toSource);
    if (!(facing > 0.0) || count < 3) return 0.0;
    // The receiver's corners moved along the beam onto its plane (through corner 0), so that the
    // prism's sides and the outline the shadows are cut from agree. Corners that leave the plane
    // by their rounding (a file's digits: cornell13k's 1e-4 mm) were dropped onto it square while
    // the sides run along the beam, 1/cos as far at a grazing sun: a sphere's facet at cos 0.03
    // behind a block kept slivers along its rim lit (3.8e-5 of it, where rays find it dark).
    const double offset = normal.dot(p[0]);
    const auto alongBeam = [&](const Vec3& y) { return Vec3(y - toSource * ((normal.dot(y) - offset) / facing)); };
    s.onPlane.resize(count);
    for (std::size_t k = 0; k < count; ++k) s.onPlane[k] = alongBeam(p[k]);
    const Vec3* q = s.onPlane.data();
    // The whole receiver in its plane's axes: a receiver without area is lit nowhere.
    planeAxes(normal, s.u, s.v);
    s.clear.rest.clear();
    for (std::size_t k = 0; k < count; ++k) {
        s.clear.rest.push_back((q[k] - q[0]).dot(s.u));
        s.clear.rest.push_back((q[k] - q[0]).dot(s.v));
    }
    const double whole = std::abs(doubleArea(s.clear.rest.data(), count));
    if (!(whole > 0.0)) return 0.0;
    if (m_items.empty()) return 1.0;
    Vec3 box[2];
    const bool boxed = beamRegion(q, count, normal, toSource, tolerance, nullptr, 0.0, s, box);
    // Parallel projection along the beam onto the receiver's plane, the blockers nearest the
    // receiver first: they cover it soonest.
    castShadows(
        q, count, normal, offset, s.planeNormals.size(), tolerance, r, r, s, nullptr, alongBeam, &toSource,
        boxed ? box : nullptr, false, nullptr, &toSource);
    if (s.shadows == 0) return 1.0;
    double clear = 0.0;
    if (s.shadows == 1) {
        clear = whole - std::abs(doubleArea(s.firstShadow.data(), s.firstShadow.size() / 2));
    } else {
        for (std::size_t at = 0; at < s.clear.pieces.size();) {
            const std::size_t k = std::size_t(s.clear.pieces[at]);
            clear += std::abs(doubleArea(&s.clear.pieces[at + 1], k));
            at += 1 + 2 * k;
        }
    }
    return std::clamp(clear / whole, 0.0, 1.0);
}

void ShadowPolygons::shadeBeam(const Vec3* p, std::size_t count, const Vec3& normal, PatchId r, const Vec3& toSource,
                               double tolerance, const Vec3* slabNormal, double slabOffset, Scratch& s) const {
    s.shadows = 0;
    const double facing = normal.dot(toSource);
    if (!(facing > 0.0) || count < 3) {
        s.clear.pieces.clear();
        return;
    }
    if (m_items.empty() || s.clear.pieces.empty()) return;
    const double offset = normal.dot(p[0]);
    Vec3 box[2];
    const bool boxed = beamRegion(p, count, normal, toSource, tolerance, slabNormal, slabOffset, s, box);
    castShadows(
        p, count, normal, offset, s.planeNormals.size(), tolerance, r, r, s, nullptr,
        [&](const Vec3& y) { return Vec3(y - toSource * ((normal.dot(y) - offset) / facing)); }, &toSource,
        boxed ? box : nullptr, true, nullptr, slabNormal ? nullptr : &toSource);
}

}  // namespace hemirad
