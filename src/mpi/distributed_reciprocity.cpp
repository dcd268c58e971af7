// --enforce-reciprocity across MPI ranks, through PETSc's parallel transpose.
#include "mpi/distributed_reciprocity.hpp"

#include "mpi/petsc_rows.hpp"

#include <mpi.h>

#include <algorithm>
#include <utility>

namespace hemirad::mpi {

std::size_t enforceReciprocityDistributed(const Context& context, const Scene& scene, DistributedFormFactors& F) {
    const std::size_t n = scene.size();
    const Layout layout = layoutOf(context, F.owner);
    const std::size_t m = layout.mine.size();
    // Row j of G holds A_j F_jk, computed as one process computes it; row i of G^T is column i of G.
    OwnedMat Gt;
    {
        OwnedMat G(areaWeightedRows(scene, F, layout, preallocationOf(F, layout)));
        check(MatTranspose(G.mat, MAT_INITIAL_MATRIX, &Gt.mat), "MatTranspose");
    }
    std::vector<PatchId> patchOf(n);
    for (std::size_t i = 0; i < n; ++i) patchOf[std::size_t(layout.perm[i])] = PatchId(i);

    std::vector<std::vector<FormFactors::Entry>> rows(n);
    std::vector<std::pair<PatchId, double>> column;  // (j, A_j F_ji) for this row i, by j
    std::uint64_t changed = 0;
    for (std::size_t k = 0; k < m; ++k) {
        const PatchId i = layout.mine[k];
        if (F.owner[i] != context.rank()) continue;  // rows nobody computed stay empty
        PetscInt count = 0;
        const PetscInt* columns = nullptr;
        const PetscScalar* values = nullptr;
        const PetscInt row = layout.begin + PetscInt(k);
        check(MatGetRow(Gt.mat, row, &count, &columns, &values), "MatGetRow");
        column.clear();
        for (PetscInt t = 0; t < count; ++t) column.emplace_back(patchOf[std::size_t(columns[t])], double(values[t]));
        check(MatRestoreRow(Gt.mat, row, &count, &columns, &values), "MatRestoreRow");
        std::sort(column.begin(), column.end());
        // Row i and column i merged by j, as mergeRowAndColumn walks them in one process.
        const double Ai = scene.patches[i].area;
        std::uint64_t a = F.local.rowBegin(i), aEnd = F.local.rowEnd(i);
        std::size_t b = 0;
        std::vector<FormFactors::Entry>& out = rows[i];
        while (a < aEnd || b < column.size()) {
            const std::uint32_t ja = a < aEnd ? F.local.columns()[a] : UINT32_MAX;
            const std::uint32_t jb = b < column.size() ? column[b].first : UINT32_MAX;
            const std::uint32_t j = std::min(ja, jb);
            const double fij = ja == j ? double(F.local.values()[a++]) : 0.0;
            const double ajfji = jb == j ? column[b++].second : 0.0;
            double v = fij;
            if (j != i && F.owner[j] >= 0) v = 0.5 * (Ai * fij + ajfji) / Ai;
            if (static_cast<float>(v) != static_cast<float>(fij)) ++changed;
            if (v > 0.0) out.push_back({j, static_cast<float>(v)});
        }
    }
    FormFactors updated = FormFactors::fromRows(std::move(rows), F.local.computedFlags());
    updated.sceneHash = F.local.sceneHash;
    updated.provenance = F.local.provenance;
    updated.parameters = F.local.parameters;
    updated.parameters["reciprocity"] = "enforced";
    F.local = std::move(updated);
    std::uint64_t total = 0;
    MPI_Allreduce(&changed, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    return std::size_t(total);
}

}  // namespace hemirad::mpi
