// F's rows as PETSc parallel matrices: the renumbering and the row assembly.
#include "mpi/petsc_rows.hpp"

#include <string>
#include <type_traits>

namespace hemirad::mpi {

// F's rows go to PETSc as they are, and the transpose of diag(A) F comes back bit for bit as one
// process computes A_j F_ji (--enforce-reciprocity, --drop-below, the emitted pairs): PETSc's
// scalars must be F's doubles (Debian's PETSc is real, double precision).
static_assert(std::is_same_v<PetscScalar, double>, "Hemirad needs a real, double-precision PETSc");

void check(PetscErrorCode code, const char* what) {
    if (!code) return;
    const char* text = nullptr;
    PetscErrorMessage(code, &text, nullptr);
    // The other ranks may be inside a PETSc collective that this rank will never join: ending them
    // all is the only way not to hang.
    abortAllRanks(std::string("PETSc: ") + what + ": " + (text ? text : "error " + std::to_string(int(code))));
}

Layout layoutOf(const Context& context, const std::vector<std::int32_t>& owner) {
    const int K = context.size();
    std::vector<std::vector<PatchId>> byRank(static_cast<std::size_t>(K));
    for (std::size_t i = 0; i < owner.size(); ++i)
        byRank[std::size_t(owner[i] >= 0 ? owner[i] : int(i % std::size_t(K)))].push_back(PatchId(i));
    Layout layout;
    layout.perm.resize(owner.size());
    PetscInt next = 0;
    for (int r = 0; r < K; ++r) {
        if (r == context.rank()) layout.begin = next;
        for (PatchId i : byRank[std::size_t(r)]) layout.perm[i] = next++;
        if (r == context.rank()) layout.end = next;
    }
    layout.mine = std::move(byRank[std::size_t(context.rank())]);
    return layout;
}

Preallocation preallocationOf(const DistributedFormFactors& F, const Layout& layout) {
    const PetscInt m = layout.end - layout.begin;
    Preallocation counts;
    counts.diagonal.assign(std::size_t(m), 1);
    counts.off.assign(std::size_t(m), 0);
    for (PetscInt k = 0; k < m; ++k) {
        const PatchId i = layout.mine[std::size_t(k)];
        if (F.owner[i] < 0) continue;
        for (std::uint64_t e = F.local.rowBegin(i); e < F.local.rowEnd(i); ++e) {
            const PetscInt p = layout.perm[F.local.columns()[e]];
            if (p == layout.begin + k) continue;  // the diagonal is counted already
            ++(p >= layout.begin && p < layout.end ? counts.diagonal : counts.off)[std::size_t(k)];
        }
    }
    return counts;
}

Mat rowsMatrix(const DistributedFormFactors& F, const Layout& layout, std::size_t n, const Preallocation& counts,
               const std::vector<double>& diagonal, const std::vector<double>& scale) {
    const PetscInt m = layout.end - layout.begin;
    Mat A;
    check(MatCreateAIJ(PETSC_COMM_WORLD, m, m, PetscInt(n), PetscInt(n), 0, counts.diagonal.data(), 0,
                       counts.off.data(), &A),
          "MatCreateAIJ");
    std::vector<PetscInt> columns;
    std::vector<PetscScalar> values;
    for (PetscInt k = 0; k < m; ++k) {
        const PatchId i = layout.mine[std::size_t(k)];
        const PetscInt row = layout.begin + k;
        const double a = scale[std::size_t(k)];
        columns.assign(1, row);
        values.assign(1, diagonal[std::size_t(k)]);
        if (F.owner[i] >= 0 && a != 0.0)
            for (std::uint64_t e = F.local.rowBegin(i); e < F.local.rowEnd(i); ++e) {
                const PetscInt p = layout.perm[F.local.columns()[e]];
                const double v = a * double(F.local.values()[e]);
                if (p == row) values[0] += v;
                else columns.push_back(p), values.push_back(v);
            }
        check(MatSetValues(A, 1, &row, PetscInt(columns.size()), columns.data(), values.data(), INSERT_VALUES),
              "MatSetValues");
    }
    check(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    return A;
}

Mat areaWeightedRows(const Scene& scene, const DistributedFormFactors& F, const Layout& layout,
                     const Preallocation& counts) {
    const std::size_t m = layout.mine.size();
    std::vector<double> zero(m, 0.0), area(m);
    for (std::size_t k = 0; k < m; ++k) area[k] = scene.patches[layout.mine[k]].area;
    return rowsMatrix(F, layout, scene.size(), counts, zero, area);
}

}  // namespace hemirad::mpi
