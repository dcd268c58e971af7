// F's rows as PETSc parallel matrices. PETSc's parallel matrices own contiguous row ranges, while the
// work queue leaves each rank an arbitrary set of rows; patches are therefore renumbered so that each
// rank's rows come first-to-last in its range (rows nobody computed, B = E, go round-robin):
//
//   old patch i --perm--> new index p;  rank r owns new [offset_r, offset_r + count_r)
#pragma once

#include "mpi/distributed_form_factors.hpp"

#include <petscmat.h>

#include <vector>

namespace hemirad::mpi {

/// For a non-zero code, ends every rank with PETSc's message (abortAllRanks): an error on one rank
/// may leave the others waiting in a PETSc collective, so it cannot be agreed on.
void check(PetscErrorCode code, const char* what);

/// A Mat destroyed with its owner (error paths included).
struct OwnedMat {
    Mat mat = nullptr;
    OwnedMat() = default;
    explicit OwnedMat(Mat m) : mat(m) {}
    OwnedMat(const OwnedMat&) = delete;
    OwnedMat& operator=(const OwnedMat&) = delete;
    ~OwnedMat() { MatDestroy(&mat); }
};

/// The renumbering: new index per patch, and this rank's rows (old indices, in new order).
struct Layout {
    std::vector<PetscInt> perm;
    std::vector<PatchId> mine;
    PetscInt begin = 0, end = 0;
};
Layout layoutOf(const Context& context, const std::vector<std::int32_t>& owner);

/// Per local row: entries inside this rank's column range (the diagonal always counted) and outside.
struct Preallocation {
    std::vector<PetscInt> diagonal, off;
};
Preallocation preallocationOf(const DistributedFormFactors& F, const Layout& layout);

/// This rank's rows of a MATMPIAIJ (N x N, new numbering) with the pattern of I - R F, the diagonal
/// always present: local row k holds diagonal[k] + scale[k] F_ii on the diagonal and scale[k] F_ij
/// elsewhere. Collective.
Mat rowsMatrix(const DistributedFormFactors& F, const Layout& layout, std::size_t n, const Preallocation& counts,
               const std::vector<double>& diagonal, const std::vector<double>& scale);

/// G = diag(A) F (row i holds A_i F_ij, with an explicit diagonal), in the layout's numbering: the
/// area-weighted F whose transpose pairs F_ij with F_ji. Collective.
Mat areaWeightedRows(const Scene& scene, const DistributedFormFactors& F, const Layout& layout,
                     const Preallocation& counts);

}  // namespace hemirad::mpi
