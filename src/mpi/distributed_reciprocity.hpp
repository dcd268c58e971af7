// --enforce-reciprocity across MPI ranks: F_ji for a rank's row i lives in row j, on any rank; PETSc's
// transpose of G = diag(A) F brings column i of G to the rank that holds row i.
#pragma once

#include "engine/emitted_pairs.hpp"
#include "engine/reciprocal_closure.hpp"
#include "mpi/distributed_form_factors.hpp"

namespace hemirad::mpi {

/// enforceReciprocity (engine/reciprocal_closure.hpp) over the ranks' rows: the pair means built
/// with one process's arithmetic, the scaling's vectors shared by MPI_Allgatherv and its sums taken
/// in one order, so the rows are bit for bit those of one process. The report (entries changed over
/// all ranks) is the same on every rank. Collective.
ReciprocityReport enforceReciprocityDistributed(const Context& context, const Scene& scene, DistributedFormFactors& F);

/// dropBelow (engine/reciprocal_closure.hpp) over the ranks' rows: the same pairs dropped (each
/// row's cut shared across ranks, pairs with an emitter kept), then the same closure. Collective.
SparsifyReport dropBelowDistributed(const Context& context, const Scene& scene, DistributedFormFactors& F, double threshold);

/// takePairsFromEmitters (engine/emitted_pairs.hpp) over the ranks' rows: each receiver entry
/// from its emitting row on any rank, through G^T (G = diag(A) F), with one process's arithmetic,
/// so that F is bit for bit one process's. The report is summed over the ranks. Collective.
EmittedPairsReport takePairsFromEmittersDistributed(const Context& context, const Scene& scene, DistributedFormFactors& F);

}  // namespace hemirad::mpi
