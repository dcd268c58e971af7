// Internals shared by the solver files: channels, sparse kernels on the CSR F, the symmetric form.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/wide_kernels.hpp"
#include "engine/scene.hpp"
#include "solve/solver.hpp"

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
/// relativeResidual of every channel, in one pass over F for all of them (a year's batch of hours
/// would otherwise read F once per hour).
void relativeResiduals(const FormFactors& F, const std::vector<Channel*>& channels);
/// The same for m channels interleaved per patch (value (i, c) at [i m + c]): ||E - (I - R F) B||
/// per channel, unnormalised, into `norms` (m values).
void interleavedResidualNorms(const FormFactors& F, int m, const double* rho, const double* E, const double* B, double* norms);

using Transposed = TransposedFormFactors;

/// Called after each sweep with the channels' B already stored back (progressive display).
using SweepHook = std::function<void(int sweep)>;

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

}  // namespace hemirad::detail
