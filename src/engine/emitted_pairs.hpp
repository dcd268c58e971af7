// Pairs of F computed once: which patch of a pair computes it, and F's entries of the other patch
// taken from that computation (A_i F_ij = A_j F_ji to rounding, 1e-16 relative).
#pragma once

#include "engine/form_factors.hpp"
#include "engine/scene.hpp"

#include <cstddef>

namespace hemirad {

/// Which patch of a pair computes it (the analytic estimator's emitting patch): the smaller one,
/// then the lower index.
inline bool emitsFor(const Scene& scene, PatchId e, PatchId r) {
    const double a = scene.patches[e].area, b = scene.patches[r].area;
    return a < b || (a == b && e < r);
}

/// What takePairsFromEmitters changed.
struct EmittedPairsReport {
    std::size_t pairs = 0;     ///< receiver entries set from their emitting row (changed or not)
    std::size_t changed = 0;   ///< of those, entries that changed beyond rounding (1e-12 relative)
    std::size_t added = 0;     ///< entries the receiver's row lacked
    std::size_t removed = 0;   ///< entries the emitting row has not
    double largestChange = 0;  ///< the largest |change| of an entry (F units)
    std::size_t rescaledRows = 0;  ///< rows above the bound afterwards, scaled to it
    double largestRowSum = 0;      ///< the largest of those rows' sums before scaling
};

/// Rows whose sum exceeds F's row-sum bound by more than this are scaled to the bound (as the
/// analytic estimator scales its own rows): a receiver row that takes its emitters' values may
/// otherwise carry their visibility errors past what F files accept.
constexpr double kRowSumExcess = 1e-3;

/// For every pair (e, r) with emitsFor(e, r) whose rows were both computed: F_re = A_e F_er / A_r, so
/// that each pair's value is the one its emitting row computed, whichever row met it first, on any
/// thread (the analytic estimator's rows agree bit for bit where both rows evaluated the pair alike;
/// where one row split a receiver on a silhouette and the other did not, the emitting row's value
/// stands). Rows whose emitting partner was not computed keep their own value. Then rows summing
/// above F.provenance.rowSumBound + kRowSumExcess are scaled to the bound (their pairs' reciprocity
/// gives way there: counted in the report). Threads: OpenMP.
EmittedPairsReport takePairsFromEmitters(FormFactors& F, const Scene& scene);

/// The scaling's part: rows of F (those computed) above F.provenance.rowSumBound + kRowSumExcess
/// scaled to the bound, each sum taken in column order. Into `report`.
void scaleRowsAboveBound(FormFactors& F, EmittedPairsReport& report);

}  // namespace hemirad
