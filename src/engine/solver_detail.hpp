// Internals shared by the solver files: channels, sparse kernels on the float CSR F, the solver families.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/scene.hpp"
#include "engine/solver.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hemirad::detail {

using Vector = Eigen::VectorXd;

/// One distinct channel of the RGB problem: reflectance and emission per patch. B holds the start
/// on entry and the solution on exit.
struct Channel {
    std::string names;  ///< the RGB channels it stands for, e.g. "rgb" or "g"
    Vector rho, E, B;
    SolveReport report;
};

/// y = F x (rows in parallel).
void multiplyF(const FormFactors& F, const Vector& x, Vector& y);
/// ||E - (I - R F) B|| / ||E||; 0 when E = 0.
double relativeResidual(const FormFactors& F, const Vector& rho, const Vector& E, const Vector& B);

using Transposed = TransposedFormFactors;

/// Called after each sweep with the channels' B already stored back (progressive display).
using SweepHook = std::function<void(int sweep)>;

/// Jacobi B <- E + R F B, all channels in one pass over F per sweep.
void solveJacobi(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options,
                 const SweepHook& afterSweep = {});
/// Gauss-Seidel sweeps in place, all channels in one pass over F.
void solveGaussSeidel(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options,
                      const SweepHook& afterSweep = {});
/// Southwell iteration (progressive refinement shooting) for one channel.
void solveSouthwell(const Scene& scene, const FormFactors& F, const Transposed& Ft, Channel& channel,
                    const SolverOptions& options);

using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

/// K = diag(A / rho) - sym(diag(A) F) on patches with rho > 0 (identity rows for black ones). The
/// off-diagonal part is the same for every channel with the same black patches, so it is built once
/// and only the diagonal is rewritten per channel.
class SymmetricForm {
public:
    SymmetricForm(const Scene& scene, const FormFactors& F, const Transposed& Ft) : m_scene(scene), m_F(F), m_Ft(Ft) {}
    /// K for `rho`; valid until the next call.
    const RowMatrix& matrixFor(const Vector& rho);

private:
    const Scene& m_scene;
    const FormFactors& m_F;
    const Transposed& m_Ft;
    RowMatrix m_K;
    std::vector<std::uint8_t> m_active;
    std::vector<int> m_diagonalAt;   ///< index of K_ii in the value array
    std::vector<double> m_self;      ///< A_i F_ii
};

/// The Eigen solvers for one reflectance vector: LU and BiCGSTAB on I - R F; Cholesky and CG on
/// K = diag(A / rho) - sym(diag(A) F) with black patches moved to the right-hand side.
class EigenSystem {
public:
    /// `symmetric` is needed for Cholesky and CG (else may be null) and must outlive this system.
    EigenSystem(const Scene& scene, const FormFactors& F, SymmetricForm* symmetric, const Vector& rho,
                SolverKind kind, const SolverOptions& options);
    ~EigenSystem();
    void solve(Channel& channel);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace hemirad::detail
