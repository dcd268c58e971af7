// The distributed radiosity solve: PETSc's Krylov and Richardson solvers on a MATMPIAIJ built from
// the rows each rank computed (no gather of F); B comes back to rank 0.
#pragma once

#include "mpi/distributed_form_factors.hpp"
#include "solve/solver.hpp"

#include <string>

namespace hemirad::mpi {

/// The --solver values the distributed solve takes ("auto" picks bicgstab).
const std::vector<std::string>& distributedSolverNames();

/// Throws UsageError for a solver that does not run distributed (lu, gauss-seidel, ...).
void checkDistributedSolver(const std::string& name);

/// Solves (I - R F) B = E per distinct channel (identical rho and E columns once) with PETSc:
/// bicgstab = KSPBCGS with a right Jacobi preconditioner, jacobi = KSPRICHARDSON with PCJACOBI: both
/// stop at the relative residual ||E - (I - R F) B|| / ||E|| <= options.tolerance, as the one-process
/// solvers do, starting from B = E. cg = KSPCG with PCJACOBI on the symmetric form
/// K = diag(A / rho) - (diag(A) F + F^T diag(A)) / 2 (black patches on the right-hand side), built with
/// MatTranspose; it stops at options.tolerance on K, and, as in one process, counts as converged
/// only when the residual on I - R F is within max(10 x tolerance, 1e-6) (F reciprocal enough).
/// Collective; B on rank 0 (empty elsewhere).
/// Throws hemirad::Error as solveRadiosity does (a needed row missing, unconverged).
Radiosity solveDistributed(const Context& context, const Scene& scene, const DistributedFormFactors& F,
                           const SolverOptions& options);

/// solveBands across the ranks: (I - R_k F) X_k = S_k per distinct band (rho and source per patch,
/// the same on every rank), by solveDistributed's solvers and stopping rule (no warm start: X = S
/// first). Collective; every X whole on every rank. Throws hemirad::Error for a reflecting row that
/// was not computed and, unless options.allowUnconverged, an unconverged band (checkConverged).
BandSolution solveBandsDistributed(const Context& context, const Scene& scene, const DistributedFormFactors& F,
                                   const std::vector<Band>& bands, const SolverOptions& options);

}  // namespace hemirad::mpi
