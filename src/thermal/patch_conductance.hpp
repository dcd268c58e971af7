// Every patch pair's radiative conductor from one dense symmetric factorisation. With S = A F
// (m^2, symmetrised), the patches P that reflect diffusely (rho_d > 0) and the others Q (black, or
// purely specular), W = A / rho_d on P and M = W - S_PP, symmetric positive definite when
// rho_d,i sum_j F_ij < 1, the conductors GR = eps S (I - rho_d F)^-1 eps are
//
//     GR_PP = eps (W M^-1 W - W) eps,   GR_PQ = eps W M^-1 S_PQ eps,   GR_QQ = eps (S_QP M^-1 S_PQ + S_QQ) eps
//
// (push (I - rho_d F)^-1 = (W - S)^-1 W through S = W - M). One Cholesky factorisation and inverse
// of M, |P|^3 flops, replace a column solve per patch; with LAPACK (OpenBLAS) at about 90 Gflop/s
// on two cores.
#pragma once

#include "engine/form_factors.hpp"

#include <Eigen/Dense>

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <vector>

namespace hemirad::thermal {

class PatchConductance {
public:
    /// Per patch: area (m^2), emissivity eps and diffuse reflectance rho (>= 0; at most 1e-12, a
    /// rounding leftover of 1 - eps - s, counts as 0); F with every row.
    /// Throws hemirad::Error when M is not positive definite (a diffuse reflectance of 1 enclosed by
    /// such patches alone). Threads: OpenMP's count (LAPACK's and Eigen's products).
    PatchConductance(const FormFactors& F, const std::vector<double>& area, const std::vector<double>& eps,
                     const std::vector<double>& rho);

    std::size_t size() const { return m_position.size(); }
    /// GR_ij = GR_ji = eps_i A_i B_ij, m^2 (i == j: what i absorbs of its own emission).
    double operator()(std::size_t i, std::size_t j) const {
        const std::size_t a = m_position[i], b = m_position[j];
        const double g = a >= b ? m_G[b * m_n + a] : m_G[a * m_n + b];
        return m_left[i] * m_left[j] * g - (i == j ? m_self[i] : 0.0);
    }
    /// max |A_i F_ij - A_j F_ji| / max A_i F_ij: F's reciprocity defect, which symmetrising S removes.
    double asymmetry() const { return m_asymmetry; }

    /// Bytes the factorisation holds: one n x n matrix of doubles (and a |P| x |Q| one while built).
    static std::size_t memoryBytes(std::size_t patches);
    /// Whether one dense factorisation of n patches is expected to beat `columns` column solves over
    /// F's `nonZeros` (the measured costs of both routes on this kind of machine).
    static bool pays(std::size_t patches, std::size_t columns, std::size_t nonZeros);
    /// Whether the factorisation runs in LAPACK (OpenBLAS) rather than Eigen's own, slower kernels.
    static bool usesLapack();

private:
    std::vector<std::size_t> m_position;  ///< patch -> its row in m_G (P first, then Q)
    std::vector<double> m_left;           ///< eps W on P, eps on Q
    std::vector<double> m_self;           ///< eps^2 W on P (the diagonal's -eps W eps), 0 on Q
    struct Free {
        void operator()(double* p) const { std::free(p); }
    };
    std::size_t m_n = 0;
    /// n x n, column-major, in huge pages where the kernel gives them (a fault per 4 KiB page cost
    /// 2.3 s of 10k patches' 840 MB on a virtual machine). Lower triangle (row a >= column b):
    ///     [ M^-1             .                   ]
    ///     [ (M^-1 S_PQ)^T    S_QP M^-1 S_PQ + S_QQ ]
    std::unique_ptr<double[], Free> m_G;
    double m_asymmetry = 0.0;
};

}  // namespace hemirad::thermal
