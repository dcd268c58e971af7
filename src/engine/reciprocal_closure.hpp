// --enforce-reciprocity that keeps closure: G = diag(A) F made symmetric, then scaled symmetrically
// (G'_ij = x_i S_ij x_j, S the pair means) so that every row reaches its target sum. One algorithm
// for one process and for MPI ranks: a process holds some rows, vectors are shared in full.
#pragma once

#include "engine/form_factors.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hemirad {

/// The rows of S = (G + G^T) / 2 one process holds, G = diag(A) F; every entry in the order of its
/// column, in double as F is (12 bytes per nonzero with the columns). An entry whose column's row
/// was not computed is fixed: it holds F_ij itself and is kept.
struct SymmetricRows {
    std::vector<PatchId> rows;            ///< the patches whose rows this process holds
    std::vector<std::uint8_t> computed;   ///< per held row: F's row was computed
    std::vector<double> estimated;        ///< per held row: its sum in F as estimated
    std::vector<std::uint64_t> start{0};  ///< CSR over held rows
    std::vector<std::uint32_t> columns;
    std::vector<double> values;
    std::vector<std::uint8_t> scales;     ///< per patch (all of them): its row was computed

    /// Appends held row i: call add() for its entries, by column, then this.
    void endRow(PatchId i, bool rowComputed, double estimatedSum);
    void add(std::uint32_t j, double value) {
        columns.push_back(j);
        values.push_back(value);
    }
    /// The value of entry e for row i: the pair's mean S_ij, or F_ij where j's row was not computed.
    static double pairMean(std::uint32_t i, std::uint32_t j, double Ai, double fij, double Ajfji, bool jComputed) {
        return j == i ? Ai * fij : jComputed ? 0.5 * (Ai * fij + Ajfji) : fij;
    }
};

/// How the processes that hold the rows talk: `share` completes a vector of patch length from each
/// process's entries for its own rows (nothing to do in one process), `max` is the maximum over
/// processes. Both are collective.
struct RowExchange {
    std::function<void(std::vector<double>&)> share;
    std::function<double(double)> max;
};
RowExchange singleProcess();

/// What the closure did: the targets, how well they were met, what changed.
struct ReciprocityReport {
    bool closedTargets = false;  ///< rows aimed at 1 (a closed scene), else at their estimated sums
    std::string why;             ///< why those targets, for people
    double residual = 0.0;       ///< max |row sum - target| / max(target, 1e-9) over the rows it could aim
    int newtonSteps = 0, cgIterations = 0;
    bool converged = false;
    std::size_t changed = 0;     ///< entries whose value changed (all processes)
    double largestChange = 0.0;  ///< max |F'_ij - F_ij|
};

/// Solves x_i (S x)_i = A_i (t_i - sum of row i's fixed F_ij) for the held rows by Newton's method with
/// conjugate gradients on the symmetric Jacobian (Knight & Ruiz 2013 balance a matrix the same
/// way), t_i = 1 when `closed`, else the row's estimated sum. Rows whose target cannot be reached
/// (nothing to scale, or a target at or below the fixed part) keep x_i = 1. Every reduction runs in
/// one order over the full vector, so any split of the rows over processes gives the same x bit for
/// bit. Returns x for every patch (1 where nobody holds a computed row).
std::vector<double> closureScaling(const Scene& scene, const SymmetricRows& S, bool closed, const RowExchange& exchange,
                                   ReciprocityReport& report);

/// The held rows of F' = diag(A)^-1 diag(x) S diag(x), fixed entries kept (an entry that comes
/// to 0 drops out); rows not computed stay empty. Counts changes into `report`.
std::vector<std::vector<FormFactors::Entry>> closedRows(const Scene& scene, const SymmetricRows& S,
                                                        const std::vector<double>& x, const FormFactors& before,
                                                        ReciprocityReport& report);

/// Whether row targets of 1 are right: no mirrors (extended rows exceed 1), a watertight surface
/// (every patch edge shared by exactly two patches, positions matched within 1e-9 of the scene's
/// size; a T-junction counts as open), and every computed row estimated within 1e-2 of 1.
/// `rowSumsNearOne` is that last test over all processes. Sets report.closedTargets and why.
void chooseTargets(const Scene& scene, bool rowSumsNearOne, ReciprocityReport& report);

/// Whether each patch edge is shared by exactly two patches (see chooseTargets).
bool isWatertight(const Scene& scene);

/// Whether S's computed rows were estimated within 1e-2 of 1 (this process's rows).
bool estimatedNearOne(const SymmetricRows& S);

/// One line for the run's report: targets, residual, steps, entries changed.
std::string describe(const ReciprocityReport& report);

/// --enforce-reciprocity in one process: A_i F_ij = A_j F_ji exactly (to rounding), each row
/// summing to its target (chooseTargets). Rows of F not computed are left as they are.
ReciprocityReport enforceReciprocity(FormFactors& F, const Scene& scene);

/// --drop-below takes from a row at most this fraction of its sum: rows that hold only small entries
/// (a small patch that sees much of the scene) keep most of them, and the closure scales each row by
/// little.
constexpr double kDropBudget = 0.05;

/// --drop-below's cut for one row: its entries below `threshold`, smallest first, while their sum
/// stays within kDropBudget of the row's sum; returns the value below which its entries may go
/// (`threshold` when all of them fit). `scratch` is reused.
double dropCut(const double* values, std::size_t count, double threshold, std::vector<double>& scratch);

/// --drop-below's test of a pair (i, j): both entries below their rows' cuts, each side weighed by
/// its patch's area (A_i F_ij < A_i cut_i, A_j F_ji < A_j cut_j). Rows i and j, in one process or
/// on two MPI ranks (which hold A_j F_ji from the transpose of diag(A) F, not F_ji), then take the
/// same products and agree on the pair, where F_ji < cut_j and A_j F_ji < A_j cut_j can differ for
/// values an ulp apart.
inline bool droppedPair(double aiFij, double aiCutI, double ajFji, double ajCutJ) {
    return aiFij < aiCutI && ajFji < ajCutJ;
}

/// What --drop-below did: F's size before and after, and what the rows lost before rebalancing.
struct SparsifyReport {
    double threshold = 0.0;
    std::size_t nonzerosBefore = 0, nonzerosAfter = 0;
    std::size_t bytesBefore = 0, bytesAfter = 0;
    double largestDroppedRow = 0.0;  ///< the most weight a row lost to dropped entries, before rebalancing
    ReciprocityReport closure;       ///< the rebalancing
};

/// Whether --drop-below must keep the pair (i, j) whatever its entries: one of the two patches emits
/// (E > 0 in some channel). F_ij with E_j > 0 carries row i's power from the light; dropping it and
/// rebalancing the row moved that weight onto other patches (a patch that saw the light through one
/// small entry lost it and 43 % of its B, issue 35 #3).
bool keptFromDropping(const Scene& scene, PatchId i, PatchId j);

/// --drop-below in one process: drops every pair whose entries F_ij and F_ji are both below their
/// rows' cuts (dropCut; entries whose column's row was not computed, and pairs with an emitting
/// patch, keptFromDropping, are kept), then closes the rest as
/// enforceReciprocity does, toward each row's sum before dropping (1 in a closed scene): the dropped
/// weight goes to the row's other entries by symmetric scaling, so rows and reciprocity stay intact.
SparsifyReport dropBelow(FormFactors& F, const Scene& scene, double threshold);

/// One line for the run's report: the sizes, the largest loss, then the closure's line.
std::string describe(const SparsifyReport& report);

/// Records what was dropped in F's parameters ("sparsified": "pairs below EPS dropped ..."), with the
/// totals of `report`; a stored F keeps the record, so that a reuse does not drop again.
void markSparsified(FormFactors& F, const SparsifyReport& report);

/// The EPS F's "sparsified" record names (exactly as dropped), or none when F was not dropped.
std::optional<double> sparsifiedThreshold(const FormFactors& F);

}  // namespace hemirad
