// Radiosity solvers. Direct: Eigen SparseLU on I - R F, Cholesky on the symmetric form
// K = diag(A/rho) - sym(diag(A) F). Iterative: Eigen CG (on K) and BiCGSTAB (on I - R F); Jacobi,
// Gauss-Seidel and Southwell progressive refinement (Cohen et al. 1988) on the CSR F directly.
#include "engine/solver.hpp"

#include "engine/error.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

namespace hemirad {
namespace {

using Vector = Eigen::VectorXd;
using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using ColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Clock = std::chrono::steady_clock;

const char* kChannelNames[3] = {"r", "g", "b"};

/// y = F x, rows in parallel.
void multiplyF(const FormFactors& F, const Vector& x, Vector& y) {
    const auto n = static_cast<std::ptrdiff_t>(F.size());
    y.resize(n);
    const std::uint32_t* col = F.columns();
    const float* val = F.values();
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        double sum = 0.0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) sum += val[k] * x[col[k]];
        y[i] = sum;
    }
}

/// ||E - (I - R F) B|| / ||E||.
double relativeResidual(const FormFactors& F, const Vector& rho, const Vector& E, const Vector& B) {
    Vector FB;
    multiplyF(F, B, FB);
    const double norm = E.norm();
    return norm > 0 ? (E - B + rho.cwiseProduct(FB)).norm() / norm : 0.0;
}

/// Collatz-Wielandt bounds on the spectral radius of R F (a non-negative matrix) after power steps.
void spectralBounds(const FormFactors& F, const Vector& rho, double& lower, double& upper) {
    Vector x = Vector::Ones(static_cast<Eigen::Index>(F.size())), y;
    for (int step = 0; step < 200; ++step) {
        multiplyF(F, x, y);
        y = rho.cwiseProduct(y);
        lower = std::numeric_limits<double>::infinity();
        upper = 0.0;
        for (Eigen::Index i = 0; i < x.size(); ++i) {
            if (x[i] <= 0.0) continue;
            lower = std::min(lower, y[i] / x[i]);
            upper = std::max(upper, y[i] / x[i]);
        }
        const double scale = y.maxCoeff();
        if (!(scale > 0.0)) {
            lower = upper = 0.0;
            return;
        }
        x = y / scale;
        // Patches that receive nothing drop out of the bound: restrict to the support found so far.
        if (upper < 1.0 || lower >= 1.0 - 1e-12 || upper - lower < 1e-9) return;
    }
}

std::size_t memoryLimit(const SolverOptions& options) {
    if (options.memoryLimit) return options.memoryLimit;
    const std::size_t available = availableMemory();
    return available ? available / 10 * 8 : std::size_t(8) << 30;
}

std::string gib(double bytes) {
    std::ostringstream s;
    s.precision(3);
    s << bytes / double(1 << 30) << " GiB";
    return s.str();
}

/// One channel's system: reflectances rho (per patch) against the shared F.
class ChannelSystem {
public:
    ChannelSystem(const Scene& scene, const FormFactors& F, Vector rho, const SolverOptions& options)
        : m_scene(scene), m_F(F), m_rho(std::move(rho)), m_options(options) {}

    const Vector& rho() const { return m_rho; }

    /// Factors once for direct solvers (LU / Cholesky); iterative solvers need nothing.
    void prepare(SolverKind kind) {
        m_kind = kind;
        const double n = static_cast<double>(m_F.size());
        if (kind == SolverKind::LU || kind == SolverKind::Cholesky) {
            // Radiosity matrices are nearly dense once factored: budget for full fill-in.
            const double factor = kind == SolverKind::LU ? 1.0 : 0.5;
            const double estimate = n * n * 8.0 * factor + 24.0 * static_cast<double>(m_F.nonZeros());
            if (estimate > static_cast<double>(memoryLimit(m_options)))
                throw Error("solver " + solverName(kind) + ": the factorisation of " + std::to_string(m_F.size()) +
                            " patches may need " + gib(estimate) + ", more than the " +
                            gib(static_cast<double>(memoryLimit(m_options))) +
                            " available; use --solver cg, bicgstab or gauss-seidel");
        }
        if (kind == SolverKind::LU) {
            m_lu.compute(ColMatrix(systemMatrix()));
            if (m_lu.info() != Eigen::Success)
                throw Error("solver lu: factorisation failed (" + m_lu.lastErrorMessage() + "): I - R F is singular");
        } else if (kind == SolverKind::Cholesky) {
            m_llt.compute(ColMatrix(symmetricMatrix()));
            if (m_llt.info() != Eigen::Success)
                throw Error("solver cholesky: K = diag(A/rho) - sym(A F) is not positive definite "
                            "(rho >= 1, or F far from reciprocal); use --solver lu or bicgstab");
        } else if (kind == SolverKind::CG) {
            m_K = symmetricMatrix();
        } else if (kind == SolverKind::BiCGSTAB) {
            m_A = systemMatrix();
        } else if (kind == SolverKind::Southwell) {
            buildTranspose();
        }
    }

    /// Solves for emission E; `B` holds the warm start on entry (iterative solvers) and the result on exit.
    SolveReport solve(const Vector& E, Vector& B) {
        SolveReport report;
        report.solver = solverName(m_kind);
        const auto start = Clock::now();
        if (E.norm() == 0.0) {
            B.setZero();
            report.converged = true;
            report.note = "no emission in this channel";
        } else {
            switch (m_kind) {
            case SolverKind::LU: B = m_lu.solve(E); report.converged = m_lu.info() == Eigen::Success; break;
            case SolverKind::Cholesky: solveSymmetricDirect(E, B, report); break;
            case SolverKind::CG: solveCg(E, B, report); break;
            case SolverKind::BiCGSTAB: solveBiCgStab(E, B, report); break;
            case SolverKind::Jacobi: jacobi(E, B, report); break;
            case SolverKind::GaussSeidel: gaussSeidel(E, B, report); break;
            case SolverKind::Southwell: southwell(E, B, report); break;
            case SolverKind::Auto: throw Error("internal: solver kind not chosen");
            }
            report.residualOriginal = relativeResidual(m_F, m_rho, E, B);
            if (m_kind == SolverKind::LU) {
                report.residual = report.residualOriginal;
                report.converged = report.converged && std::isfinite(report.residual);
            }
        }
        if (!B.allFinite()) {
            report.converged = false;
            report.note = "the solution is not finite";
        }
        report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        return report;
    }

private:
    bool active(Eigen::Index i) const { return m_rho[i] > 0.0; }

    /// I - R F, row-major.
    RowMatrix systemMatrix() const {
        const auto n = static_cast<int>(m_F.size());
        RowMatrix A(n, n);
        A.reserve(static_cast<Eigen::Index>(m_F.nonZeros() + m_F.size()));
        for (int i = 0; i < n; ++i) {
            A.startVec(i);
            bool diagonalDone = false;
            for (std::uint64_t k = m_F.rowBegin(i); k < m_F.rowEnd(i); ++k) {
                const int j = static_cast<int>(m_F.columns()[k]);
                if (!diagonalDone && j >= i) {
                    A.insertBack(i, i) = 1.0 - (j == i ? m_rho[i] * m_F.values()[k] : 0.0);
                    diagonalDone = true;
                    if (j == i) continue;
                }
                A.insertBack(i, j) = -m_rho[i] * m_F.values()[k];
            }
            if (!diagonalDone) A.insertBack(i, i) = 1.0;
        }
        A.finalize();
        return A;
    }

    /// K = diag(A/rho) - (D F + (D F)^T) / 2 on active patches (rho > 0); identity rows elsewhere
    /// (physics: Cohen & Wallace, radiosity as an SPD system when F is reciprocal).
    RowMatrix symmetricMatrix() const {
        const auto n = static_cast<int>(m_F.size());
        RowMatrix DF(n, n);
        DF.reserve(static_cast<Eigen::Index>(m_F.nonZeros()));
        for (int i = 0; i < n; ++i) {
            DF.startVec(i);
            if (!active(i)) continue;
            const double area = m_scene.patches[i].area;
            for (std::uint64_t k = m_F.rowBegin(i); k < m_F.rowEnd(i); ++k) {
                const int j = static_cast<int>(m_F.columns()[k]);
                if (active(j)) DF.insertBack(i, j) = area * m_F.values()[k];
            }
        }
        DF.finalize();
        RowMatrix DFt = DF.transpose();
        RowMatrix K = -0.5 * (DF + DFt);
        Vector diagonal(n);
        for (int i = 0; i < n; ++i) diagonal[i] = active(i) ? m_scene.patches[i].area / m_rho[i] : 1.0;
        RowMatrix D(n, n);
        D.reserve(n);
        for (int i = 0; i < n; ++i) {
            D.startVec(i);
            D.insertBack(i, i) = diagonal[i];
        }
        D.finalize();
        return K + D;
    }

    /// b_i = A_i E_i / rho_i + A_i sum over black j of F_ij E_j (black patches: B = E, moved right).
    Vector symmetricRhs(const Vector& E) const {
        const auto n = static_cast<Eigen::Index>(m_F.size());
        Vector b(n);
        for (Eigen::Index i = 0; i < n; ++i) {
            if (!active(i)) {
                b[i] = E[i];
                continue;
            }
            const double area = m_scene.patches[i].area;
            double known = 0.0;
            for (std::uint64_t k = m_F.rowBegin(i); k < m_F.rowEnd(i); ++k) {
                const auto j = static_cast<Eigen::Index>(m_F.columns()[k]);
                if (!active(j)) known += m_F.values()[k] * E[j];
            }
            b[i] = area * (E[i] / m_rho[i] + known);
        }
        return b;
    }

    static constexpr const char* kSymmetrisedNote = "F symmetrised for the SPD form: A_i F_ij -> (A_i F_ij + A_j F_ji) / 2";

    void solveSymmetricDirect(const Vector& E, Vector& B, SolveReport& report) {
        const Vector b = symmetricRhs(E);
        B = m_llt.solve(b);
        report.converged = m_llt.info() == Eigen::Success;
        report.residual = b.norm() > 0 ? (b - ColMatrix(symmetricMatrix()) * B).norm() / b.norm() : 0.0;
        report.note = kSymmetrisedNote;
    }

    void solveCg(const Vector& E, Vector& B, SolveReport& report) {
        Eigen::ConjugateGradient<RowMatrix, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>> cg;
        cg.setTolerance(m_options.tolerance);
        cg.setMaxIterations(m_options.maxIterations);
        cg.compute(m_K);
        const Vector b = symmetricRhs(E);
        B = cg.solveWithGuess(b, B);
        report.iterations = static_cast<int>(cg.iterations());
        report.residual = cg.error();
        report.converged = cg.info() == Eigen::Success;
        report.note = kSymmetrisedNote;
    }

    void solveBiCgStab(const Vector& E, Vector& B, SolveReport& report) {
        Eigen::BiCGSTAB<RowMatrix, Eigen::DiagonalPreconditioner<double>> solver;
        solver.setTolerance(m_options.tolerance);
        solver.setMaxIterations(m_options.maxIterations);
        solver.compute(m_A);
        B = solver.solveWithGuess(E, B);
        report.iterations = static_cast<int>(solver.iterations());
        report.residual = solver.error();
        report.converged = solver.info() == Eigen::Success;
    }

    /// B <- E + R F B (parallel); the step ||B' - B|| is the residual of the previous iterate.
    void jacobi(const Vector& E, Vector& B, SolveReport& report) {
        const double norm = E.norm();
        Vector FB, next;
        for (int it = 1; it <= m_options.maxIterations; ++it) {
            multiplyF(m_F, B, FB);
            next = E + m_rho.cwiseProduct(FB);
            const double step = (next - B).norm() / norm;
            B.swap(next);
            report.iterations = it;
            if (!std::isfinite(step)) break;
            if (step <= m_options.tolerance && finish(E, B, report)) return;
        }
        report.residual = relativeResidual(m_F, m_rho, E, B);
    }

    /// In-place sweeps solving each row for B_i (the self factor F_ii included).
    void gaussSeidel(const Vector& E, Vector& B, SolveReport& report) {
        const double norm = E.norm();
        const auto n = static_cast<Eigen::Index>(m_F.size());
        const std::uint32_t* col = m_F.columns();
        const float* val = m_F.values();
        for (int it = 1; it <= m_options.maxIterations; ++it) {
            double change = 0.0;
            for (Eigen::Index i = 0; i < n; ++i) {
                double sum = 0.0, self = 0.0;
                for (std::uint64_t k = m_F.rowBegin(i); k < m_F.rowEnd(i); ++k) {
                    if (col[k] == static_cast<std::uint32_t>(i)) self = val[k];
                    else sum += val[k] * B[col[k]];
                }
                const double value = (E[i] + m_rho[i] * sum) / (1.0 - m_rho[i] * self);
                change += (value - B[i]) * (value - B[i]);
                B[i] = value;
            }
            report.iterations = it;
            const double step = std::sqrt(change) / norm;
            if (!std::isfinite(step)) break;
            if (step <= m_options.tolerance && finish(E, B, report)) return;
        }
        report.residual = relativeResidual(m_F, m_rho, E, B);
    }

    void buildTranspose() {
        const std::size_t n = m_F.size();
        m_tStart.assign(n + 1, 0);
        for (std::uint64_t k = 0; k < m_F.nonZeros(); ++k) ++m_tStart[m_F.columns()[k] + 1];
        for (std::size_t j = 0; j < n; ++j) m_tStart[j + 1] += m_tStart[j];
        m_tRows.resize(m_F.nonZeros());
        m_tValues.resize(m_F.nonZeros());
        std::vector<std::uint64_t> fill(m_tStart.begin(), m_tStart.end() - 1);
        for (std::size_t i = 0; i < n; ++i)
            for (std::uint64_t k = m_F.rowBegin(i); k < m_F.rowEnd(i); ++k) {
                const std::uint64_t slot = fill[m_F.columns()[k]]++;
                m_tRows[slot] = static_cast<std::uint32_t>(i);
                m_tValues[slot] = m_F.values()[k];
            }
    }

    /// Southwell iteration = progressive refinement: shoot the patch with the most unshot power
    /// A_i |dB_i| along column i of F; the residual is R F dB, checked once per N shots.
    void southwell(const Vector& E, Vector& B, SolveReport& report) {
        const auto n = static_cast<Eigen::Index>(m_F.size());
        Vector unshot;
        {
            Vector FB;
            multiplyF(m_F, B, FB);
            // Solve for the correction x = B* - B: (I - R F) x = r with r the start's residual, shot
            // like an emission (x starts at r, all of it unshot).
            unshot = E + m_rho.cwiseProduct(FB) - B;
            B += unshot;
        }
        Vector area(n);
        for (Eigen::Index i = 0; i < n; ++i) area[i] = m_scene.patches[i].area;
        Vector power = area.cwiseProduct(unshot.cwiseAbs());
        for (int sweep = 1; sweep <= m_options.maxIterations; ++sweep) {
            for (Eigen::Index shot = 0; shot < n; ++shot) {
                Eigen::Index i;
                if (power.maxCoeff(&i) <= 0.0) break;
                const double dB = unshot[i];
                unshot[i] = 0.0;
                power[i] = 0.0;
                for (std::uint64_t k = m_tStart[i]; k < m_tStart[i + 1]; ++k) {
                    const std::uint32_t j = m_tRows[k];
                    const double received = m_rho[j] * m_tValues[k] * dB;
                    B[j] += received;
                    unshot[j] += received;
                    power[j] = area[j] * std::abs(unshot[j]);
                }
            }
            report.iterations = sweep;
            Vector FdB;
            multiplyF(m_F, unshot, FdB);
            report.residual = m_rho.cwiseProduct(FdB).norm() / E.norm();
            if (!std::isfinite(report.residual)) return;
            if (report.residual <= m_options.tolerance) {
                report.converged = true;
                return;
            }
        }
        report.note = "iterations count sweeps of N shots";
    }

    /// Confirms convergence with the true residual.
    bool finish(const Vector& E, const Vector& B, SolveReport& report) const {
        report.residual = relativeResidual(m_F, m_rho, E, B);
        report.converged = report.residual <= m_options.tolerance;
        return report.converged;
    }

    const Scene& m_scene;
    const FormFactors& m_F;
    Vector m_rho;
    const SolverOptions& m_options;
    SolverKind m_kind = SolverKind::Auto;
    Eigen::SparseLU<ColMatrix> m_lu;
    Eigen::SimplicialLLT<ColMatrix> m_llt;
    RowMatrix m_K, m_A;
    std::vector<std::uint64_t> m_tStart;
    std::vector<std::uint32_t> m_tRows;
    std::vector<float> m_tValues;
};

}  // namespace

SolverKind parseSolverKind(const std::string& name) {
    static const std::pair<const char*, SolverKind> names[] = {
        {"auto", SolverKind::Auto},     {"lu", SolverKind::LU},           {"cholesky", SolverKind::Cholesky},
        {"cg", SolverKind::CG},         {"bicgstab", SolverKind::BiCGSTAB}, {"jacobi", SolverKind::Jacobi},
        {"gauss-seidel", SolverKind::GaussSeidel}, {"southwell", SolverKind::Southwell}};
    for (const auto& [text, kind] : names)
        if (name == text) return kind;
    throw Error("unknown solver '" + name + "' (auto, lu, cholesky, cg, bicgstab, jacobi, gauss-seidel, southwell)");
}

std::string solverName(SolverKind kind) {
    switch (kind) {
    case SolverKind::Auto: return "auto";
    case SolverKind::LU: return "lu";
    case SolverKind::Cholesky: return "cholesky";
    case SolverKind::CG: return "cg";
    case SolverKind::BiCGSTAB: return "bicgstab";
    case SolverKind::Jacobi: return "jacobi";
    case SolverKind::GaussSeidel: return "gauss-seidel";
    case SolverKind::Southwell: return "southwell";
    }
    return "?";
}

SolverKind chooseSolver(std::size_t patches, const Scene&) {
    // Small systems: exact LU. Large ones: Gauss-Seidel on the unsymmetrised F, which converges for
    // any rho < 1 with row sums <= 1 (diagonally dominant I - R F).
    return patches <= 2000 ? SolverKind::LU : SolverKind::GaussSeidel;
}

std::size_t availableMemory() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    std::size_t value = 0;
    std::string unit;
    while (in >> key >> value >> unit)
        if (key == "MemAvailable:") return value * 1024;
    return 0;
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
    const SolverKind kind = options.kind == SolverKind::Auto ? chooseSolver(n, scene) : options.kind;

    std::array<Vector, 3> rho, E;
    for (int c = 0; c < 3; ++c) {
        rho[c].resize(static_cast<Eigen::Index>(n));
        E[c].resize(static_cast<Eigen::Index>(n));
        for (std::size_t i = 0; i < n; ++i) {
            rho[c][i] = scene.patches[i].rho[c];
            E[c][i] = scene.patches[i].emission[c];
        }
    }
    Radiosity result;
    result.B.assign(n, Rgb::Zero());
    std::array<bool, 3> done{false, false, false};
    for (int c = 0; c < 3; ++c) {
        if (done[c]) continue;
        // One system per distinct reflectance channel; a direct factorisation serves all its emissions.
        ChannelSystem system(scene, F, rho[c], options);
        double lower = 0.0, upper = 0.0;
        if (rho[c].maxCoeff() >= 1.0) {
            spectralBounds(F, rho[c], lower, upper);
            if (lower >= 1.0 - 1e-9) {
                std::ostringstream msg;
                msg << "solve: channel " << kChannelNames[c] << " is singular: the spectral radius of R F is " << lower
                    << " >= 1 (reflectance >= 1 in a closed part of the scene: no steady state exists)";
                throw Error(msg.str());
            }
        }
        system.prepare(kind);
        for (int d = c; d < 3; ++d) {
            if (done[d] || rho[d] != rho[c]) continue;
            std::string channels;
            for (int e = d; e < 3; ++e)
                if (!done[e] && rho[e] == rho[c] && E[e] == E[d]) channels += kChannelNames[e];
            Vector B(static_cast<Eigen::Index>(n));
            for (std::size_t i = 0; i < n; ++i) B[i] = initial ? (*initial)[i][d] : E[d][i];
            SolveReport report = system.solve(E[d], B);
            report.channels = channels;
            for (int e = d; e < 3; ++e)
                if (!done[e] && rho[e] == rho[c] && E[e] == E[d]) {
                    for (std::size_t i = 0; i < n; ++i) result.B[i][e] = B[i];
                    done[e] = true;
                }
            if (!report.converged && !options.allowUnconverged) {
                std::ostringstream msg;
                msg << "solve: " << report.solver << " did not converge on channel(s) " << channels << " after "
                    << report.iterations << " iterations (relative residual " << report.residual << ", tolerance "
                    << options.tolerance << ")";
                if (!report.note.empty()) msg << "; " << report.note;
                msg << "; raise --max-iterations, try another --solver, or pass --allow-unconverged";
                throw Error(msg.str());
            }
            result.reports.push_back(report);
        }
    }
    return result;
}

}  // namespace hemirad
