// Pairs of rows on two ranks through PETSc's parallel transpose: --enforce-reciprocity and
// --drop-below (shared vectors), and each pair from its emitting row.
#include "mpi/distributed_reciprocity.hpp"

#include "mpi/petsc_rows.hpp"

#include <mpi.h>

#include <algorithm>
#include <utility>

namespace hemirad::mpi {
namespace {

/// The rows of S = (G + G^T) / 2 this rank holds (layout.mine), merged by column as
/// enforceReciprocity merges them in one process. With `cut` (per patch, dropCut), pairs whose
/// entries are both below their rows' cuts are left out as dropBelow leaves them out, their weight
/// per held row into `droppedWeight`.
SymmetricRows symmetricRows(const Scene& scene, const DistributedFormFactors& F, const Layout& layout,
                            const std::vector<double>* cut = nullptr, std::vector<double>* droppedWeight = nullptr) {
    const std::size_t n = scene.size();
    // Row j of G holds A_j F_jk, computed as one process computes it; row i of G^T is column i of G.
    OwnedMat Gt;
    {
        OwnedMat G(areaWeightedRows(scene, F, layout, preallocationOf(F, layout)));
        check(MatTranspose(G.mat, MAT_INITIAL_MATRIX, &Gt.mat), "MatTranspose");
    }
    std::vector<PatchId> patchOf(n);
    for (std::size_t i = 0; i < n; ++i) patchOf[std::size_t(layout.perm[i])] = PatchId(i);

    SymmetricRows S;
    S.scales.resize(n);
    for (std::size_t i = 0; i < n; ++i) S.scales[i] = F.owner[i] >= 0;
    std::vector<std::pair<PatchId, double>> column;  // (j, A_j F_ji) for this row i, by j
    for (std::size_t k = 0; k < layout.mine.size(); ++k) {
        const PatchId i = layout.mine[k];
        const bool computed = F.owner[i] >= 0;
        if (computed) {
            PetscInt count = 0;
            const PetscInt* columns = nullptr;
            const PetscScalar* values = nullptr;
            const PetscInt row = layout.begin + PetscInt(k);
            check(MatGetRow(Gt.mat, row, &count, &columns, &values), "MatGetRow");
            column.clear();
            for (PetscInt t = 0; t < count; ++t) column.emplace_back(patchOf[std::size_t(columns[t])], double(values[t]));
            check(MatRestoreRow(Gt.mat, row, &count, &columns, &values), "MatRestoreRow");
            std::sort(column.begin(), column.end());
            const double Ai = scene.patches[i].area;
            std::uint64_t a = F.local.rowBegin(i);
            const std::uint64_t aEnd = F.local.rowEnd(i);
            std::size_t b = 0;
            while (a < aEnd || b < column.size()) {
                const std::uint32_t ja = a < aEnd ? F.local.columns()[a] : UINT32_MAX;
                const std::uint32_t jb = b < column.size() ? column[b].first : UINT32_MAX;
                const std::uint32_t j = std::min(ja, jb);
                const double fij = ja == j ? double(F.local.values()[a++]) : 0.0;
                const double ajfji = jb == j ? column[b++].second : 0.0;
                if (cut && j != i && F.owner[j] >= 0 && !keptFromDropping(scene, i, j)) {
                    // As one process tests it (droppedPair): each side weighed by its area, the
                    // product G^T holds for F_ji (A_j times F_ji).
                    if (droppedPair(Ai * fij, Ai * (*cut)[i], ajfji, scene.patches[j].area * (*cut)[j])) {
                        if (droppedWeight) (*droppedWeight)[i] += fij;
                        continue;
                    }
                }
                S.add(j, SymmetricRows::pairMean(i, j, Ai, fij, ajfji, F.owner[j] >= 0));
            }
        }
        S.endRow(i, computed, computed ? F.local.rowSum(i) : 0.0);
    }
    return S;
}

/// Shares vectors of patch length: each rank's entries for layout.mine, gathered in PETSc's numbering.
class VectorSharing {
public:
    explicit VectorSharing(const Layout& layout) : m_layout(layout) {
        int size = 0;
        MPI_Comm_size(MPI_COMM_WORLD, &size);
        const int mine = int(layout.mine.size());
        m_counts.resize(std::size_t(size));
        MPI_Allgather(&mine, 1, MPI_INT, m_counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
        m_offsets.assign(std::size_t(size), 0);
        for (std::size_t r = 1; r < m_offsets.size(); ++r) m_offsets[r] = m_offsets[r - 1] + m_counts[r - 1];
        m_send.resize(layout.mine.size());
        m_gathered.resize(layout.perm.size());
    }

    void share(std::vector<double>& full) {
        for (std::size_t k = 0; k < m_layout.mine.size(); ++k) m_send[k] = full[m_layout.mine[k]];
        MPI_Allgatherv(m_send.data(), int(m_send.size()), MPI_DOUBLE, m_gathered.data(), m_counts.data(),
                       m_offsets.data(), MPI_DOUBLE, MPI_COMM_WORLD);
        for (std::size_t i = 0; i < full.size(); ++i) full[i] = m_gathered[std::size_t(m_layout.perm[i])];
    }

private:
    const Layout& m_layout;
    std::vector<int> m_counts, m_offsets;
    std::vector<double> m_send, m_gathered;
};

double maxOverRanks(double value) {
    double out = 0.0;
    MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return out;
}

/// The closure of S over the ranks into F.local (see enforceReciprocityDistributed).
ReciprocityReport closeDistributed(const Scene& scene, const SymmetricRows& S, const Layout& layout, VectorSharing& sharing,
                                   DistributedFormFactors& F) {
    const std::size_t n = scene.size();
    const RowExchange exchange{[&](std::vector<double>& v) { sharing.share(v); }, maxOverRanks};

    ReciprocityReport report;
    // Every computed row near 1 on every rank: the maximum of "not near" is 0.
    chooseTargets(scene, maxOverRanks(estimatedNearOne(S) ? 0.0 : 1.0) == 0.0, report);
    const std::vector<double> x = closureScaling(scene, S, report.closedTargets, exchange, report);
    std::vector<std::vector<FormFactors::Entry>> held = closedRows(scene, S, x, F.local, report);

    std::vector<std::vector<FormFactors::Entry>> rows(n);
    for (std::size_t k = 0; k < layout.mine.size(); ++k) rows[layout.mine[k]] = std::move(held[k]);
    FormFactors updated = FormFactors::fromRows(std::move(rows), F.local.computedFlags());
    updated.sceneHash = F.local.sceneHash;
    updated.provenance = F.local.provenance;
    updated.parameters = F.local.parameters;
    updated.parameters["reciprocity"] =
        report.closedTargets ? "enforced, rows closed to 1" : "enforced, estimated row sums kept";
    F.local = std::move(updated);
    // Totals over the ranks, for the one report line.
    std::uint64_t changed = report.changed, total = 0;
    MPI_Allreduce(&changed, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    report.changed = std::size_t(total);
    report.largestChange = maxOverRanks(report.largestChange);
    return report;
}

std::size_t sumOverRanks(std::size_t value) {
    std::uint64_t mine = value, total = 0;
    MPI_Allreduce(&mine, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    return std::size_t(total);
}

}  // namespace

ReciprocityReport enforceReciprocityDistributed(const Context& context, const Scene& scene, DistributedFormFactors& F) {
    const Layout layout = layoutOf(context, F.owner);
    VectorSharing sharing(layout);
    return closeDistributed(scene, symmetricRows(scene, F, layout), layout, sharing, F);
}

SparsifyReport dropBelowDistributed(const Context& context, const Scene& scene, DistributedFormFactors& F, double threshold) {
    SparsifyReport report;
    report.threshold = threshold;
    report.nonzerosBefore = sumOverRanks(F.local.nonZeros());
    report.bytesBefore = sumOverRanks(F.local.memoryBytes());
    const Layout layout = layoutOf(context, F.owner);
    VectorSharing sharing(layout);
    // Each row's cut, shared: a pair's test reads both rows'.
    std::vector<double> cut(scene.size(), 0.0), dropped(scene.size(), 0.0);
    std::vector<double> scratch;
    for (const PatchId i : layout.mine)
        cut[i] = dropCut(F.local.values() + F.local.rowBegin(i), F.local.rowEnd(i) - F.local.rowBegin(i), threshold, scratch);
    sharing.share(cut);
    const SymmetricRows S = symmetricRows(scene, F, layout, &cut, &dropped);
    for (const double w : dropped) report.largestDroppedRow = std::max(report.largestDroppedRow, w);
    report.largestDroppedRow = maxOverRanks(report.largestDroppedRow);
    report.closure = closeDistributed(scene, S, layout, sharing, F);
    report.nonzerosAfter = sumOverRanks(F.local.nonZeros());
    report.bytesAfter = sumOverRanks(F.local.memoryBytes());
    markSparsified(F.local, report);
    return report;
}

EmittedPairsReport takePairsFromEmittersDistributed(const Context& context, const Scene& scene, DistributedFormFactors& F) {
    const std::size_t n = scene.size();
    const Layout layout = layoutOf(context, F.owner);
    OwnedMat Gt;
    {
        OwnedMat G(areaWeightedRows(scene, F, layout, preallocationOf(F, layout)));
        check(MatTranspose(G.mat, MAT_INITIAL_MATRIX, &Gt.mat), "MatTranspose");
    }
    std::vector<PatchId> patchOf(n);
    for (std::size_t i = 0; i < n; ++i) patchOf[std::size_t(layout.perm[i])] = PatchId(i);
    const auto fromEmitter = [&](PatchId e, PatchId r) { return e != r && emitsFor(scene, e, r) && F.owner[e] >= 0; };

    EmittedPairsReport report;
    std::vector<std::vector<FormFactors::Entry>> rows(n);
    std::vector<std::pair<PatchId, double>> column;  // (e, A_e F_er) for this row r, by e
    for (std::size_t k = 0; k < layout.mine.size(); ++k) {
        const PatchId r = layout.mine[k];
        if (F.owner[r] != context.rank()) continue;
        PetscInt count = 0;
        const PetscInt* columns = nullptr;
        const PetscScalar* values = nullptr;
        const PetscInt row = layout.begin + PetscInt(k);
        check(MatGetRow(Gt.mat, row, &count, &columns, &values), "MatGetRow");
        column.clear();
        for (PetscInt t = 0; t < count; ++t) column.emplace_back(patchOf[std::size_t(columns[t])], double(values[t]));
        check(MatRestoreRow(Gt.mat, row, &count, &columns, &values), "MatRestoreRow");
        std::sort(column.begin(), column.end());
        // Row r's own entries merged with its emitters' (as takePairsFromEmitters sets them).
        std::vector<FormFactors::Entry>& out = rows[r];
        std::uint64_t a = F.local.rowBegin(r);
        const std::uint64_t aEnd = F.local.rowEnd(r);
        std::size_t b = 0;
        while (a < aEnd || b < column.size()) {
            const PatchId ja = a < aEnd ? F.local.columns()[a] : UINT32_MAX;
            const PatchId jb = b < column.size() ? column[b].first : UINT32_MAX;
            const PatchId j = std::min(ja, jb);
            const bool own = ja == j;
            const double mine = own ? F.local.values()[a++] : 0.0;
            const double emitted = jb == j ? column[b++].second : 0.0;
            if (!fromEmitter(j, r)) {
                if (own) out.push_back({j, mine});
                continue;
            }
            const double value = emitted / scene.patches[r].area;
            if (!own && !(value > 0.0)) continue;
            const double change = std::abs(value - mine);
            ++report.pairs;
            if (change > 1e-12 * std::max(value, mine)) ++report.changed;
            report.largestChange = std::max(report.largestChange, change);
            if (value > 0.0) {
                if (!own) ++report.added;
                out.push_back({j, value});
            } else if (own) {
                ++report.removed;
            }
        }
    }
    FormFactors updated = FormFactors::fromRows(std::move(rows), F.local.computedFlags());
    updated.sceneHash = F.local.sceneHash;
    updated.provenance = F.local.provenance;
    updated.parameters = F.local.parameters;
    F.local = std::move(updated);
    scaleRowsAboveBound(F.local, report);  // each rank's own rows, as one process scales them
    std::uint64_t mine[5] = {report.pairs, report.changed, report.added, report.removed, report.rescaledRows}, total[5];
    MPI_Allreduce(mine, total, 5, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    report.pairs = total[0], report.changed = total[1], report.added = total[2], report.removed = total[3];
    report.rescaledRows = total[4];
    report.largestChange = maxOverRanks(report.largestChange);
    report.largestRowSum = maxOverRanks(report.largestRowSum);
    return report;
}

}  // namespace hemirad::mpi
