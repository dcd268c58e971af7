// Sensors through mirrors: a point's chains of reflectors, breadth first, each node's receivers found
// in a ball tree within the cone from its image through its mirror, clipped to its aperture, their
// factors from the image, and shadow rays along the reflected paths.
#include "environment/sensor_mirrors.hpp"

#include "engine/error.hpp"
#include "engine/parallel_failure.hpp"
#include "preprocess/hemisphere/mirror_images.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <omp.h>

namespace hemirad {

std::string sensorMirrorsNote(const Scene& scene, std::vector<Reflector>& reflectors) {
    reflectors.clear();
    if (!scene.hasMirrors()) return {};
    if (!rayCastingNotBuilt().empty())
        return "not followed: " + rayCastingNotBuilt() + " (what the sensors would see in the mirrors is not counted)";
    const std::string why = findReflectors(scene, reflectors);
    if (!why.empty()) {
        reflectors.clear();
        return "not followed: " + why + " (what the sensors would see in the mirrors is not counted)";
    }
    return "followed";
}

SensorMirrors::SensorMirrors(const Scene& scene, const PatchGeometry& geometry, std::vector<Reflector> reflectors,
                             const RayScene& rays, const MirrorChainLimits& limits)
    : m_scene(scene), m_geometry(geometry), m_reflectors(std::move(reflectors)), m_rays(rays), m_limits(limits),
      m_reflectorOf(scene.size(), -1), m_flat(1e-9 * scene.extent()) {
    std::vector<Vec3> centres;
    std::vector<double> radii;
    for (PatchId j = 0; j < scene.size(); ++j) {
        centres.push_back(geometry.shapes[j].centroid);
        radii.push_back(geometry.shapes[j].radius);
    }
    m_patchTree.build(centres, radii);
    for (std::size_t k = 0; k < m_reflectors.size(); ++k)
        for (const PatchId j : m_reflectors[k].patches) m_reflectorOf[j] = std::int32_t(k);
}

SensorMirrors::Workspace SensorMirrors::workspace() const {
    Workspace ws;
    ws.childReach.assign(m_reflectors.size(), 0.0);
    ws.status.assign(m_geometry.shapes.size(), 0);
    return ws;
}

bool SensorMirrors::clip(std::size_t q, PatchId r, Workspace& ws) const {
    const Reflector& m = m_reflectors[ws.nodes[q].reflector];
    clipAbovePlane(m.centre, m.normal, m_geometry.polygon(r), m_geometry.shapes[r].count, ws.clipped);
    clipToCone(ws.nodes[q].image, ws.apertures[q], ws.clipped, ws.scratch);
    return ws.clipped.size() >= 3;
}

void SensorMirrors::appendPath(std::size_t q, const Vec3& x, const Vec3& n, const Vec3& target, const Vec3& targetNormal,
                               Workspace& ws) const {
    auto link = [&](std::int32_t k) {
        const Node& node = ws.nodes[std::size_t(k)];
        return ChainLink{&m_reflectors[node.reflector], &node.image, node.parent};
    };
    appendReflectedPath(m_rays, std::int32_t(q), link, x, n, target, targetNormal, ws.legFrom, ws.legTo);
}

void SensorMirrors::castLegs(Workspace& ws, Totals& totals) const {
    const std::size_t legs = ws.legFrom.size() / 3;
    ws.legBlocked.assign(legs, 0);
    if (legs > 0) m_rays.occludedSegmentPairs(ws.legFrom.data(), ws.legTo.data(), legs, ws.legBlocked.data());
    totals.rays += legs;
    ws.legFrom.clear();
    ws.legTo.clear();
}

bool SensorMirrors::pathFree(std::size_t q, const Vec3& x, const Vec3& n, const Vec3& target, const Vec3& targetNormal,
                             Workspace& ws, Totals& totals) const {
    appendPath(q, x, n, target, targetNormal, ws);
    castLegs(ws, totals);
    return std::find(ws.legBlocked.begin(), ws.legBlocked.end(), 1) == ws.legBlocked.end();
}

double SensorMirrors::inPieces(std::size_t q, const Vec3& x, const Vec3& n, PatchId r, Workspace& ws, Totals& totals) const {
    // The receiver's part in the aperture in quads (splitPolygon), a quad above kPiecesAbove split
    // again, kPieceLevels deep at most; each quad seen or hidden by the ray to its middle.
    const Node& node = ws.nodes[q];
    clip(q, r, ws);
    ws.pieces.clear();
    ws.levels.clear();
    splitPolygon(ws.clipped.data(), ws.clipped.size(), ws.pieces);
    ws.levels.assign(ws.pieces.size() / 4, 1);
    double seen = 0.0;
    while (!ws.pieces.empty()) {
        const Vec3 quad[4] = {ws.pieces[ws.pieces.size() - 4], ws.pieces[ws.pieces.size() - 3], ws.pieces[ws.pieces.size() - 2],
                              ws.pieces[ws.pieces.size() - 1]};
        const int level = ws.levels.back();
        ws.pieces.resize(ws.pieces.size() - 4);
        ws.levels.pop_back();
        const double f = pointToPolygonFactor(node.image, node.axis, quad, 4);
        if (!(f > 0.0)) continue;
        if (f > kPiecesAbove && level < kPieceLevels) {
            const std::size_t before = ws.pieces.size();
            splitPolygon(quad, 4, ws.pieces);
            ws.levels.resize(ws.levels.size() + (ws.pieces.size() - before) / 4, level + 1);
            continue;
        }
        if (pathFree(q, x, n, vertexMean(quad, 4), m_geometry.shapes[r].normal, ws, totals)) seen += f;
    }
    return seen;
}

SensorMirrors::Totals SensorMirrors::sees(const Vec3& x, const Vec3& n, const std::vector<double>& reach, Workspace& ws,
                                          std::vector<std::pair<PatchId, double>>& terms) const {
    Totals totals;
    const std::size_t count = m_scene.size();
    ws.nodes.clear();
    auto push = [&](const Node& node) -> std::vector<Vec3>& {
        ws.nodes.push_back(node);
        if (ws.apertures.size() < ws.nodes.size()) ws.apertures.resize(ws.nodes.size());
        return ws.apertures[ws.nodes.size() - 1];
    };
    // The reflectors x sees straight, by index: the part of each above x's plane is the aperture.
    for (std::uint32_t k = 0; k < m_reflectors.size(); ++k) {
        const Reflector& m = m_reflectors[k];
        if (!(reach[k] > 0.0) || m.normal.dot(x) - m.offset <= m_flat) continue;
        std::vector<Vec3>& aperture = push({-1, k, 1, m.specular, reach[k], reflectPoint(m, x), reflectDirection(m, n)});
        clipAbovePlane(x, n, m.polygon.data(), m.polygon.size(), aperture);
        if (aperture.size() < 3) ws.nodes.pop_back();
    }
    for (std::size_t q = 0; q < ws.nodes.size(); ++q) {
        const Node node = ws.nodes[q];
        if (node.depth > m_limits.maxDepth || node.weight < m_limits.minWeight) {
            totals.cutoff += node.weight * node.reach;
            totals.sky += node.weight * node.reach;
            continue;
        }
        const Reflector& m = m_reflectors[node.reflector];
        // The receivers in front of the mirror within the cone from the image through it: each one's
        // factor, and the legs of the path to its part's middle.
        const BallCone cone(node.image, 0.0, m.centre, m.radius);
        auto ahead = [&](const Vec3& c, double radius) { return m.normal.dot(c) - m.offset > -radius && cone.meets(c, radius); };
        ws.batch.clear();
        ws.factors.clear();
        ws.legStart.clear();
        m_patchTree.query(ws.stack, ahead, [&](std::uint32_t j) {
            if (m_reflectorOf[j] == std::int32_t(node.reflector)) return;
            const PatchShape& t = m_geometry.shapes[j];
            const double side = t.normal.dot(node.image - t.centroid);
            if (std::abs(side) <= 1e-9 * t.radius) return;  // seen edge-on
            const PatchId r = side > 0.0 ? j : PatchId(count + j);  // its front, or its back (hides, receives nothing)
            if (!clip(q, r, ws)) return;
            const double f = pointToPolygonFactor(node.image, node.axis, ws.clipped.data(), ws.clipped.size());
            if (!(f > 0.0)) return;
            ++totals.terms;
            ws.batch.push_back(r);
            ws.factors.push_back(f);
            ws.legStart.push_back(std::uint32_t(ws.legFrom.size() / 3));
            appendPath(q, x, n, vertexMean(ws.clipped.data(), ws.clipped.size()), m_geometry.shapes[r].normal, ws);
        });
        ws.legStart.push_back(std::uint32_t(ws.legFrom.size() / 3));
        castLegs(ws, totals);  // every leg of the batch's paths in one cast
        ws.blocked.assign(ws.batch.size(), 0);
        for (std::size_t b = 0; b < ws.batch.size(); ++b) {
            for (std::uint32_t l = ws.legStart[b]; l < ws.legStart[b + 1] && !ws.blocked[b]; ++l) ws.blocked[b] = ws.legBlocked[l];
            ws.status[ws.batch[b]] = ws.blocked[b] ? 2 : 1;
        }
        // What each receiver fills of the aperture; one on a silhouette in pieces, a ray each.
        double landed = 0.0;
        ws.children.clear();
        for (std::size_t b = 0; b < ws.batch.size(); ++b) {
            const PatchId r = ws.batch[b];
            double seen = 0.0;
            if (m_geometry.onSilhouette(r, ws.status) || ws.factors[b] > kPiecesAbove) {
                seen = inPieces(q, x, n, r, ws, totals);
            } else if (!ws.blocked[b]) {
                seen = ws.factors[b];
            }
            if (!(seen > 0.0)) continue;
            landed += seen;
            if (r >= count) continue;
            terms.emplace_back(r, node.weight * seen);
            const std::int32_t k = m_reflectorOf[r];
            if (k >= 0) {
                if (ws.childReach[std::size_t(k)] == 0.0) ws.children.push_back(std::uint32_t(k));
                ws.childReach[std::size_t(k)] += seen;
            }
        }
        for (const PatchId r : ws.batch) ws.status[r] = 0;
        // The part of the aperture that no patch fills is sky (the receivers' factors may overshoot
        // it by their rules' rounding).
        totals.sky += node.weight * std::max(0.0, node.reach - landed);
        // The reflectors seen through this one, by index: what reached each goes on.
        std::sort(ws.children.begin(), ws.children.end());
        for (const std::uint32_t k : ws.children) {
            const double reached = ws.childReach[k];
            ws.childReach[k] = 0.0;
            const Reflector& next = m_reflectors[k];
            if (next.normal.dot(node.image) - next.offset <= m_flat) continue;
            std::vector<Vec3>& aperture = push({std::int32_t(q), k, node.depth + 1, node.weight * next.specular, reached,
                                                reflectPoint(next, node.image), reflectDirection(next, node.axis)});
            clipAbovePlane(m.centre, m.normal, next.polygon.data(), next.polygon.size(), aperture);
            clipToCone(node.image, ws.apertures[q], aperture, ws.scratch);
            if (aperture.size() < 3) ws.nodes.pop_back();
        }
    }
    return totals;
}

namespace {

/// Whether p (on m's plane) lies in m, a point on an edge in one mirror only of those that share it
/// (a facade's panes): the polygon and p in the plane of the two coordinates across m's largest
/// normal component (the same plane for coplanar panes, counter-clockwise), by the top-left rule.
bool insideMirror(const Reflector& m, const Vec3& p, std::vector<std::array<double, 2>>& outline) {
    int k = 0;
    for (int c = 1; c < 3; ++c)
        if (std::abs(m.normal[c]) > std::abs(m.normal[k])) k = c;
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    outline.clear();
    for (const Vec3& corner : m.polygon) outline.push_back({corner[u], corner[v]});
    if (m.normal[k] < 0.0) std::reverse(outline.begin(), outline.end());  // seen from -k: clockwise
    thread_local std::vector<std::uint8_t> closed;  // no open edge: every edge is shared or the mirror's own
    if (closed.size() < outline.size()) closed.assign(outline.size(), 0);
    return insideTopLeft(outline, closed, {p[u], p[v]});
}

}  // namespace

SensorReflections::SensorReflections(const Scene& scene, int threads) : m_threads(threads) {
    m_note = sensorMirrorsNote(scene, m_reflectors);
    if (!m_reflectors.empty()) m_rays = std::make_unique<RayScene>(scene, threads);
}

SensorReflections::~SensorReflections() = default;

std::vector<double> SensorReflections::sun(const BeamShadows& beams, const Sensors& sensors, const Vec3& toSun,
                                           double dni) const {
    if (!toSun.allFinite() || !(toSun.norm() > 0.0)) throw Error("sun: the direction to the sun must be a finite non-zero vector");
    std::vector<double> out(sensors.size(), 0.0);
    if (!active() || !(dni > 0.0)) return out;
    const Vec3 d = toSun.normalized();
    const double flat = 1e-9 * beams.scene().extent();
    const double lift = m_rays->originOffset();
    ParallelFailure failure;
#pragma omp parallel num_threads(m_threads > 0 ? m_threads : omp_get_max_threads())
    {
        ShadowPolygons::Scratch scratch;
        std::vector<float> from, to;
        std::vector<std::uint8_t> blocked;
        std::vector<double> gain;
        std::vector<std::array<double, 2>> outline;
#pragma omp for schedule(dynamic, 64)
        for (std::int64_t ss = 0; ss < std::int64_t(sensors.size()); ++ss) {
            if (failure.failed()) continue;
            failure.run([&] {
                const std::size_t s = std::size_t(ss);
                const Vec3& x = sensors.position[s];
                const Vec3& n = sensors.normal[s];
                from.clear();
                to.clear();
                gain.clear();
                for (const Reflector& m : m_reflectors) {
                    const double facing = m.normal.dot(d);
                    const double height = m.normal.dot(x) - m.offset;
                    if (!(facing > 0.0) || height <= flat) continue;  // the sun or the sensor behind the mirror
                    const Vec3 back = d - 2.0 * facing * m.normal;     // from the sensor toward the mirror, against the beam
                    const double cosine = n.dot(back);
                    if (!(cosine > 0.0)) continue;
                    const Vec3 p = x + (height / facing) * back;
                    if (!insideMirror(m, p, outline) || beams.blockers().blocksRay(p, d, beams.tolerance(), scratch)) continue;
                    float a[3], b[3];
                    m_rays->toLocal(x + lift * back, a);
                    m_rays->toLocal(p + lift * m.normal, b);
                    from.insert(from.end(), a, a + 3);
                    to.insert(to.end(), b, b + 3);
                    gain.push_back(m.specular * dni * cosine);
                }
                if (gain.empty()) return;
                blocked.assign(gain.size(), 0);
                m_rays->occludedSegmentPairs(from.data(), to.data(), gain.size(), blocked.data());
                for (std::size_t k = 0; k < gain.size(); ++k)
                    if (!blocked[k]) out[s] += gain[k];
            });
        }
    }
    failure.rethrowIfFailed();
    return out;
}

}  // namespace hemirad
