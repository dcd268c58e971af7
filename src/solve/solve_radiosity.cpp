// Radiosity solve: distinct channels, the singularity check, dispatch to the registered solver
// (solver_registry.hpp), and the convergence verdict on the system the user posed.
#include "solve/solver.hpp"

#include "engine/error.hpp"
#include "engine/threads.hpp"
#include "solve/solver_detail.hpp"
#include "solve/solver_registry.hpp"

#include <algorithm>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

namespace hemirad {
namespace {

using detail::Channel;
using detail::Vector;

const char* kChannelNames[3] = {"r", "g", "b"};

/// A symmetrised solve (Cholesky, CG) counts as converged only while the residual on the original
/// I - R F stays within this factor of the tolerance, or within the float precision of F's values
/// (a reciprocal F stored in float is symmetric only to ~1e-7 relative).
constexpr double kSymmetricGateFactor = 10.0;
constexpr double kFloatResidualFloor = 1e-6;

/// Collatz-Wielandt bound from below on the spectral radius of R F (non-negative) after power steps.
double spectralLowerBound(const FormFactors& F, const Vector& rho) {
    Vector x = Vector::Ones(static_cast<Eigen::Index>(F.size())), y;
    double lower = 0.0;
    for (int step = 0; step < 200; ++step) {
        detail::multiplyF(F, x, y);
        y = rho.cwiseProduct(y);
        lower = std::numeric_limits<double>::infinity();
        double upper = 0.0;
        for (Eigen::Index i = 0; i < x.size(); ++i) {
            if (x[i] <= 0.0) continue;
            lower = std::min(lower, y[i] / x[i]);
            upper = std::max(upper, y[i] / x[i]);
        }
        const double scale = y.maxCoeff();
        if (!(scale > 0.0)) return 0.0;
        x = y / scale;
        if (upper < 1.0 || lower >= 1.0 - 1e-12 || upper - lower < 1e-9) break;
    }
    return lower;
}

}  // namespace

void checkConverged(const SolveReport& r, const SolverOptions& options) {
    if (r.converged || options.allowUnconverged) return;
    std::ostringstream msg;
    msg << "solve: " << r.solver << " did not converge on channel(s) " << r.channels << " after " << r.iterations
        << " iterations (relative residual " << r.residual << ", tolerance " << options.tolerance << ")";
    if (!r.note.empty()) msg << "; " << r.note;
    msg << "; raise --max-iterations, try another --solver, or pass --allow-unconverged";
    throw Error(msg.str());
}

std::string chooseSolver(std::size_t patches, const Scene&) {
    // Small systems: exact LU. Large ones: a stationary iteration on the unsymmetrised F, which
    // converges for any rho < 1 with row sums <= 1 (diagonally dominant I - R F) and serves RGB in one
    // pass. Gauss-Seidel needs fewer sweeps, but each runs in order on one core; Jacobi's sweeps run
    // on every thread. Measured on cornell13k (bench/results/auto_solver.md): 15 against 26 sweeps,
    // 1.5 s against 2.2 s on 1 thread, even (1.37 s) on 2: Jacobi ahead beyond.
    if (patches <= 2000) return "lu";
    return resolveThreads(0) > 2 ? "jacobi" : "gauss-seidel";
}

Radiosity solveRadiosity(const Scene& scene, const FormFactors& F, const SolverOptions& options,
                         const std::vector<Rgb>* initial) {
    const std::size_t n = scene.size();
    if (F.size() != n)
        throw Error("solve: F has " + std::to_string(F.size()) + " rows but the scene has " + std::to_string(n) + " patches");
    if (!(options.tolerance > 0.0) || options.tolerance >= 1.0)
        throw Error("solve: tolerance must be in (0, 1), got " + std::to_string(options.tolerance));
    for (std::size_t i = 0; i < n; ++i)
        if ((scene.patches[i].rho > 0.0).any() && !F.rowComputed(i))
            throw Error("solve: row " + std::to_string(i) + " of F was not computed (the patch was black then) "
                        "but its reflectance is now > 0; recompute F or its missing rows");
    if (initial && initial->size() != n) throw Error("solve: warm start has the wrong size");
    const std::string name = options.solver == "auto" ? chooseSolver(n, scene) : options.solver;
    const SolverDescriptor& solver = findSolver(name);

    // Distinct channels: identical (rho, E) columns are solved once.
    std::vector<Channel> channels;
    std::array<int, 3> channelOf{};
    for (int c = 0; c < 3; ++c) {
        Channel ch;
        ch.rho.resize(static_cast<Eigen::Index>(n));
        ch.E.resize(static_cast<Eigen::Index>(n));
        ch.B.resize(static_cast<Eigen::Index>(n));
        for (std::size_t i = 0; i < n; ++i) {
            ch.rho[i] = scene.patches[i].rho[c];
            ch.E[i] = scene.patches[i].emission[c];
            ch.B[i] = initial ? (*initial)[i][c] : ch.E[i];
        }
        int same = -1;
        for (std::size_t d = 0; d < channels.size(); ++d)
            if (channels[d].rho == ch.rho && channels[d].E == ch.E) same = int(d);
        if (same >= 0) {
            channels[same].names += kChannelNames[c];
        } else {
            ch.names = kChannelNames[c];
            channels.push_back(std::move(ch));
            same = int(channels.size() - 1);
        }
        channelOf[c] = same;
    }

    // No steady state when the spectral radius of R F reaches 1: rho >= 1 in a closed part of the
    // scene, or rows of F summing above 1 / rho (estimates made non-closed, e.g. by averaging).
    // Cheap test first (row sums times rho below 1 bound the radius), power steps only if needed.
    for (const Channel& ch : channels) {
        double worstGain = 0.0;
        for (std::size_t i = 0; i < n; ++i)
            if (F.rowComputed(i)) worstGain = std::max(worstGain, ch.rho[Eigen::Index(i)] * F.rowSum(i));
        if (worstGain < 1.0) continue;
        const double lower = spectralLowerBound(F, ch.rho);
        if (lower >= 1.0 - 1e-9) {
            std::ostringstream msg;
            msg << "solve: channel " << ch.names << " is singular: the spectral radius of R F is " << lower
                << " >= 1 (largest rho x row sum " << worstGain << "): no steady state exists";
            if (ch.rho.maxCoeff() >= 1.0) msg << "; reflectance >= 1 in a closed part of the scene";
            else msg << "; rows of F sum above 1 / rho (try --normalize-rows for a closed scene)";
            throw Error(msg.str());
        }
    }

    std::optional<detail::Transposed> Ft;
    std::optional<detail::SymmetricForm> symmetric;
    if (solver.needsTranspose || solver.symmetricForm) Ft = transpose(F);
    if (solver.symmetricForm) symmetric.emplace(scene, F, *Ft);

    std::vector<Channel*> active;  // channels with emission; the others are B = 0
    for (Channel& ch : channels) {
        ch.report.solver = solver.name;
        ch.report.channels = ch.names;
        if (ch.E.norm() == 0.0) {
            ch.B.setZero();
            ch.report.converged = true;
            ch.report.note = "no emission in this channel";
        } else {
            active.push_back(&ch);
        }
    }
    if (!active.empty()) {
        SolveProblem problem{scene, F, options, Ft ? &*Ft : nullptr, symmetric ? &*symmetric : nullptr, {}};
        if (options.progress)
            problem.afterSweep = [&](int sweep) {
                std::vector<Rgb> B(n);
                for (int c = 0; c < 3; ++c)
                    for (std::size_t i = 0; i < n; ++i) B[i][c] = channels[channelOf[c]].B[i];
                options.progress(sweep, B);
            };
        solver.solve(problem, active);
    }

    Radiosity result;
    result.B.assign(n, Rgb::Zero());
    for (int c = 0; c < 3; ++c) {
        const Channel& ch = channels[channelOf[c]];
        for (std::size_t i = 0; i < n; ++i) result.B[i][c] = ch.B[i];
    }
    for (Channel& ch : channels) {
        SolveReport& r = ch.report;
        r.residualOriginal = ch.E.norm() > 0 ? detail::relativeResidual(F, ch.rho, ch.E, ch.B) : 0.0;
        // Cholesky and CG solve the symmetrised K: their own residual says nothing about I - R F when
        // F is not reciprocal. Converged means converged on the system the user posed.
        const double originalLimit = std::max(kSymmetricGateFactor * options.tolerance, kFloatResidualFloor);
        if (solver.symmetricForm && r.converged && !(r.residualOriginal <= originalLimit)) {
            std::ostringstream note;
            note << "the symmetrised system converged (residual " << r.residual << ") but the residual on I - R F is "
                 << r.residualOriginal << " > " << originalLimit
                 << ": F is not reciprocal enough for the symmetric form; use lu, bicgstab or gauss-seidel, or "
                    "--enforce-reciprocity";
            r.converged = false;
            r.note = note.str();
        }
        if (!ch.B.allFinite()) {
            r.converged = false;
            r.note = "the solution is not finite";
        }
        checkConverged(r, options);
        result.reports.push_back(r);
    }
    return result;
}

}  // namespace hemirad
