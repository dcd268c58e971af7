// Pairs of patches close to each other (touching or within a few radii): one computation per pair,
// exact where nothing lies between them, adaptive where something does.
#pragma once

#include "preprocess/hemisphere/exchange_area.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/shadow_polygons.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace hemirad {

/// A triangle of a close pair's hidden-part integral: its rule's value, its four children's, and
/// their disagreement (the error estimate by which the next triangle to split is chosen).
struct ContactCell {
    std::array<Vec3, 3> corner;
    double coarse = 0.0;
    std::array<double, 4> child{};
    double fine = 0.0, error = 0.0;
    bool rim = false;  ///< its rim had a view none of its rule's points had (or, for a far pair, a hidden part well beyond theirs): its children's rims are evaluated
};

/// A close pair's exchange area A_e F_er as a function of the pair alone, so that whichever row,
/// thread or rank meets it computes the same bits (the rows of a pair agree without being told):
///   - the unoccluded part exactly, by the double contour integral (exchange_area.hpp), whatever
///     the contact: shared or partly shared edges, a corner on the other's edge (T-junctions);
///   - nothing more where no patch that can obstruct reaches into the pair's shaft (the convex
///     hull of the parts of e and r in front of each other; Haines & Wallace 1994's shaft culling);
///   - otherwise minus the hidden part, sum over e of (f - visible) with Lambert's factor f and
///     the visible part from shadow polygons at each point, integrated by an adaptive rule over e
///     (a degree-5 seven-point rule on triangles, the one whose four children disagree most with
///     it split next) to kHiddenTolerance of the exact value, within a budget of evaluations.
/// Far pairs keep the analytic estimator's rules: their factor varies slowly over the emitter.
class ContactPairs {
public:
    /// How far the hidden part is refined: until its triangles' disagreements sum below
    /// `tolerance` of the pair's unoccluded value, or below `floor` of F (whichever is larger), or
    /// `budget` visible-part evaluations divided by the blockers in its shaft (each evaluation meets
    /// them all) are spent. Past that budget a pair whose disagreements still sum above `overrun`
    /// of F goes on, up to kBudgetOverrun times it. The disagreement overstates the error: with
    /// the defaults (--pair-digits 2) a touching pair past an occluder comes within 6e-6 relative
    /// (test_contact_pairs.cpp).
    struct Precision {
        double tolerance = 1e-4;
        double floor = 1e-5;
        double overrun = 2e-5;
        std::uint32_t budget = 2500;
    };
    /// For --pair-digits D: tolerance 10^-(D+2), floor 10^-(D+3), overrun twice the floor, budget
    /// 2500 x 10^(D-2) (at most 2^31): two digits past the pair rule's, as the defaults are for D = 2.
    static Precision precisionFor(std::uint32_t pairDigits);
    /// The least evaluations: the first triangle of the emitter's fan, its rule (7 points), its
    /// first split (4 x 7) and its corners and edge midpoints (6).
    static constexpr std::uint32_t kLeastEvaluations = 41;
    /// How many times its budget a pair whose disagreements sum above Precision::overrun may spend.
    /// district1k's ground 264 and wall 580 (8 blockers in their shaft, a budget of 312) stopped
    /// at 3.3e-5 for 1.37e-4, its disagreements at 1.7e-4 of F. With 4 its entries off by more
    /// than 1e-4 went from 4 to 2 and its rows from 38 to 26, for 22 % more visible-part
    /// evaluations (the 60 mm Cornell box 0.6 %, cornell13k 0.4 %: few blockers per shaft there);
    /// with 10, 27 rows; with an overrun of 5e-5 (and 4), 28 rows for 8.5 %.
    static constexpr std::uint32_t kBudgetOverrun = 4;

    struct Scratch {
        ExchangeAreaScratch exchange;
        std::vector<Vec3> emitter, receiver;  // the parts in front of each other
        std::vector<Vec3> hullNormals;        // the shaft's planes (inward normals and offsets)
        std::vector<double> hullOffsets;
        std::vector<std::uint32_t> blockers;  // the blockers reaching into the shaft
        std::vector<double> coarse;           // the rule's hidden part per fan triangle
        std::vector<ContactCell> cells;       // the hidden part's triangles, a heap by error
        ShadowPolygons::Scratch shadow;
    };
    /// What the pair took, for the run's report.
    struct Cost {
        std::uint64_t shafts = 0;       ///< pairs whose shaft held a blocker
        std::uint64_t evaluations = 0;  ///< visible-part evaluations of those pairs
    };

    /// The geometry and the blockers (both outlive this); `visibility` false: nothing can obstruct;
    /// `precision`: how far hidden parts are refined (precisionFor(--pair-digits)).
    void build(const PatchGeometry& geometry, const ShadowPolygons& shadows, bool visibility, Precision precision) {
        m_geometry = &geometry;
        m_shadows = &shadows;
        m_visibility = visibility && !shadows.empty();
        m_precision = precision;
    }

    /// A_e F_er (area units of the scene) past the blockers, and in `unoccluded` without them (0: the
    /// pair has no view at all, not even a hidden one). Thread-safe with one Scratch per thread.
    /// `changes`: the hidden part's triangles also count least errors where the view changes
    /// between their points (its rims, its jumps: hidden()), as close pairs need; far pairs
    /// computed whole (across a shadow's edge, in a penumbra) go by the disagreements and their
    /// rims alone (a view the points lack, a hidden part beyond theirs).
    double exchange(PatchId e, PatchId r, Scratch& s, Cost& cost, double& unoccluded, bool changes = true) const;

private:
    /// The hidden part of the exchange, sum over the emitter part of (f - visible).
    double hidden(PatchId e, PatchId r, double exact, Scratch& s, Cost& cost, bool changes) const;

    const PatchGeometry* m_geometry = nullptr;
    const ShadowPolygons* m_shadows = nullptr;
    bool m_visibility = false;
    Precision m_precision;
};

}  // namespace hemirad
