// Eigen's solvers on Hemirad's systems: SparseLU and BiCGSTAB on I - R F; SimplicialLLT and
// ConjugateGradient on the symmetric positive-definite K = diag(A / rho) - sym(diag(A) F).
#include "engine/error.hpp"
#include "solve/solver_detail.hpp"
#include "solve/solver_registry.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <chrono>
#include <limits>
#include <memory>
#include <sstream>

namespace hemirad::detail {
namespace {

using ColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

enum class EigenKind { LU, Cholesky, CG, BiCGSTAB };

const char* eigenName(EigenKind kind) {
    switch (kind) {
    case EigenKind::LU: return "lu";
    case EigenKind::Cholesky: return "cholesky";
    case EigenKind::CG: return "cg";
    case EigenKind::BiCGSTAB: return "bicgstab";
    }
    return "?";
}

constexpr const char* kSymmetrisedNote = "F symmetrised for the SPD form: A_i F_ij -> (A_i F_ij + A_j F_ji) / 2";

std::string gib(double bytes) {
    std::ostringstream s;
    s.precision(3);
    s << bytes / double(1 << 30) << " GiB";
    return s.str();
}

/// Fills a compressed row-major matrix from per-row counts and a row writer, rows in parallel.
/// write(i, columns, values) stores row i's entries (sorted) and returns how many it wrote.
template <class Count, class Write>
RowMatrix buildRows(std::size_t n, Count count, Write write) {
    std::vector<std::uint64_t> start(n + 1, 0);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) start[i + 1] = count(std::size_t(i));
    for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    if (start[n] > std::uint64_t(std::numeric_limits<int>::max()))
        throw Error("solve: the system has " + std::to_string(start[n]) + " nonzeros, more than Eigen's 32-bit indices");
    RowMatrix M(static_cast<int>(n), static_cast<int>(n));
    M.resizeNonZeros(static_cast<Eigen::Index>(start[n]));
    int* outer = M.outerIndexPtr();
    for (std::size_t i = 0; i <= n; ++i) outer[i] = static_cast<int>(start[i]);
    int* inner = M.innerIndexPtr();
    double* value = M.valuePtr();
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) write(std::size_t(i), inner + start[i], value + start[i]);
    return M;
}

/// I - R F.
RowMatrix systemMatrix(const FormFactors& F, const Vector& rho) {
    auto count = [&](std::size_t i) {
        bool self = false;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) self |= F.columns()[k] == i;
        return F.rowEnd(i) - F.rowBegin(i) + (self ? 0 : 1);
    };
    auto write = [&](std::size_t i, int* col, double* val) {
        bool diagonal = false;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            const std::uint32_t j = F.columns()[k];
            if (!diagonal && j >= i) {
                *col++ = int(i);
                *val++ = 1.0 - (j == i ? rho[i] * F.values()[k] : 0.0);
                diagonal = true;
                if (j == i) continue;
            }
            *col++ = int(j);
            *val++ = -rho[i] * F.values()[k];
        }
        if (!diagonal) {
            *col = int(i);
            *val = 1.0;
        }
    };
    return buildRows(F.size(), count, write);
}

}  // namespace

const RowMatrix& SymmetricForm::matrixFor(const Vector& rho) {
    const std::size_t n = m_F.size();
    std::vector<std::uint8_t> active(n);
    for (std::size_t i = 0; i < n; ++i) active[i] = rho[i] > 0.0;
    std::vector<double> area(n);  // contiguous: patches are large structs, read at random below
    for (std::size_t i = 0; i < n; ++i) area[i] = m_scene.patches[i].area;
    if (active != m_active) {
        m_active = std::move(active);
        m_diagonalAt.assign(n, 0);
        m_self.assign(n, 0.0);
        // Row i merges row i of F (A_i F_ij) with column i (A_j F_ji), both sorted: O(nnz).
        auto merge = [&](std::size_t i, auto&& visit) {
            mergeRowAndColumn(m_F, m_Ft, i, [&](std::uint32_t j, double fij, double fji) {
                visit(j, 0.5 * (area[i] * fij + area[j] * fji));  // (A_i F_ij + A_j F_ji) / 2
            });
        };
        auto count = [&](std::size_t i) -> std::uint64_t {
            std::uint64_t c = 1;  // the diagonal
            if (m_active[i]) merge(i, [&](std::uint32_t j, double) { c += j != i && m_active[j]; });
            return c;
        };
        auto write = [&](std::size_t i, int* col, double* val) {
            if (!m_active[i]) {
                *col = int(i);
                *val = 1.0;
                return;
            }
            bool placed = false;
            merge(i, [&](std::uint32_t j, double g) {
                if (!placed && j >= i) {
                    *col++ = int(i);
                    *val++ = 0.0;  // the diagonal, set per channel below
                    placed = true;
                    if (j == i) {
                        m_self[i] = g;
                        return;
                    }
                }
                if (m_active[j]) {
                    *col++ = int(j);
                    *val++ = -g;
                }
            });
            if (!placed) {
                *col = int(i);
                *val = 0.0;
            }
        };
        m_K = buildRows(n, count, write);
        for (std::size_t i = 0; i < n; ++i) {
            const int* begin = m_K.innerIndexPtr() + m_K.outerIndexPtr()[i];
            const int* end = m_K.innerIndexPtr() + m_K.outerIndexPtr()[i + 1];
            m_diagonalAt[i] = static_cast<int>(std::lower_bound(begin, end, int(i)) - m_K.innerIndexPtr());
        }
    }
    double* value = m_K.valuePtr();
    for (std::size_t i = 0; i < n; ++i)
        if (m_active[i]) value[m_diagonalAt[i]] = area[i] / rho[i] - m_self[i];
    return m_K;
}

namespace {

/// The Eigen solvers for one reflectance vector: LU and BiCGSTAB on I - R F; Cholesky and CG on
/// K = diag(A / rho) - sym(diag(A) F) with black patches moved to the right-hand side.
class EigenSystem {
public:
    /// `symmetric` is needed for Cholesky and CG (else may be null) and must outlive this system.
    EigenSystem(const Scene& scene, const FormFactors& F, SymmetricForm* symmetric, const Vector& rho, EigenKind kind,
                const SolverOptions& options);
    ~EigenSystem();
    void solve(Channel& channel);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace

struct EigenSystem::Impl {
    const Scene& scene;
    const FormFactors& F;
    Vector rho;
    EigenKind kind;
    const SolverOptions& options;
    Eigen::SparseLU<ColMatrix> lu;
    Eigen::SimplicialLLT<ColMatrix> llt;
    RowMatrix system;               // I - R F for BiCGSTAB
    const RowMatrix* K = nullptr;   // the symmetric form for Cholesky residuals and CG

    Impl(const Scene& s, const FormFactors& f, const Vector& r, EigenKind k, const SolverOptions& o)
        : scene(s), F(f), rho(r), kind(k), options(o) {}

    /// b_i = A_i E_i / rho_i + A_i sum over black j of F_ij E_j (black patches: B = E, moved right).
    Vector symmetricRhs(const Vector& E) const {
        const auto n = static_cast<Eigen::Index>(F.size());
        Vector b(n);
        for (Eigen::Index i = 0; i < n; ++i) {
            if (!(rho[i] > 0.0)) {
                b[i] = E[i];
                continue;
            }
            double known = 0.0;
            for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
                const auto j = static_cast<Eigen::Index>(F.columns()[k]);
                if (!(rho[j] > 0.0)) known += F.values()[k] * E[j];
            }
            b[i] = scene.patches[i].area * (E[i] / rho[i] + known);
        }
        return b;
    }
};

EigenSystem::EigenSystem(const Scene& scene, const FormFactors& F, SymmetricForm* symmetric, const Vector& rho,
                         EigenKind kind, const SolverOptions& options)
    : m_impl(std::make_unique<Impl>(scene, F, rho, kind, options)) {
    const double n = static_cast<double>(F.size());
    if (kind == EigenKind::LU || kind == EigenKind::Cholesky) {
        // Radiosity matrices are nearly dense once factored: budget for full fill-in.
        const double factor = kind == EigenKind::LU ? 1.0 : 0.5;
        const double estimate = n * n * 8.0 * factor + 24.0 * static_cast<double>(F.nonZeros());
        std::size_t limit = options.memoryLimit;
        if (!limit) {
            const std::size_t available = availableMemory();
            limit = available ? available / 10 * 8 : std::size_t(8) << 30;
        }
        if (estimate > static_cast<double>(limit)) {
            throw Error(std::string("solver ") + eigenName(kind) + ": the factorisation of " + std::to_string(F.size()) +
                        " patches may need " + gib(estimate) + ", more than the " + gib(double(limit)) +
                        " available; use --solver cg, bicgstab or gauss-seidel");
        }
    }
    {
        if (kind == EigenKind::LU) {
            m_impl->lu.compute(ColMatrix(systemMatrix(F, rho)));
            if (m_impl->lu.info() != Eigen::Success)
                throw Error("solver lu: factorisation failed (" + m_impl->lu.lastErrorMessage() + "): I - R F is singular");
        } else if (kind == EigenKind::Cholesky || kind == EigenKind::CG) {
            if (!symmetric) throw Error("internal: the symmetric form is missing");
            m_impl->K = &symmetric->matrixFor(rho);
            if (kind == EigenKind::Cholesky) {
                m_impl->llt.compute(ColMatrix(*m_impl->K));
                if (m_impl->llt.info() != Eigen::Success)
                    throw Error("solver cholesky: K = diag(A/rho) - sym(A F) is not positive definite "
                                "(rho >= 1, or F far from reciprocal); use --solver lu or bicgstab");
            }
        } else if (kind == EigenKind::BiCGSTAB) {
            m_impl->system = systemMatrix(F, rho);
        } else {
            throw Error(std::string("internal: ") + eigenName(kind) + " is not an Eigen solver");
        }
    }
}

EigenSystem::~EigenSystem() = default;

void EigenSystem::solve(Channel& ch) {
    Impl& s = *m_impl;
    SolveReport& report = ch.report;
    switch (s.kind) {
    case EigenKind::LU:
        ch.B = s.lu.solve(ch.E);
        report.converged = s.lu.info() == Eigen::Success;
        report.residual = relativeResidual(s.F, s.rho, ch.E, ch.B);
        report.converged = report.converged && std::isfinite(report.residual);
        break;
    case EigenKind::Cholesky: {
        const Vector b = s.symmetricRhs(ch.E);
        ch.B = s.llt.solve(b);
        report.converged = s.llt.info() == Eigen::Success;
        report.residual = b.norm() > 0 ? (b - *s.K * ch.B).norm() / b.norm() : 0.0;
        report.note = kSymmetrisedNote;
        break;
    }
    case EigenKind::CG: {
        Eigen::ConjugateGradient<RowMatrix, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>> cg;
        cg.setTolerance(s.options.tolerance);
        cg.setMaxIterations(s.options.maxIterations);
        cg.compute(*s.K);
        ch.B = cg.solveWithGuess(s.symmetricRhs(ch.E), ch.B);
        report.iterations = static_cast<int>(cg.iterations());
        report.residual = cg.error();
        report.converged = cg.info() == Eigen::Success;
        report.note = kSymmetrisedNote;
        break;
    }
    case EigenKind::BiCGSTAB: {
        Eigen::BiCGSTAB<RowMatrix, Eigen::DiagonalPreconditioner<double>> solver;
        solver.setTolerance(s.options.tolerance);
        solver.setMaxIterations(s.options.maxIterations);
        solver.compute(s.system);
        ch.B = solver.solveWithGuess(ch.E, ch.B);
        report.iterations = static_cast<int>(solver.iterations());
        report.residual = solver.error();
        report.converged = solver.info() == Eigen::Success;
        break;
    }
    default: throw Error("internal: not an Eigen solver");
    }
}

namespace {

/// Direct factorisations (and the Krylov setups) are shared by channels with the same reflectance.
void solveEigen(EigenKind kind, const SolveProblem& p, std::vector<Channel*>& active) {
    using Clock = std::chrono::steady_clock;
    for (std::size_t a = 0; a < active.size(); ++a) {
        const auto t0 = Clock::now();
        bool done = false;
        for (std::size_t q = 0; q < a && !done; ++q) done = active[q]->rho == active[a]->rho;
        if (done) continue;
        EigenSystem system(p.scene, p.F, p.symmetric, active[a]->rho, kind, p.options);
        for (std::size_t b = a; b < active.size(); ++b) {
            if (active[b]->rho != active[a]->rho) continue;
            system.solve(*active[b]);
            active[b]->report.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        }
    }
}

SolverDescriptor eigenSolver(EigenKind kind, std::string summary, bool symmetric) {
    SolverDescriptor d;
    d.name = eigenName(kind);
    d.summary = std::move(summary);
    d.symmetricForm = symmetric;
    d.needsTranspose = symmetric;
    if (kind == EigenKind::CG || kind == EigenKind::BiCGSTAB) d.flags = {"--tolerance", "--max-iterations"};
    d.solve = [kind](const SolveProblem& p, std::vector<Channel*>& active) { solveEigen(kind, p, active); };
    return d;
}

}  // namespace

}  // namespace hemirad::detail

namespace hemirad {

const std::vector<SolverDescriptor>& eigenSolvers() {
    using detail::EigenKind;
    static const std::vector<SolverDescriptor> family = {
        detail::eigenSolver(EigenKind::LU, "Eigen SparseLU on I - R F (exact; the default up to 2000 patches)", false),
        detail::eigenSolver(EigenKind::Cholesky, "Eigen SimplicialLLT on the symmetric form (needs a reciprocal F)", true),
        detail::eigenSolver(EigenKind::CG, "conjugate gradients on the symmetric form (needs a reciprocal F)", true),
        detail::eigenSolver(EigenKind::BiCGSTAB, "Eigen BiCGSTAB on I - R F, Jacobi preconditioner", false),
    };
    return family;
}

}  // namespace hemirad
