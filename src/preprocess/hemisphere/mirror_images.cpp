// Virtual images through planar mirrors: an emitter's chains (reflector_chains.hpp) evaluated per
// emitter point by clipping each receiver to the aperture's cone, and the pairs through mirrors
// shared between their two rows.
#include "preprocess/hemisphere/mirror_images.hpp"

#include "preprocess/hemisphere/emitter_rule.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>

namespace hemirad {

MirrorImages::MirrorImages(const Scene& scene, const PatchGeometry& geometry, std::vector<Reflector> reflectors,
                           const RayScene& rays, const Settings& settings)
    : m_scene(scene), m_geometry(geometry),
      m_chains(scene, geometry, std::move(reflectors), settings.limits,
               EmitterOrders(settings.tolerance, farOrder(settings.origins), nearOrder(settings.origins)), settings.maxChains),
      m_rays(rays), m_settings(settings), m_lowest(farOrder(settings.origins)), m_flat(1e-9 * scene.extent()) {
    m_ruleNodes.resize(std::size_t(m_chains.orders().highest()) + 1);
    m_ruleWeights.resize(m_ruleNodes.size());
    for (int m = std::max(2, m_lowest); m <= m_chains.orders().highest(); ++m)
        gaussLegendre(m, m_ruleNodes[m], m_ruleWeights[m]);
}

MirrorImages::~MirrorImages() = default;

std::unique_ptr<MirrorImages::Workspace> MirrorImages::workspace() const {
    auto ws = std::make_unique<Workspace>();
    ws->status.assign(m_geometry.shapes.size(), 0);
    ws->summed.assign(m_geometry.shapes.size(), 0);
    ws->sums.assign(m_geometry.shapes.size(), 0.0);
    ws->published.assign(m_geometry.shapes.size(), -1.0);
    return ws;
}

void MirrorImages::appendPath(std::size_t node, const Vec3& emitterPoint, const Vec3& emitterNormal, const Vec3& target,
                              const Vec3& targetNormal, Workspace& ws) const {
    auto link = [&](std::int32_t q) {
        const ChainNode& n = ws.chains.nodes[std::size_t(q)];
        return ChainLink{&m_chains.reflector(n.reflector), &ws.apex[std::size_t(q)], n.parent};
    };
    appendReflectedPath(m_rays, std::int32_t(node), link, emitterPoint, emitterNormal, target, targetNormal, ws.legFrom, ws.legTo);
}

void MirrorImages::castPaths(Workspace& ws, RayCounts& counts) const {
    const std::size_t legs = ws.legFrom.size() / 3;
    ws.legBlocked.assign(legs, 0);
    if (legs > 0) m_rays.occludedSegmentPairs(ws.legFrom.data(), ws.legTo.data(), legs, ws.legBlocked.data());
    counts.rays += legs;
    ws.legFrom.clear();
    ws.legTo.clear();
}

bool MirrorImages::pathBlocked(std::size_t node, const Vec3& emitterPoint, const Vec3& emitterNormal, const Vec3& target,
                               const Vec3& targetNormal, Workspace& ws, RayCounts& counts) const {
    appendPath(node, emitterPoint, emitterNormal, target, targetNormal, ws);
    castPaths(ws, counts);
    return std::find(ws.legBlocked.begin(), ws.legBlocked.end(), 1) != ws.legBlocked.end();
}

void MirrorImages::evaluate(PatchId i, int order, PatchId only, double unit, Workspace& ws, RayCounts& counts) const {
    const PatchShape& e = m_geometry.shapes[i];
    ws.points.clear();
    ws.weights.clear();
    if (order <= 1) {
        ws.points.push_back(e.centroid);
        ws.weights.push_back(1.0);
    } else {
        polygonQuadrature(m_geometry.polygon(i), e.count, m_ruleNodes[order], m_ruleWeights[order], ws.points, ws.weights);
    }
    const std::size_t count = ws.chains.nodes.size();
    ws.apex.resize(count);
    ws.axis.resize(count);
    ws.apertures.resize(count);
    ws.alive.assign(count, 0);
    for (std::size_t point = 0; point < ws.points.size(); ++point) {
        const Vec3& x = ws.points[point];
        const double w = ws.weights[point];
        for (std::size_t q = 0; q < count; ++q) {
            const ChainNode& node = ws.chains.nodes[q];
            ws.alive[q] = 0;
            const Reflector& m = m_chains.reflector(node.reflector);
            const Vec3& from = node.parent < 0 ? x : ws.apex[node.parent];
            const Vec3& fromAxis = node.parent < 0 ? e.normal : ws.axis[node.parent];
            if (node.parent >= 0 && !ws.alive[node.parent]) continue;
            if (m.normal.dot(from) - m.offset <= m_flat) continue;  // the (image) source is behind this mirror, or on it
            std::vector<Vec3>& aperture = ws.apertures[q];
            if (node.parent < 0) {
                clipAbovePlane(x, e.normal, m.polygon.data(), m.polygon.size(), aperture);
            } else {
                const Reflector& previous = m_chains.reflector(ws.chains.nodes[node.parent].reflector);
                clipAbovePlane(previous.centre, previous.normal, m.polygon.data(), m.polygon.size(), aperture);
                clipToCone(from, ws.apertures[node.parent], aperture, ws.scratch);
            }
            if (aperture.empty()) continue;
            if (node.cutoff) {  // the power reaching this mirror and reflected on is cut off
                if (order == m_lowest && only == kEveryReceiver)
                    counts.cutoffWeight += w * node.weight * pointToPolygonFactor(from, fromAxis, aperture.data(), aperture.size());
                continue;
            }
            ws.alive[q] = 1;
            ws.apex[q] = reflectPoint(m, from);
            ws.axis[q] = reflectDirection(m, fromAxis);
            // Each receiver's factor and shadow-ray verdict; receivers whose mesh neighbours disagree
            // sit on a silhouette (seen through this aperture) and are split into pieces.
            ws.batch.clear();
            ws.factors.clear();
            ws.legStart.clear();
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                if (ws.chains.orders[k] != order || !ws.mine[k] || !clipReceiver(q, ws.chains.receivers[k], ws)) continue;
                const PatchId j = ws.chains.receivers[k];
                const double f = pointToPolygonFactor(ws.apex[q], ws.axis[q], ws.clipped.data(), ws.clipped.size());
                if (!(f > 0.0)) continue;
                ws.batch.push_back(j);
                ws.factors.push_back(f);
                ws.legStart.push_back(std::uint32_t(ws.legFrom.size() / 3));
                if (m_settings.visibility)
                    appendPath(q, x, e.normal, vertexMean(ws.clipped.data(), ws.clipped.size()), m_geometry.shapes[j].normal, ws);
            }
            // Every leg of the batch's paths in one cast; a path is blocked where any leg is.
            ws.legStart.push_back(std::uint32_t(ws.legFrom.size() / 3));
            castPaths(ws, counts);
            ws.blocked.assign(ws.batch.size(), 0);
            for (std::size_t b = 0; b < ws.batch.size(); ++b)
                for (std::uint32_t l = ws.legStart[b]; l < ws.legStart[b + 1] && !ws.blocked[b]; ++l) ws.blocked[b] = ws.legBlocked[l];
            const double scale = unit * w * node.weight;
            if (m_settings.visibility)
                for (std::size_t b = 0; b < ws.batch.size(); ++b) ws.status[ws.batch[b]] = ws.blocked[b] ? 2 : 1;
            for (std::size_t b = 0; b < ws.batch.size(); ++b) {
                const PatchId j = ws.batch[b];
                if (only != kEveryReceiver && j != only) continue;  // its status only
                if (m_settings.visibility && m_geometry.onSilhouette(j, ws.status)) {
                    clipReceiver(q, j, ws);
                    ws.pieces.clear();
                    splitPolygon(ws.clipped.data(), ws.clipped.size(), ws.pieces);
                    for (std::size_t p = 0; p < ws.pieces.size(); p += 4) {
                        const double f = pointToPolygonFactor(ws.apex[q], ws.axis[q], &ws.pieces[p], 4);
                        const Vec3 aim = vertexMean(&ws.pieces[p], 4);
                        if (f > 0.0 && !pathBlocked(q, x, e.normal, aim, m_geometry.shapes[j].normal, ws, counts))
                            addTerm(j, scale * f, ws);
                    }
                } else if (!ws.blocked[b]) {
                    addTerm(j, scale * ws.factors[b], ws);
                }
                counts.bounces += node.depth;
            }
            if (m_settings.visibility)
                for (const PatchId j : ws.batch) ws.status[j] = 0;
        }
    }
}

bool MirrorImages::clipReceiver(std::size_t q, PatchId j, Workspace& ws) const {
    const PatchShape& t = m_geometry.shapes[j];
    if (t.normal.dot(ws.apex[q] - t.centroid) <= 1e-9 * t.radius) return false;  // must face the image
    const Reflector& m = m_chains.reflector(ws.chains.nodes[q].reflector);
    clipAbovePlane(m.centre, m.normal, m_geometry.polygon(j), t.count, ws.clipped);
    clipToCone(ws.apex[q], ws.apertures[q], ws.clipped, ws.scratch);
    return !ws.clipped.empty();
}

void MirrorImages::ownTerms(PatchId i, double unit, Workspace& ws, RayCounts& counts) const {
    m_chains.enumerate(i, ws.chains);
    if (ws.chains.nodes.empty()) return;
    // One pass per emitter rule in use; the lowest always runs (it counts what is cut off). The
    // orders are the direct factors' (EmitterOrders): up to ceil(sqrt K) for --origins K, 256 at
    // the most, so they are flagged per order, not as bits of a word (issue 35 #1: past order 31
    // the mirror terms vanished).
    ws.mine.resize(ws.chains.receivers.size());
    ws.used.assign(std::size_t(m_chains.orders().highest()) + 1, 0);
    ws.used[std::size_t(m_lowest)] = 1;
    for (std::size_t k = 0; k < ws.chains.receivers.size(); ++k) {
        const PatchId r = ws.chains.receivers[k];
        ws.mine[k] = r == i || emitsFor(m_scene, i, r);
        if (ws.mine[k]) ws.used[ws.chains.orders[k]] = 1;
    }
    for (int order = m_lowest; order <= m_chains.orders().highest(); ++order)
        if (ws.used[std::size_t(order)]) evaluate(i, order, kEveryReceiver, unit, ws, counts);
}

void MirrorImages::collect(PatchId i, RowAccumulator& row, double unit, Workspace& ws) const {
    ws.outgoing.clear();
    for (const PatchId j : ws.touched) {
        ws.summed[j] = 0;
        if (!(ws.sums[j] > 0.0)) continue;
        row.addWeight(j, ws.sums[j]);
        if (j != i) ws.outgoing.push_back({j, handOver(m_scene, ws.sums[j], i, j, unit)});
    }
    ws.touched.clear();
}

void MirrorImages::addRow(PatchId i, RowAccumulator& row, double unit, PairExchange& exchange, Workspace& ws,
                          RayCounts& counts) const {
    // The pairs i emits for (and i seen in a mirror), published for their other rows.
    ownTerms(i, unit, ws, counts);
    collect(i, row, unit, ws);
    exchange.publish(i, ws.outgoing);
    // The pairs emitted for i: handed over, or absent from an emitter that had finished (no term),
    // or recomputed from the emitter along the chains by which i sees it, reversed.
    const std::uint64_t ticket = exchange.open(i, ws.taken);
    for (const PairExchange::Entry& entry : ws.taken) {
        ws.published[entry.patch] = entry.value;
        if (entry.value > 0.0) row.addWeight(entry.patch, entry.value * unit);
    }
    ws.pending.clear();
    for (std::uint32_t q = 0; q < ws.chains.nodes.size(); ++q) {
        const ChainNode& node = ws.chains.nodes[q];
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
            const PatchId e = ws.chains.receivers[k];
            if (e != i && !ws.mine[k] && ws.published[e] < 0.0 && !exchange.finished(e, ticket))
                ws.pending.push_back({e, q});
        }
    }
    for (const PairExchange::Entry& entry : ws.taken) ws.published[entry.patch] = -1.0;
    std::sort(ws.pending.begin(), ws.pending.end());
    ws.pending.erase(std::unique(ws.pending.begin(), ws.pending.end()), ws.pending.end());
    if (!ws.pair && !ws.pending.empty()) ws.pair = workspace();
    for (std::size_t p = 0; p < ws.pending.size();) {
        const PatchId e = ws.pending[p].first;
        ws.reversed.clear();
        for (; p < ws.pending.size() && ws.pending[p].first == e; ++p) {
            ws.reversed.emplace_back();
            for (std::int32_t q = std::int32_t(ws.pending[p].second); q >= 0; q = ws.chains.nodes[q].parent)
                ws.reversed.back().push_back(ws.chains.nodes[q].reflector);  // the last mirror first: e's side
        }
        const double terms = pairTerms(e, i, ws, unit, *ws.pair, counts);
        const double value = handOver(m_scene, terms, e, i, unit);
        if (value > 0.0) row.addWeight(e, value * unit);
    }
}

double MirrorImages::pairTerms(PatchId e, PatchId r, const Workspace& from, double unit, Workspace& ws,
                               RayCounts& counts) const {
    // e's nodes on the chains by which r sees it, as e's own row makes them (the chain order), with
    // r's mesh neighbours for the silhouette test where there are shadow rays.
    m_chains.enumerateToward(e, r, from.reversed, m_settings.visibility, ws.chains);
    ws.used.assign(std::size_t(m_chains.orders().highest()) + 1, 0);
    for (std::size_t k = 0; k < ws.chains.receivers.size(); ++k)
        if (ws.chains.receivers[k] == r) ws.used[ws.chains.orders[k]] = 1;
    ws.mine.assign(ws.chains.receivers.size(), 1);
    for (int order = m_lowest; order <= m_chains.orders().highest(); ++order)
        if (ws.used[std::size_t(order)]) evaluate(e, order, r, unit, ws, counts);
    double terms = 0.0;
    for (const PatchId j : ws.touched) {
        if (j == r) terms = ws.sums[j];
        ws.summed[j] = 0;
    }
    ws.touched.clear();
    return terms;
}

}  // namespace hemirad
