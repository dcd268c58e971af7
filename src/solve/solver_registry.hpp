// The radiosity solvers by name: each family registers descriptors (name, summary, what it needs,
// the function that solves a set of channels). The CLI, the GUI and the bench list the registry;
// adding a family (e.g. a distributed PETSc solver) is its own files plus one line in
// solver_registry.cpp.
#pragma once

#include "solve/solver_detail.hpp"

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace hemirad {

/// What a solver gets: the system and the channels to solve.
struct SolveProblem {
    const Scene& scene;
    const FormFactors& F;
    const SolverOptions& options;
    const TransposedFormFactors* Ft = nullptr;      ///< F^T when the descriptor needs it
    detail::SymmetricForm* symmetric = nullptr;     ///< K when the descriptor solves the symmetric form
    detail::SweepHook afterSweep;                   ///< progressive display, for sweep-based solvers
};

struct SolverDescriptor {
    std::string name;     ///< the --solver value
    std::string summary;  ///< one line for usage texts and the GUI
    /// Solves K = diag(A / rho) - sym(diag(A) F) instead of I - R F: needs a reciprocal F, and its
    /// convergence is judged on the residual of I - R F.
    bool symmetricForm = false;
    bool needsTranspose = false;  ///< reads F^T (column access)
    /// Its report's residual is ||E - (I - R F) B|| / ||E|| of the B it returns (not recomputed).
    bool residualOnPosedSystem = false;
    /// The solve options it takes beyond the common ones: "--tolerance" and "--max-iterations" for
    /// iterative solvers; none for a factorisation (giving them to it is a usage error).
    std::vector<std::string> flags;
    /// Solves every channel in `active` (B holds the start on entry, the solution on exit) and fills
    /// their reports (converged, iterations, residual of the system it worked on, seconds, note).
    /// Throws hemirad::Error for a system it cannot take (singular, too large).
    std::function<void(const SolveProblem&, std::vector<detail::Channel*>& active)> solve;
};

/// Every solver of this build, in the order usage texts list them.
const std::vector<const SolverDescriptor*>& solverRegistry();

/// The named solver; throws hemirad::Error listing the names ("auto" is resolved by chooseSolver first).
const SolverDescriptor& findSolver(std::string_view name);

/// "auto, lu, cholesky, ...": the accepted --solver values.
std::string solverNames();

/// Throws hemirad::Error ("unknown solver 'x' (auto, lu, ...)") unless `name` is "auto" or registered.
void checkSolverName(const std::string& name);

/// The families (eigen_solvers.cpp, iterative_solvers.cpp).
const std::vector<SolverDescriptor>& eigenSolvers();
const std::vector<SolverDescriptor>& stationarySolvers();

}  // namespace hemirad
