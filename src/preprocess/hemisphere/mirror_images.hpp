// Extended form factors through planar mirrors by virtual images: the analytic estimator's mirror
// terms, exact per emitter point where the rays were Monte Carlo.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemisphere/pair_exchange.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/reflector_chains.hpp"
#include "preprocess/hemisphere/reflectors.hpp"
#include "preprocess/row_accumulator.hpp"
#include "rays/mirror_chain.hpp"
#include "rays/ray_scene.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hemirad {

/// One node of a chain of reflectors as appendReflectedPath walks it back: its mirror, its image of
/// the source and its parent (-1: reflected straight from the source).
struct ChainLink {
    const Reflector* mirror;
    const Vec3* image;
    std::int32_t parent;
};

/// The legs of the path reflected from `source` to `target` through the chain that ends at `node`,
/// appended to `from` / `to` (ray-scene coordinates, each end lifted along its normal): back along
/// the chain, the leg into an end starts where the line from the node's image to that end crosses
/// the node's mirror. link(q) gives node q's ChainLink.
template <class Link>
void appendReflectedPath(const RayScene& rays, std::int32_t node, Link link, const Vec3& source, const Vec3& sourceNormal,
                         const Vec3& target, const Vec3& targetNormal, std::vector<float>& from, std::vector<float>& to) {
    const double offset = rays.originOffset();
    auto leg = [&](const Vec3& a, const Vec3& aNormal, const Vec3& b, const Vec3& bNormal) {
        float la[3], lb[3];
        rays.toLocal(a + offset * aNormal, la);
        rays.toLocal(b + offset * bNormal, lb);
        from.insert(from.end(), la, la + 3);
        to.insert(to.end(), lb, lb + 3);
    };
    Vec3 end = target, endNormal = targetNormal;
    for (std::int32_t q = node; q >= 0;) {
        const ChainLink l = link(q);
        const Reflector& m = *l.mirror;
        const Vec3& image = *l.image;
        const double along = (m.offset - m.normal.dot(image)) / m.normal.dot(end - image);
        const Vec3 onMirror = image + along * (end - image);
        leg(onMirror, m.normal, end, endNormal);
        end = onMirror;
        endNormal = m.normal;
        q = l.parent;
    }
    leg(source, sourceNormal, end, endNormal);
}

/// For each point x of the emitter and each reflector m in front of it, x and the emitter's normal
/// are reflected about m's plane; a receiver seen through m's aperture gets Lambert's exact factor
/// from the image of the part of it inside the aperture's cone, times s_m; the cone's part on a
/// further reflector is the next aperture (chains to --max-depth, or until the product of the s met
/// falls below --min-weight, the power still travelling reported as cut off). Shadow rays follow
/// the reflected path leg by leg where some patch can obstruct. The emitter rule is chosen per
/// receiver and chain from the distance of the receiver to the emitter's image (emitter_rule.hpp).
///
/// A path through mirrors and its reverse are one pair: the pair's emitting patch (pair_exchange.hpp)
/// sums its terms through every chain toward the receiver, and the receiver's row takes that sum,
/// scaled by the areas, through an exchange of its own: handed over when the emitting row finished
/// first, else recomputed from the emitter's side along the reversed chains by which this row sees
/// the emitter, equal bit for bit. The image terms are reciprocal to F's rounding.
class MirrorImages {
public:
    struct Settings {
        MirrorChainLimits limits;
        bool visibility = true;   ///< cast shadow rays (false where no patch can obstruct)
        std::uint32_t origins = 1;  ///< --origins: the lowest emitter rule
        double tolerance = 1e-7;  ///< estimated relative error per (chain, receiver) for the rule
        std::size_t maxChains = 200000;  ///< per row; more is refused with advice
    };

    /// Per-thread scratch.
    struct Workspace {
        EmitterChains chains;               // the row's emitter's chains (its own, or a pair's)
        std::vector<std::uint8_t> used;     // per order: some receiver takes that rule
        // Per emitter point: each node's image of the point and of the normal, and its aperture.
        std::vector<Vec3> apex, axis;
        std::vector<std::vector<Vec3>> apertures;
        std::vector<std::uint8_t> alive;
        std::vector<Vec3> points, clipped, scratch, pieces;
        // One node's receivers at one point: factor and shadow-ray verdict; statuses per patch.
        std::vector<PatchId> batch;
        std::vector<double> factors;
        std::vector<std::uint8_t> blocked, status;
        std::vector<float> legFrom, legTo;      // the batch's path legs
        std::vector<std::uint8_t> legBlocked;
        std::vector<std::uint32_t> legStart;    // per batch receiver: its first leg
        std::vector<double> weights;
        // The pairs: per (node, receiver) entry whether this row computes it; per patch this row's
        // terms (ray units, `summed` marks them); the exchange's entries for and from this row.
        std::vector<std::uint8_t> mine, summed;
        std::vector<double> sums;
        std::vector<PatchId> touched;
        std::vector<double> published;
        std::vector<PairExchange::Entry> taken, outgoing;
        std::vector<std::pair<PatchId, std::uint32_t>> pending;  // (emitter, this row's node seeing it)
        std::vector<std::vector<std::uint32_t>> reversed;        // an emitter's chains toward this row, from its side
        std::unique_ptr<Workspace> pair;  // a pair recomputed from its emitter
    };

    MirrorImages(const Scene& scene, const PatchGeometry& geometry, std::vector<Reflector> reflectors,
                 const RayScene& rays, const Settings& settings);
    ~MirrorImages();

    /// Adds row i's factors through every chain of reflectors to `row`, `unit` per unit of F: the
    /// pairs i emits for from i's points (published to `exchange`), the others handed over or
    /// recomputed from their emitter.
    void addRow(PatchId i, RowAccumulator& row, double unit, PairExchange& exchange, Workspace& ws,
                RayCounts& counts) const;

    std::unique_ptr<Workspace> workspace() const;
    std::size_t reflectorCount() const { return m_chains.size(); }

private:
    static constexpr PatchId kEveryReceiver = ~PatchId(0);
    /// Adds the terms from emitter i's points of `order` to ws.sums (every receiver marked mine, or
    /// `only`); the power cut off is counted for every receiver's pass only (the row's own).
    void evaluate(PatchId i, int order, PatchId only, double unit, Workspace& ws, RayCounts& counts) const;
    /// Emitter i's terms for the receivers it emits for (and itself) into ws.sums / ws.touched.
    void ownTerms(PatchId i, double unit, Workspace& ws, RayCounts& counts) const;
    /// ws.sums added to `row` and as the entries the exchange hands over (ws.outgoing); clears them.
    void collect(PatchId i, RowAccumulator& row, double unit, Workspace& ws) const;
    /// Emitter e's terms for receiver r (ray units), as row e sums them, along the chains in
    /// `from.reversed` (each from e's side); `ws` is scratch.
    double pairTerms(PatchId e, PatchId r, const Workspace& from, double unit, Workspace& ws, RayCounts& counts) const;
    void addTerm(PatchId j, double value, Workspace& ws) const {
        if (!ws.summed[j]) {
            ws.summed[j] = 1;
            ws.sums[j] = 0.0;
            ws.touched.push_back(j);
        }
        ws.sums[j] += value;
    }
    /// The legs of the reflected path from the emitter point to `target` through node's chain,
    /// appended to ws.legFrom / ws.legTo (ray-scene coordinates, lifted off their surfaces).
    void appendPath(std::size_t node, const Vec3& emitterPoint, const Vec3& emitterNormal, const Vec3& target,
                    const Vec3& targetNormal, Workspace& ws) const;
    /// Casts the appended legs into ws.legBlocked and clears them.
    void castPaths(Workspace& ws, RayCounts& counts) const;
    bool pathBlocked(std::size_t node, const Vec3& emitterPoint, const Vec3& emitterNormal, const Vec3& target,
                     const Vec3& targetNormal, Workspace& ws, RayCounts& counts) const;
    /// Receiver j's part seen through node q's aperture (into ws.clipped); false when empty.
    bool clipReceiver(std::size_t q, PatchId j, Workspace& ws) const;

    const Scene& m_scene;
    const PatchGeometry& m_geometry;
    ReflectorChains m_chains;
    const RayScene& m_rays;
    Settings m_settings;
    int m_lowest;  ///< the lowest emitter rule, run for every row (it counts what is cut off)
    std::vector<std::vector<double>> m_ruleNodes, m_ruleWeights;  ///< Gauss-Legendre per order
    double m_flat;  ///< 1e-9 of the scene's size: nearer a plane than this is on it
};

}  // namespace hemirad
