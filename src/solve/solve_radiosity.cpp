// Radiosity solve: distinct channels, the singularity check, dispatch to the registered solver
// (solver_registry.hpp), and the convergence verdict on the system the user posed.
#include "solve/solver.hpp"

#include "engine/error.hpp"
#include "engine/threads.hpp"
#include "solve/solver_detail.hpp"
#include "solve/solver_registry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>
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
/// I - R F stays within this factor of the tolerance, or within 1e-6: an F whose values were
/// rounded to float (a version 1 .hff, float32 arrays from Python) is symmetric only to ~1e-7.
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
    // pass. Ordered sweeps need fewer of them, but each runs in order on one core; Jacobi's sweeps run
    // on every thread. SOR (Gauss-Seidel over-relaxed by its own convergence) needs fewer again.
    // Measured on cornell13k at 1e-6 (bench/results/auto_solver.md): SOR 11, Gauss-Seidel 15, Jacobi
    // 26 sweeps; on 2 threads 1.31, 1.66 and 1.56 s. Jacobi is ahead beyond 2 threads.
    if (patches <= 2000) return "lu";
    return resolveThreads(0) > 2 ? "jacobi" : "sor";
}

namespace {

/// FNV-1a over a band's reflectance and source: finds identical bands without comparing every pair.
std::uint64_t bandKey(const Band& band) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](const std::vector<double>& v) {
        for (const double x : v) {
            std::uint64_t bits = 0;
            std::memcpy(&bits, &x, sizeof bits);
            h = (h ^ bits) * 1099511628211ull;
        }
    };
    mix(band.rho);
    mix(band.source);
    return h;
}

}  // namespace

std::string joinBandNames(const std::vector<std::string>& names) {
    bool letters = true;
    for (const std::string& n : names) letters = letters && n.size() == 1;
    std::string joined;
    for (const std::string& n : names) joined += (joined.empty() || letters ? "" : ",") + n;
    return joined;
}

BandSolution solveBands(const Scene& scene, const FormFactors& F, const std::vector<Band>& bands,
                        const SolverOptions& options,
                        const std::function<void(int sweep, const std::vector<std::vector<double>>& X)>& afterSweep) {
    const std::size_t n = scene.size();
    if (F.size() != n)
        throw Error("solve: F has " + std::to_string(F.size()) + " rows but the scene has " + std::to_string(n) + " patches");
    if (!(options.tolerance > 0.0) || options.tolerance >= 1.0)
        throw Error("solve: tolerance must be in (0, 1), got " + std::to_string(options.tolerance));
    for (const Band& band : bands) {
        if (band.rho.size() != n || band.source.size() != n || (band.initial && band.initial->size() != n))
            throw Error("solve: band " + band.name + " does not have one value per patch");
        for (std::size_t i = 0; i < n; ++i)
            if (band.rho[i] > 0.0 && !F.rowComputed(i))
                throw Error("solve: row " + std::to_string(i) + " of F was not computed (the patch was black then) "
                            "but its reflectance is now > 0; recompute F or its missing rows");
    }
    const std::string name = options.solver == "auto" ? chooseSolver(n, scene) : options.solver;
    const SolverDescriptor& solver = findSolver(name);

    // Distinct bands: identical (rho, source) bands are solved once.
    std::vector<Channel> channels;
    std::vector<std::size_t> channelOf(bands.size());
    std::vector<std::vector<std::string>> namesOf;
    std::unordered_multimap<std::uint64_t, std::size_t> byKey;
    channels.reserve(bands.size());
    for (std::size_t b = 0; b < bands.size(); ++b) {
        const Band& band = bands[b];
        const std::uint64_t key = bandKey(band);
        std::size_t same = SIZE_MAX;
        for (auto [it, last] = byKey.equal_range(key); it != last && same == SIZE_MAX; ++it) {
            const Channel& c = channels[it->second];
            bool equal = true;
            for (std::size_t i = 0; i < n && equal; ++i)
                equal = c.rho[Eigen::Index(i)] == band.rho[i] && c.E[Eigen::Index(i)] == band.source[i];
            if (equal) same = it->second;
        }
        if (same != SIZE_MAX) {
            namesOf[same].push_back(band.name);
            channelOf[b] = same;
            continue;
        }
        Channel ch;
        namesOf.push_back({band.name});
        ch.rho = Eigen::Map<const Vector>(band.rho.data(), Eigen::Index(n));
        ch.E = Eigen::Map<const Vector>(band.source.data(), Eigen::Index(n));
        ch.B = band.initial ? Vector(Eigen::Map<const Vector>(band.initial->data(), Eigen::Index(n))) : ch.E;
        channels.push_back(std::move(ch));
        channelOf[b] = channels.size() - 1;
        byKey.emplace(key, channelOf[b]);
    }
    for (std::size_t c = 0; c < channels.size(); ++c) channels[c].names = joinBandNames(namesOf[c]);

    // No steady state when the spectral radius of R F reaches 1: rho >= 1 in a closed part of the
    // scene, or rows of F summing above 1 / rho (estimates made non-closed, e.g. by averaging).
    // Cheap test first (row sums times rho below 1 bound the radius), power steps only if needed.
    std::vector<const Vector*> checked;
    for (const Channel& ch : channels) {
        bool seen = false;
        for (const Vector* rho : checked) seen = seen || *rho == ch.rho;
        if (seen) continue;
        checked.push_back(&ch.rho);
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

    std::vector<Channel*> active;  // channels with a source; the others are X = 0
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
    auto values = [&] {
        std::vector<std::vector<double>> X(bands.size());
        for (std::size_t b = 0; b < bands.size(); ++b) {
            const Vector& x = channels[channelOf[b]].B;
            X[b].assign(x.data(), x.data() + x.size());
        }
        return X;
    };
    if (!active.empty()) {
        SolveProblem problem{scene, F, options, Ft ? &*Ft : nullptr, symmetric ? &*symmetric : nullptr, {}};
        if (afterSweep) problem.afterSweep = [&](int sweep) { afterSweep(sweep, values()); };
        solver.solve(problem, active);
    }

    BandSolution result;
    {
        // The residual on I - R F, in one pass over F for every channel that lacks it: a solver that
        // sweeps I - R F itself reports it for its final B (one pass fewer for a year's batch).
        std::vector<Channel*> all;
        for (Channel& ch : channels) {
            if (!solver.residualOnPosedSystem || ch.E.norm() == 0.0) all.push_back(&ch);
            else ch.report.residualOriginal = ch.report.residual;
        }
        detail::relativeResiduals(F, all);
    }
    for (Channel& ch : channels) {
        SolveReport& r = ch.report;
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
    result.X = values();
    return result;
}

Radiosity solveRadiosity(const Scene& scene, const FormFactors& F, const SolverOptions& options,
                         const std::vector<Rgb>* initial) {
    const std::size_t n = scene.size();
    if (F.size() != n)
        throw Error("solve: F has " + std::to_string(F.size()) + " rows but the scene has " + std::to_string(n) + " patches");
    if (initial && initial->size() != n) throw Error("solve: warm start has the wrong size");
    std::vector<Band> bands(3);
    std::array<std::vector<double>, 3> starts;
    for (int c = 0; c < 3; ++c) {
        Band& band = bands[std::size_t(c)];
        band.name = kChannelNames[c];
        band.rho.resize(n);
        band.source.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            band.rho[i] = scene.patches[i].rho[c];
            band.source[i] = scene.patches[i].emission[c];
        }
        if (initial) {
            starts[std::size_t(c)].resize(n);
            for (std::size_t i = 0; i < n; ++i) starts[std::size_t(c)][i] = (*initial)[i][c];
            band.initial = &starts[std::size_t(c)];
        }
    }
    auto toRgb = [n](const std::vector<std::vector<double>>& X) {
        std::vector<Rgb> B(n);
        for (int c = 0; c < 3; ++c)
            for (std::size_t i = 0; i < n; ++i) B[i][c] = X[std::size_t(c)][i];
        return B;
    };
    std::function<void(int, const std::vector<std::vector<double>>&)> hook;
    if (options.progress) hook = [&](int sweep, const std::vector<std::vector<double>>& X) { options.progress(sweep, toRgb(X)); };
    BandSolution solved = solveBands(scene, F, bands, options, hook);
    Radiosity result;
    result.B = toRgb(solved.X);
    result.reports = std::move(solved.reports);
    return result;
}

}  // namespace hemirad
