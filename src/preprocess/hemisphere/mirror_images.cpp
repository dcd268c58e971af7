// Virtual images through planar mirrors: chains enumerated per emitter with a conservative cone,
// then evaluated per emitter point by clipping each receiver to the aperture's cone.
#include "preprocess/hemisphere/mirror_images.hpp"

#include "engine/error.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hemirad {

MirrorImages::MirrorImages(const Scene& scene, const PatchGeometry& geometry, std::vector<Reflector> reflectors,
                           const RayScene& rays, const Settings& settings)
    : m_scene(scene), m_geometry(geometry), m_reflectors(std::move(reflectors)), m_rays(rays), m_settings(settings),
      m_lowest(farOrder(settings.origins)), m_near(nearOrder(settings.origins)),
      m_orders(settings.tolerance, m_lowest, m_near), m_flat(1e-9 * scene.extent()) {
    m_ruleNodes.resize(std::size_t(m_orders.highest()) + 1);
    m_ruleWeights.resize(m_ruleNodes.size());
    for (int m = std::max(2, m_lowest); m <= m_orders.highest(); ++m) gaussLegendre(m, m_ruleNodes[m], m_ruleWeights[m]);
    std::vector<Vec3> centres;
    std::vector<double> radii;
    for (const PatchShape& t : geometry.shapes) {
        centres.push_back(t.centroid);
        radii.push_back(t.radius);
    }
    m_patchTree.build(centres, radii);
    centres.clear();
    radii.clear();
    for (const Reflector& r : m_reflectors) {
        centres.push_back(r.centre);
        radii.push_back(r.radius);
    }
    m_reflectorTree.build(centres, radii);
}

MirrorImages::~MirrorImages() = default;

std::unique_ptr<MirrorImages::Workspace> MirrorImages::workspace() const {
    auto ws = std::make_unique<Workspace>();
    ws->status.assign(m_geometry.shapes.size(), 0);
    ws->summed.assign(m_geometry.shapes.size(), 0);
    ws->sums.assign(m_geometry.shapes.size(), 0.0);
    ws->published.assign(m_geometry.shapes.size(), -1.0f);
    return ws;
}

MirrorImages::Node MirrorImages::makeNode(const std::vector<Node>& nodes, std::int32_t parent, std::uint32_t k,
                                          const Vec3& from) const {
    // The product of the s met, multiplied smallest first: the same bits for the chain and its
    // reverse, so that both rows of a pair cut it off alike at --min-weight.
    thread_local std::vector<double> s;
    s.assign(1, m_reflectors[k].specular);
    for (std::int32_t q = parent; q >= 0; q = nodes[q].parent) s.push_back(m_reflectors[nodes[q].reflector].specular);
    std::sort(s.begin(), s.end());
    double weight = 1.0;
    for (const double factor : s) weight *= factor;
    const std::uint32_t depth = parent < 0 ? 1 : nodes[parent].depth + 1;
    Node node{parent, k, depth, weight, reflectPoint(m_reflectors[k], from)};
    node.cutoff = depth > m_settings.limits.maxDepth || weight < m_settings.limits.minWeight;
    return node;
}

bool MirrorImages::seesFromEmitter(const PatchShape& e, std::uint32_t k) const {
    // Partly above the emitter's plane, the emitter partly in front, each by more than rounding: a
    // mirror in the emitter's own plane (another pane of its facade) reflects nothing to it (with
    // a tolerance of 0, a normal 1e-17 off made such panes "seen", and their images, on the
    // emitter itself, sent 0.8 of its hemisphere a second time).
    const Reflector& m = m_reflectors[k];
    if (m.normal.dot(e.centroid) - m.offset <= -e.radius) return false;
    bool inFront = false;
    for (std::uint32_t c = 0; c < e.count && !inFront; ++c)
        inFront = m.normal.dot(m_geometry.corners[e.first + c]) - m.offset > m_flat;
    if (!inFront) return false;
    for (const Vec3& p : m.polygon)
        if (e.normal.dot(p - e.centroid) > m_flat) return true;
    return false;
}

bool MirrorImages::reaches(const Node& node, double r, const BallCone& cone, std::uint32_t k) const {
    const Reflector& next = m_reflectors[k];
    if (k == node.reflector || !partlyInFront(m_reflectors[node.reflector], next.polygon)) return false;
    if (next.normal.dot(node.image) - next.offset <= -r) return false;
    return cone.meets(next.centre, next.radius);
}

int MirrorImages::receiverOrder(const Node& node, double r, const BallCone& cone, PatchId j) const {
    const Reflector& m = m_reflectors[node.reflector];
    const PatchShape& t = m_geometry.shapes[j];
    if (m.normal.dot(t.centroid) - m.offset <= -t.radius) return -1;  // behind the mirror
    if (t.normal.dot(node.image - t.centroid) <= -r) return -1;        // faces away from every image point
    if (!cone.meets(t.centroid, t.radius)) return -1;
    const double ratio = std::max(0.0, (t.centroid - node.image).norm() - t.radius) / r;
    return m_orders(ratio);
}

// The chain order, the one order in which an emitter's chains become nodes: the reflectors seen
// straight from the emitter by index, then breadth first, each node's next reflectors by index;
// that is, the chains by length, then lexicographically by reflector. evaluate adds a receiver's
// terms per rule, per emitter point, per node in node order, so the pair recomputed from its
// emitter along some of the chains (pairTerms) sums its terms in the very order of the emitting
// row, equal bit for bit, because both rows build their nodes here, with the same checks
// (seesFromEmitter, reaches, makeNode's cut-offs). Only the candidates differ: roots(candidates)
// appends the first reflectors to try, expand(q, node, cone, candidates) node q's receivers (to
// ws.receivers and ws.orders) and the next reflectors to try, both in any order, repeats allowed.
template <class Roots, class Expand>
void MirrorImages::inChainOrder(PatchId i, std::size_t maxNodes, Roots roots, Expand expand, Workspace& ws) const {
    const PatchShape& e = m_geometry.shapes[i];
    const double r = e.radius;
    ws.nodes.clear();
    ws.receivers.clear();
    ws.orders.clear();
    // The candidates by index, each once, those that pass `keep` made nodes from `parent`.
    auto push = [&](std::int32_t parent, const Vec3& from, auto keep) {
        std::sort(ws.next.begin(), ws.next.end());
        ws.next.erase(std::unique(ws.next.begin(), ws.next.end()), ws.next.end());
        for (const std::uint32_t k : ws.next) {
            if (!keep(k)) continue;
            if (ws.nodes.size() >= maxNodes)
                throw Error("mirror images: patch " + std::to_string(i) + " sees more than " + std::to_string(maxNodes) +
                            " chains of mirrors; lower --max-depth or raise --min-weight, or use --mirror-estimator rays");
            ws.nodes.push_back(makeNode(ws.nodes, parent, k, from));
        }
    };
    ws.next.clear();
    roots(ws.next);
    push(-1, e.centroid, [&](std::uint32_t k) { return seesFromEmitter(e, k); });
    for (std::size_t q = 0; q < ws.nodes.size(); ++q) {
        if (ws.nodes[q].cutoff) continue;
        const Node node = ws.nodes[q];
        const Reflector& m = m_reflectors[node.reflector];
        const BallCone cone(node.image, r, m.centre, m.radius);
        ws.nodes[q].first = static_cast<std::uint32_t>(ws.receivers.size());
        ws.next.clear();
        expand(q, node, cone, ws.next);
        ws.nodes[q].count = static_cast<std::uint32_t>(ws.receivers.size()) - ws.nodes[q].first;
        push(std::int32_t(q), node.image, [&](std::uint32_t k) { return reaches(node, r, cone, k); });
    }
}

void MirrorImages::enumerate(PatchId i, Workspace& ws) const {
    const double r = m_geometry.shapes[i].radius;
    auto roots = [&](std::vector<std::uint32_t>& candidates) {
        for (std::uint32_t k = 0; k < m_reflectors.size(); ++k) candidates.push_back(k);
    };
    auto expand = [&](std::size_t, const Node& node, const BallCone& cone, std::vector<std::uint32_t>& candidates) {
        // Balls wholly behind the mirror or off the cone hold no receiver and no next reflector.
        const Reflector& m = m_reflectors[node.reflector];
        auto ahead = [&](const Vec3& c, double radius) {
            return m.normal.dot(c) - m.offset > -radius && cone.meets(c, radius);
        };
        m_patchTree.query(ws.stack, ahead, [&](std::uint32_t j) {
            const int order = receiverOrder(node, r, cone, j);
            if (order < 0) return;
            ws.receivers.push_back(j);
            ws.orders.push_back(static_cast<std::uint16_t>(order));
        });
        m_reflectorTree.query(ws.stack, ahead, [&](std::uint32_t k) { candidates.push_back(k); });
    };
    inChainOrder(i, m_settings.maxChains, roots, expand, ws);
}

void MirrorImages::appendPath(std::size_t node, const Vec3& emitterPoint, const Vec3& emitterNormal, const Vec3& target,
                              const Vec3& targetNormal, Workspace& ws) const {
    const double offset = m_rays.originOffset();
    auto leg = [&](const Vec3& from, const Vec3& fromNormal, const Vec3& to, const Vec3& toNormal) {
        float a[3], b[3];
        m_rays.toLocal(from + offset * fromNormal, a);
        m_rays.toLocal(to + offset * toNormal, b);
        ws.legFrom.insert(ws.legFrom.end(), a, a + 3);
        ws.legTo.insert(ws.legTo.end(), b, b + 3);
    };
    // Back along the chain: the leg into `to` comes from the mirror point where the line from the
    // chain's image to `to` crosses the mirror.
    Vec3 to = target, toNormal = targetNormal;
    for (std::int32_t q = std::int32_t(node); q >= 0; q = ws.nodes[q].parent) {
        const Reflector& m = m_reflectors[ws.nodes[q].reflector];
        const Vec3& image = ws.apex[q];
        const double along = (m.offset - m.normal.dot(image)) / m.normal.dot(to - image);
        const Vec3 onMirror = image + along * (to - image);
        leg(onMirror, m.normal, to, toNormal);
        to = onMirror;
        toNormal = m.normal;
    }
    leg(emitterPoint, emitterNormal, to, toNormal);
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
    const std::size_t count = ws.nodes.size();
    ws.apex.resize(count);
    ws.axis.resize(count);
    ws.apertures.resize(count);
    ws.alive.assign(count, 0);
    for (std::size_t point = 0; point < ws.points.size(); ++point) {
        const Vec3& x = ws.points[point];
        const double w = ws.weights[point];
        for (std::size_t q = 0; q < count; ++q) {
            const Node& node = ws.nodes[q];
            ws.alive[q] = 0;
            const Reflector& m = m_reflectors[node.reflector];
            const Vec3& from = node.parent < 0 ? x : ws.apex[node.parent];
            const Vec3& fromAxis = node.parent < 0 ? e.normal : ws.axis[node.parent];
            if (node.parent >= 0 && !ws.alive[node.parent]) continue;
            if (m.normal.dot(from) - m.offset <= m_flat) continue;  // the (image) source is behind this mirror, or on it
            std::vector<Vec3>& aperture = ws.apertures[q];
            if (node.parent < 0) {
                clipAbovePlane(x, e.normal, m.polygon.data(), m.polygon.size(), aperture);
            } else {
                const Reflector& previous = m_reflectors[ws.nodes[node.parent].reflector];
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
                if (ws.orders[k] != order || !ws.mine[k] || !clipReceiver(q, ws.receivers[k], ws)) continue;
                const PatchId j = ws.receivers[k];
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
    const Reflector& m = m_reflectors[ws.nodes[q].reflector];
    clipAbovePlane(m.centre, m.normal, m_geometry.polygon(j), t.count, ws.clipped);
    clipToCone(ws.apex[q], ws.apertures[q], ws.clipped, ws.scratch);
    return !ws.clipped.empty();
}

void MirrorImages::ownTerms(PatchId i, double unit, Workspace& ws, RayCounts& counts) const {
    enumerate(i, ws);
    if (ws.nodes.empty()) return;
    // One pass per emitter rule in use; the lowest always runs (it counts what is cut off). The
    // orders are the direct factors' (EmitterOrders): up to ceil(sqrt K) for --origins K, 256 at
    // the most, so they are flagged per order, not as bits of a word (issue 35 #1: past order 31
    // the mirror terms vanished).
    ws.mine.resize(ws.receivers.size());
    ws.used.assign(std::size_t(m_orders.highest()) + 1, 0);
    ws.used[std::size_t(m_lowest)] = 1;
    for (std::size_t k = 0; k < ws.receivers.size(); ++k) {
        const PatchId r = ws.receivers[k];
        ws.mine[k] = r == i || emitsFor(m_scene, i, r);
        if (ws.mine[k]) ws.used[ws.orders[k]] = 1;
    }
    for (int order = m_lowest; order <= m_orders.highest(); ++order)
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
        if (entry.value > 0.0f) row.addWeight(entry.patch, double(entry.value) * unit);
    }
    ws.pending.clear();
    for (std::uint32_t q = 0; q < ws.nodes.size(); ++q)
        for (std::uint32_t k = ws.nodes[q].first; k < ws.nodes[q].first + ws.nodes[q].count; ++k) {
            const PatchId e = ws.receivers[k];
            if (e != i && !ws.mine[k] && ws.published[e] < 0.0f && !exchange.finished(e, ticket))
                ws.pending.push_back({e, q});
        }
    for (const PairExchange::Entry& entry : ws.taken) ws.published[entry.patch] = -1.0f;
    std::sort(ws.pending.begin(), ws.pending.end());
    ws.pending.erase(std::unique(ws.pending.begin(), ws.pending.end()), ws.pending.end());
    if (!ws.pair && !ws.pending.empty()) ws.pair = workspace();
    for (std::size_t p = 0; p < ws.pending.size();) {
        const PatchId e = ws.pending[p].first;
        ws.chains.clear();
        for (; p < ws.pending.size() && ws.pending[p].first == e; ++p) {
            ws.chains.emplace_back();
            for (std::int32_t q = std::int32_t(ws.pending[p].second); q >= 0; q = ws.nodes[q].parent)
                ws.chains.back().push_back(ws.nodes[q].reflector);  // the last mirror first: e's side
        }
        const double terms = pairTerms(e, i, ws, unit, *ws.pair, counts);
        const float value = handOver(m_scene, terms, e, i, unit);
        if (value > 0.0f) row.addWeight(e, double(value) * unit);
    }
}

double MirrorImages::pairTerms(PatchId e, PatchId r, const Workspace& from, double unit, Workspace& ws,
                               RayCounts& counts) const {
    // e's nodes on the chains in from.chains (each from e's side), found as enumerate finds them.
    // The chains sorted lexicographically: those through a node, a run of them (ws.spans).
    const std::vector<std::vector<std::uint32_t>>& chains = from.chains;
    ws.ranked.resize(chains.size());
    for (std::uint32_t c = 0; c < chains.size(); ++c) ws.ranked[c] = c;
    std::sort(ws.ranked.begin(), ws.ranked.end(), [&](std::uint32_t a, std::uint32_t b) { return chains[a] < chains[b]; });
    ws.spans.clear();
    const double radius = m_geometry.shapes[e].radius;
    auto roots = [&](std::vector<std::uint32_t>& candidates) {
        for (const std::vector<std::uint32_t>& chain : chains) candidates.push_back(chain[0]);
    };
    auto expand = [&](std::size_t q, const Node& node, const BallCone& cone, std::vector<std::uint32_t>& candidates) {
        // The parent's run narrowed to the chains whose next reflector (at depth - 1) is this node's.
        const std::size_t depth = node.depth;
        const auto begin = ws.ranked.begin();
        auto first = begin, last = ws.ranked.end();
        if (node.parent >= 0) {
            first = begin + ws.spans[std::size_t(node.parent)].first;
            last = begin + ws.spans[std::size_t(node.parent)].second;
        }
        const auto at = [&](std::uint32_t c) { return chains[c].size() < depth ? -1 : std::int64_t(chains[c][depth - 1]); };
        const std::int64_t k = node.reflector;
        first = std::partition_point(first, last, [&](std::uint32_t c) { return at(c) < k; });
        last = std::partition_point(first, last, [&](std::uint32_t c) { return at(c) == k; });
        if (ws.spans.size() <= q) ws.spans.resize(q + 1);
        ws.spans[q] = {std::uint32_t(first - begin), std::uint32_t(last - begin)};
        for (auto c = first; c != last; ++c)
            if (chains[*c].size() > depth) candidates.push_back(chains[*c][depth]);
        // Its receivers: r, and r's mesh neighbours for the silhouette test (those e emits for).
        auto consider = [&](PatchId j) {
            if (j != e && !emitsFor(m_scene, e, j)) return;
            const int order = receiverOrder(node, radius, cone, j);
            if (order < 0) return;
            ws.receivers.push_back(j);
            ws.orders.push_back(static_cast<std::uint16_t>(order));
        };
        consider(r);
        if (m_settings.visibility)  // statuses matter only with shadow rays
            for (std::uint32_t n = m_geometry.neighbourStart[r]; n < m_geometry.neighbourStart[r + 1]; ++n)
                if (m_geometry.neighbours[n] != r) consider(m_geometry.neighbours[n]);
    };
    inChainOrder(e, std::numeric_limits<std::size_t>::max(), roots, expand, ws);
    ws.used.assign(std::size_t(m_orders.highest()) + 1, 0);
    for (std::size_t k = 0; k < ws.receivers.size(); ++k)
        if (ws.receivers[k] == r) ws.used[ws.orders[k]] = 1;
    ws.mine.assign(ws.receivers.size(), 1);
    for (int order = m_lowest; order <= m_orders.highest(); ++order)
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
