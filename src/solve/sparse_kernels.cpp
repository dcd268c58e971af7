// Kernels on the float CSR F: products, residuals and the transpose.
#include "solve/solver_detail.hpp"

namespace hemirad::detail {

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

double relativeResidual(const FormFactors& F, const Vector& rho, const Vector& E, const Vector& B) {
    Vector FB;
    multiplyF(F, B, FB);
    const double norm = E.norm();
    return norm > 0 ? (E - B + rho.cwiseProduct(FB)).norm() / norm : 0.0;
}

}  // namespace hemirad::detail
