// Kernels on the CSR F: products, residuals and the transpose.
#include "solve/solver_detail.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad::detail {

void multiplyF(const FormFactors& F, const Vector& x, Vector& y) {
    const auto n = static_cast<std::ptrdiff_t>(F.size());
    y.resize(n);
    const std::uint32_t* col = F.columns();
    const double* val = F.values();
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        double sum = 0.0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) sum += val[k] * x[col[k]];
        y[i] = sum;
    }
}

double relativeResidual(const FormFactors& F, const Vector& rho, const Vector& E, const Vector& B) {
    Vector FB;
    multiplyF(F, B, FB);
    const double norm = E.norm();
    return norm > 0 ? (E - B + rho.cwiseProduct(FB)).norm() / norm : 0.0;
}

void interleavedResidualNorms(const FormFactors& F, int m, const double* rho, const double* E, const double* B, double* norms) {
    std::vector<double> FB;
    multiplyInterleaved(F, std::size_t(m), B, FB);
    std::fill(norms, norms + m, 0.0);
    for (std::size_t at = 0; at < FB.size(); at += std::size_t(m))
        for (int c = 0; c < m; ++c) {
            const double r = E[at + c] - B[at + c] + rho[at + c] * FB[at + c];
            norms[c] += r * r;
        }
    for (int c = 0; c < m; ++c) norms[c] = std::sqrt(norms[c]);
}

void relativeResiduals(const FormFactors& F, const std::vector<Channel*>& channels) {
    if (channels.size() <= 1) {
        for (Channel* ch : channels) ch->report.residualOriginal = ch->E.norm() > 0 ? relativeResidual(F, ch->rho, ch->E, ch->B) : 0.0;
        return;
    }
    const std::size_t n = F.size(), m = channels.size();
    std::vector<double> rho(n * m), E(n * m), B(n * m), norms(m);
    for (std::size_t c = 0; c < m; ++c)
        for (std::size_t i = 0; i < n; ++i) {
            rho[i * m + c] = channels[c]->rho[Eigen::Index(i)];
            E[i * m + c] = channels[c]->E[Eigen::Index(i)];
            B[i * m + c] = channels[c]->B[Eigen::Index(i)];
        }
    interleavedResidualNorms(F, int(m), rho.data(), E.data(), B.data(), norms.data());
    for (std::size_t c = 0; c < m; ++c) {
        const double e = channels[c]->E.norm();
        channels[c]->report.residualOriginal = e > 0 ? norms[c] / e : 0.0;
    }
}

}  // namespace hemirad::detail
