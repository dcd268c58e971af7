// An emitter's chains of reflectors, found in the one order that both rows of a pair through mirrors
// follow, each with the receivers seen through it and their emitter rule.
#pragma once

#include "preprocess/hemisphere/ball_tree.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/reflectors.hpp"
#include "rays/mirror_chain.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace hemirad {

/// A chain of reflectors ending at `reflector`, enumerated per emitter.
struct ChainNode {
    std::int32_t parent;        ///< -1: reflected straight from the emitter
    std::uint32_t reflector;
    std::uint32_t depth;
    double weight;              ///< product of the s met, this reflector's included
    Vec3 image;                 ///< the emitter's centroid reflected along the chain
    std::uint32_t first = 0, count = 0;  ///< receivers in EmitterChains::receivers
    bool cutoff = false;        ///< past --max-depth or --min-weight: only the power reaching it is counted
};

/// An emitter's chains: a tree of nodes (parents first) in the chain order (reflector_chains.cpp),
/// each with its receivers. Per thread.
struct EmitterChains {
    std::vector<ChainNode> nodes;
    std::vector<PatchId> receivers;
    std::vector<std::uint16_t> orders;  ///< emitter rule per (node, receiver): up to 256 (--origins 65536)
    // Scratch: balls still to visit, a node's next reflectors to try; a pair's chains sorted, and per
    // node its run of them.
    std::vector<std::uint32_t> stack, next, ranked;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> spans;
};

/// The scene's reflectors, with ball trees over them and over the patches: a chain goes on to the
/// reflectors its cone can reach, to --max-depth or until the product of the s met falls below
/// --min-weight (the node that passes a limit is kept, cut off). Thread-safe after construction.
class ReflectorChains {
public:
    ReflectorChains(const Scene& scene, const PatchGeometry& geometry, std::vector<Reflector> reflectors,
                    const MirrorChainLimits& limits, const EmitterOrders& orders, std::size_t maxChains);

    /// Every chain from emitter i, with every receiver seen through it. More than `maxChains` nodes
    /// throw hemirad::Error with advice.
    void enumerate(PatchId i, EmitterChains& out) const;
    /// Emitter e's chains among `chains` (each a list of reflectors from e's side): the nodes
    /// enumerate(e) makes on them, in its order, with receiver r alone (and r's mesh neighbours
    /// that e emits for, with `neighbours`).
    void enumerateToward(PatchId e, PatchId r, const std::vector<std::vector<std::uint32_t>>& chains, bool neighbours,
                         EmitterChains& out) const;

    const Reflector& reflector(std::uint32_t k) const { return m_reflectors[k]; }
    std::size_t size() const { return m_reflectors.size(); }
    const EmitterOrders& orders() const { return m_orders; }

private:
    /// Emitter i's chains in the chain order (at its definition) into `out`; `roots` and `expand`
    /// name the reflectors and receivers to try.
    template <class Roots, class Expand>
    void inChainOrder(PatchId i, std::size_t maxNodes, Roots roots, Expand expand, EmitterChains& out) const;
    /// Whether emitter e can see reflector k at the root of a chain.
    bool seesFromEmitter(const PatchShape& e, std::uint32_t k) const;
    /// Whether the chain ending at `node` (its cone) can reach reflector k next.
    bool reaches(const ChainNode& node, double r, const BallCone& cone, std::uint32_t k) const;
    /// The node from `parent` in `nodes` (-1: the emitter) through reflector k; `from` is the
    /// parent's image (the emitter's centroid at the root).
    ChainNode makeNode(const std::vector<ChainNode>& nodes, std::int32_t parent, std::uint32_t k, const Vec3& from) const;
    /// Receiver j's rule order through `node` when j can be seen through it, else -1.
    int receiverOrder(const ChainNode& node, double r, const BallCone& cone, PatchId j) const;

    const Scene& m_scene;
    const PatchGeometry& m_geometry;
    std::vector<Reflector> m_reflectors;
    BallTree m_patchTree, m_reflectorTree;
    MirrorChainLimits m_limits;
    EmitterOrders m_orders;  ///< per (chain, receiver), from the distance to the emitter's image
    std::size_t m_maxChains;
    double m_flat;  ///< 1e-9 of the scene's size: nearer a plane than this is on it
};

}  // namespace hemirad
