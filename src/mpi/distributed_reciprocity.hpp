// --enforce-reciprocity across MPI ranks: F_ji for a rank's row i lives in row j, on any rank; PETSc's
// transpose of G = diag(A) F brings column i of G to the rank that holds row i.
#pragma once

#include "mpi/distributed_form_factors.hpp"

namespace hemirad::mpi {

/// Replaces F_ij and F_ji (both rows computed) by their area-weighted mean so that A_i F_ij = A_j F_ji,
/// with enforceReciprocity's arithmetic (engine/form_factors.hpp), so the rows are bit for bit those
/// of one process; entries present in only one of the two rows get a partner. Returns the entries
/// changed over all ranks (on every rank). Collective.
std::size_t enforceReciprocityDistributed(const Context& context, const Scene& scene, DistributedFormFactors& F);

}  // namespace hemirad::mpi
