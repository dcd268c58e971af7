// Chains of reflectors per emitter: a conservative cone per chain finds its receivers and next
// reflectors in the ball trees; one traversal (inChainOrder) fixes the order of the nodes.
#include "preprocess/hemisphere/reflector_chains.hpp"

#include "engine/error.hpp"
#include "preprocess/hemisphere/pair_exchange.hpp"

#include <algorithm>
#include <limits>
#include <string>

namespace hemirad {

ReflectorChains::ReflectorChains(const Scene& scene, const PatchGeometry& geometry, std::vector<Reflector> reflectors,
                                 const MirrorChainLimits& limits, const EmitterOrders& orders, std::size_t maxChains)
    : m_scene(scene), m_geometry(geometry), m_reflectors(std::move(reflectors)), m_limits(limits), m_orders(orders),
      m_maxChains(maxChains), m_flat(1e-9 * scene.extent()) {
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

ChainNode ReflectorChains::makeNode(const std::vector<ChainNode>& nodes, std::int32_t parent, std::uint32_t k,
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
    ChainNode node{parent, k, depth, weight, reflectPoint(m_reflectors[k], from)};
    node.cutoff = depth > m_limits.maxDepth || weight < m_limits.minWeight;
    return node;
}

bool ReflectorChains::seesFromEmitter(const PatchShape& e, std::uint32_t k) const {
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

bool ReflectorChains::reaches(const ChainNode& node, double r, const BallCone& cone, std::uint32_t k) const {
    const Reflector& next = m_reflectors[k];
    if (k == node.reflector || !partlyInFront(m_reflectors[node.reflector], next.polygon)) return false;
    if (next.normal.dot(node.image) - next.offset <= -r) return false;
    return cone.meets(next.centre, next.radius);
}

int ReflectorChains::receiverOrder(const ChainNode& node, double r, const BallCone& cone, PatchId j) const {
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
// that is, the chains by length, then lexicographically by reflector. MirrorImages::evaluate adds
// a receiver's terms per rule, per emitter point, per node in node order, so a pair recomputed
// from its emitter along some of its chains (enumerateToward) sums them in the very order of the
// emitting row (enumerate), equal bit for bit, because both build their nodes here with the same
// checks (seesFromEmitter, reaches, makeNode's cut-offs; the ball trees only skip what these would
// refuse). Only the candidates differ: roots(candidates) appends the first reflectors to try,
// expand(q, node, cone, candidates) node q's receivers (to out.receivers and out.orders) and the
// next reflectors to try, both in any order, repeats allowed.
template <class Roots, class Expand>
void ReflectorChains::inChainOrder(PatchId i, std::size_t maxNodes, Roots roots, Expand expand, EmitterChains& out) const {
    const PatchShape& e = m_geometry.shapes[i];
    const double r = e.radius;
    out.nodes.clear();
    out.receivers.clear();
    out.orders.clear();
    // The candidates by index, each once, those that pass `keep` made nodes from `parent`.
    auto push = [&](std::int32_t parent, const Vec3& from, auto keep) {
        std::sort(out.next.begin(), out.next.end());
        out.next.erase(std::unique(out.next.begin(), out.next.end()), out.next.end());
        for (const std::uint32_t k : out.next) {
            if (!keep(k)) continue;
            if (out.nodes.size() >= maxNodes)
                throw Error("mirror images: patch " + std::to_string(i) + " sees more than " + std::to_string(maxNodes) +
                            " chains of mirrors; lower --max-depth or raise --min-weight, or use --mirror-estimator rays");
            out.nodes.push_back(makeNode(out.nodes, parent, k, from));
        }
    };
    out.next.clear();
    roots(out.next);
    push(-1, e.centroid, [&](std::uint32_t k) { return seesFromEmitter(e, k); });
    for (std::size_t q = 0; q < out.nodes.size(); ++q) {
        if (out.nodes[q].cutoff) continue;
        const ChainNode node = out.nodes[q];
        const Reflector& m = m_reflectors[node.reflector];
        const BallCone cone(node.image, r, m.centre, m.radius);
        out.nodes[q].first = static_cast<std::uint32_t>(out.receivers.size());
        out.next.clear();
        expand(q, node, cone, out.next);
        out.nodes[q].count = static_cast<std::uint32_t>(out.receivers.size()) - out.nodes[q].first;
        push(std::int32_t(q), node.image, [&](std::uint32_t k) { return reaches(node, r, cone, k); });
    }
}

void ReflectorChains::enumerate(PatchId i, EmitterChains& out) const {
    const double r = m_geometry.shapes[i].radius;
    auto roots = [&](std::vector<std::uint32_t>& candidates) {
        for (std::uint32_t k = 0; k < m_reflectors.size(); ++k) candidates.push_back(k);
    };
    auto expand = [&](std::size_t, const ChainNode& node, const BallCone& cone, std::vector<std::uint32_t>& candidates) {
        // Balls wholly behind the mirror or off the cone hold no receiver and no next reflector.
        const Reflector& m = m_reflectors[node.reflector];
        auto ahead = [&](const Vec3& c, double radius) {
            return m.normal.dot(c) - m.offset > -radius && cone.meets(c, radius);
        };
        m_patchTree.query(out.stack, ahead, [&](std::uint32_t j) {
            const int order = receiverOrder(node, r, cone, j);
            if (order < 0) return;
            out.receivers.push_back(j);
            out.orders.push_back(static_cast<std::uint16_t>(order));
        });
        m_reflectorTree.query(out.stack, ahead, [&](std::uint32_t k) { candidates.push_back(k); });
    };
    inChainOrder(i, m_maxChains, roots, expand, out);
}

void ReflectorChains::enumerateToward(PatchId e, PatchId r, const std::vector<std::vector<std::uint32_t>>& chains,
                                      bool neighbours, EmitterChains& out) const {
    // The chains sorted lexicographically: those through a node are a run of them (out.spans).
    out.ranked.resize(chains.size());
    for (std::uint32_t c = 0; c < chains.size(); ++c) out.ranked[c] = c;
    std::sort(out.ranked.begin(), out.ranked.end(), [&](std::uint32_t a, std::uint32_t b) { return chains[a] < chains[b]; });
    out.spans.clear();
    const double radius = m_geometry.shapes[e].radius;
    auto roots = [&](std::vector<std::uint32_t>& candidates) {
        for (const std::vector<std::uint32_t>& chain : chains) candidates.push_back(chain[0]);
    };
    auto expand = [&](std::size_t q, const ChainNode& node, const BallCone& cone, std::vector<std::uint32_t>& candidates) {
        // The parent's run narrowed to the chains whose reflector at depth - 1 is this node's.
        const std::size_t depth = node.depth;
        const auto begin = out.ranked.begin();
        auto first = begin, last = out.ranked.end();
        if (node.parent >= 0) {
            first = begin + out.spans[std::size_t(node.parent)].first;
            last = begin + out.spans[std::size_t(node.parent)].second;
        }
        const auto at = [&](std::uint32_t c) { return chains[c].size() < depth ? -1 : std::int64_t(chains[c][depth - 1]); };
        const std::int64_t k = node.reflector;
        first = std::partition_point(first, last, [&](std::uint32_t c) { return at(c) < k; });
        last = std::partition_point(first, last, [&](std::uint32_t c) { return at(c) == k; });
        if (out.spans.size() <= q) out.spans.resize(q + 1);
        out.spans[q] = {std::uint32_t(first - begin), std::uint32_t(last - begin)};
        for (auto c = first; c != last; ++c)
            if (chains[*c].size() > depth) candidates.push_back(chains[*c][depth]);
        // Its receivers: r, and r's mesh neighbours (those e emits for).
        auto consider = [&](PatchId j) {
            if (j != e && !emitsFor(m_scene, e, j)) return;
            const int order = receiverOrder(node, radius, cone, j);
            if (order < 0) return;
            out.receivers.push_back(j);
            out.orders.push_back(static_cast<std::uint16_t>(order));
        };
        consider(r);
        if (neighbours)
            for (std::uint32_t n = m_geometry.neighbourStart[r]; n < m_geometry.neighbourStart[r + 1]; ++n)
                if (m_geometry.neighbours[n] != r) consider(m_geometry.neighbours[n]);
    };
    inChainOrder(e, std::numeric_limits<std::size_t>::max(), roots, expand, out);
}

}  // namespace hemirad
