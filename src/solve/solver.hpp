// Radiosity solve per band: (I - R F) X = S for each band's reflectance R and source S, by a solver from
// the registry (solver_registry.hpp). RGB radiosity is three bands; thermal exchange (src/thermal) is
// one IR band (or more) with its own reflectance and source.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/memory.hpp"
#include "engine/scene.hpp"

#include <functional>
#include <string>
#include <vector>

namespace hemirad {

struct SolverOptions {
    /// "auto" (chooseSolver) or the name of a registered solver (solverRegistry(): lu, cholesky, cg,
    /// bicgstab, jacobi, gauss-seidel, sor, southwell, ...).
    std::string solver = "auto";
    double tolerance = 1e-6;          ///< relative residual ||E - (I - R F) B|| / ||E|| to reach
    int maxIterations = 100000;       ///< sweeps / iterations (Southwell: sweeps of N shots)
    bool allowUnconverged = false;    ///< else an unconverged solve throws hemirad::Error
    std::size_t memoryLimit = 0;      ///< bytes a direct solver may use; 0 = 80% of available memory
    /// Called by Jacobi and Gauss-Seidel after each sweep with the current B (RGB per patch), on the
    /// solving thread: for progressive display. Empty = not called.
    std::function<void(int sweep, const std::vector<Rgb>& B)> progress;
};

struct SolveReport {
    std::string solver;
    std::string channels;     ///< channels this solve served, e.g. "rgb" when all were identical
    bool converged = false;
    int iterations = 0;
    double residual = 0;      ///< relative residual of the system the solver worked on
    double residualOriginal = 0;  ///< ||E - (I - R F) B|| / ||E|| on the unsymmetrised F
    double seconds = 0;
    std::string note;         ///< e.g. "F symmetrised: (A_i F_ij + A_j F_ji) / 2"
};

struct Radiosity {
    std::vector<Rgb> B;       ///< per patch, W/m^2
    std::vector<SolveReport> reports;
};

/// One band's system X_i = S_i + R_i sum_j F_ij X_j: per patch reflectance R (0..1) and source S.
struct Band {
    std::string name;           ///< in reports ("r", "ir", "column 12"); one-letter names concatenate
    std::vector<double> rho, source;
    const std::vector<double>* initial = nullptr;  ///< warm start for iterative solvers (size N), or null
};

struct BandSolution {
    std::vector<std::vector<double>> X;   ///< per band, per patch
    std::vector<SolveReport> reports;     ///< per distinct band (identical bands are solved once)
};

/// The names of bands solved as one, for reports: "rgb" for one-letter names, "ir,solar" otherwise.
std::string joinBandNames(const std::vector<std::string>& names);

/// Solves every band on one F: identical (rho, source) bands once, a factorisation shared by the
/// bands it serves. `afterSweep`, if given, gets each sweep's X (per band) for progressive display.
/// Throws hemirad::Error as solveRadiosity does.
BandSolution solveBands(const Scene& scene, const FormFactors& F, const std::vector<Band>& bands,
                        const SolverOptions& options,
                        const std::function<void(int sweep, const std::vector<std::vector<double>>& X)>& afterSweep = {});

/// Solves B_i = E_i + rho_i sum_j F_ij B_j for each distinct channel (identical channels are solved
/// once). `initial`, if given, warm-starts iterative solvers. Throws hemirad::Error when the system is
/// singular (rho >= 1 in a closed part), a needed row of F was not computed, a direct solver would
/// exceed memory, or the solve did not converge (unless allowUnconverged).
Radiosity solveRadiosity(const Scene& scene, const FormFactors& F, const SolverOptions& options,
                         const std::vector<Rgb>* initial = nullptr);

/// Throws hemirad::Error (the channel, iterations, residual, note and what to try) for an unconverged
/// report unless options.allowUnconverged: one verdict for every solve, distributed ones included.
void checkConverged(const SolveReport& report, const SolverOptions& options);

/// The solver "auto" picks for N patches and the given materials, on the process's worker threads
/// (resolveThreads(0): the team configureProcessThreads set): lu up to 2000 patches; above, Gauss-
/// Seidel (ordered sweeps, one core) on up to 2 threads and Jacobi (parallel sweeps) on more.
std::string chooseSolver(std::size_t patches, const Scene& scene);

}  // namespace hemirad
