// Every patch pair's radiative conductor from one dense symmetric factorisation (see the header).
#include "thermal/patch_conductance.hpp"

#include "engine/error.hpp"
#include "engine/memory.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#ifdef HEMIRAD_HAVE_LAPACK
extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dpotri_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dsymm_(const char* side, const char* uplo, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* b, const int* ldb, const double* beta, double* c, const int* ldc);
void dgemm_(const char* ta, const char* tb, const int* m, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* b, const int* ldb, const double* beta, double* c, const int* ldc);
}
#endif

namespace hemirad::thermal {
namespace {

/// A diffuse reflectance at or below this is a rounding leftover of 1 - eps - s (1 - 0.7 - 0.3 =
/// 5.6e-17): the patch is taken as not reflecting diffusely. Above it, W = A / rho keeps the self
/// terms to about 1e-16 / rho relative (gebhartMethod's auto leaves rho below 1e-6 to the columns).
constexpr double kRoundingRho = 1e-12;

[[noreturn]] void notPositiveDefinite(const std::string& where) {
    throw Error("thermal: the Gebhart system is singular" + where +
                ": patches of diffuse reflectance near 1 (eps = s = 0) that nothing absorbs; give them an emissivity");
}

using Matrix = Eigen::Map<Eigen::MatrixXd>;

/// `count` zeroed doubles, aligned to 2 MiB and advised into transparent huge pages.
double* allocateZeroed(std::size_t count) {
    constexpr std::size_t kHuge = std::size_t(1) << 21;
    const std::size_t bytes = std::max<std::size_t>(kHuge, (count * sizeof(double) + kHuge - 1) / kHuge * kHuge);
    void* p = std::aligned_alloc(kHuge, bytes);
    if (!p) throw Error("thermal: cannot allocate " + std::to_string(bytes >> 20) + " MiB for the Gebhart factorisation");
    adviseHugePages(p, bytes);
    std::memset(p, 0, bytes);
    return static_cast<double*>(p);
}

/// The lower triangle of the leading p x p block of G (leading dimension G.rows()) becomes M^-1,
/// M = that block (symmetric positive definite, its lower triangle read). patchAt(row) names the
/// patch of a row for the message.
template <class PatchAt>
void invertSymmetric(Matrix& G, std::size_t p, PatchAt patchAt) {
    if (p == 0) return;
#ifdef HEMIRAD_HAVE_LAPACK
    const int n = int(p), lda = int(G.rows());
    int info = 0;
    dpotrf_("L", &n, G.data(), &lda, &info);
    if (info > 0) notPositiveDefinite(" at patch " + std::to_string(patchAt(std::size_t(info - 1))));
    dpotri_("L", &n, G.data(), &lda, &info);
    if (info > 0) notPositiveDefinite(" at patch " + std::to_string(patchAt(std::size_t(info - 1))));
#else
    (void)patchAt;
    const Eigen::Index n = Eigen::Index(p);
    Eigen::LLT<Eigen::MatrixXd> llt(G.topLeftCorner(n, n));
    if (llt.info() != Eigen::Success) notPositiveDefinite("");
    G.topLeftCorner(n, n).triangularView<Eigen::Lower>() = llt.solve(Eigen::MatrixXd::Identity(n, n));
#endif
}

/// With M^-1 in G's leading p x p lower triangle and S symmetric elsewhere: V = M^-1 S_PQ, the
/// lower-right block += S_QP V, the lower-left block = V^T.
void completeOthers(Matrix& G, std::size_t p) {
    const Eigen::Index n = G.rows(), P = Eigen::Index(p), Q = n - P;
    if (P == 0 || Q == 0) return;
    Eigen::MatrixXd V(P, Q);
#ifdef HEMIRAD_HAVE_LAPACK
    const int m = int(P), q = int(Q), lda = int(n), ldv = int(P);
    const double one = 1.0, zero = 0.0;
    dsymm_("L", "L", &m, &q, &one, G.data(), &lda, &G(0, P), &lda, &zero, V.data(), &ldv);
    dgemm_("N", "N", &q, &q, &m, &one, &G(P, 0), &lda, V.data(), &ldv, &one, &G(P, P), &lda);
#else
    V.noalias() = G.topLeftCorner(P, P).selfadjointView<Eigen::Lower>() * G.topRightCorner(P, Q);
    G.bottomRightCorner(Q, Q).noalias() += G.bottomLeftCorner(Q, P) * V;
#endif
    G.bottomLeftCorner(Q, P) = V.transpose();
}

}  // namespace

PatchConductance::PatchConductance(const FormFactors& F, const std::vector<double>& area, const std::vector<double>& eps,
                                   const std::vector<double>& rho) {
    const std::size_t n = F.size();
    if (area.size() != n || eps.size() != n || rho.size() != n)
        throw Error("thermal: " + std::to_string(area.size()) + " areas for F's " + std::to_string(n) + " rows");
    // P first (rho > 0), then Q, each in patch order.
    auto diffuse = [&](std::size_t i) { return rho[i] > kRoundingRho; };
    m_position.assign(n, 0);
    std::vector<std::size_t> patchAt(n);
    std::size_t p = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (diffuse(i)) patchAt[p] = i, m_position[i] = p++;
    for (std::size_t i = 0, q = p; i < n; ++i)
        if (!diffuse(i)) patchAt[q] = i, m_position[i] = q++;
    m_left.resize(n);
    m_self.assign(n, 0.0);
    std::vector<double> W(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        if (diffuse(i)) {
            W[i] = area[i] / rho[i];
            m_left[i] = eps[i] * W[i];
            m_self[i] = eps[i] * eps[i] * W[i];
        } else {
            m_left[i] = eps[i];
        }
    }

    // S = A F in the permuted order, each row written down a column (contiguous), then symmetrised
    // (F's reciprocity defect measured on the way).
    const Eigen::Index N = Eigen::Index(n);
    m_n = n;
    m_G.reset(allocateZeroed(n * n));
    Matrix G(m_G.get(), N, N);
    const std::uint32_t* columns = F.columns();
    const double* values = F.values();
    for (std::size_t i = 0; i < n; ++i) {
        if (!F.rowComputed(i)) throw Error("thermal: row " + std::to_string(i) + " of F was not computed");
        const Eigen::Index a = Eigen::Index(m_position[i]);
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k)
            G(Eigen::Index(m_position[columns[k]]), a) += area[i] * double(values[k]);
    }
    double worst = 0.0, largest = 0.0;
    for (Eigen::Index b = 0; b < N; ++b) {
        largest = std::max(largest, G(b, b));
        for (Eigen::Index a = b + 1; a < N; ++a) {
            const double x = G(a, b), y = G(b, a);
            worst = std::max(worst, std::abs(x - y));
            largest = std::max({largest, x, y});
            G(a, b) = G(b, a) = 0.5 * (x + y);
        }
    }
    m_asymmetry = largest > 0.0 ? worst / largest : 0.0;

    // M = W - S_PP (its lower triangle), inverted in place.
    std::vector<double> Wp(p);
    for (std::size_t i = 0; i < n; ++i)
        if (diffuse(i)) Wp[m_position[i]] = W[i];
    for (Eigen::Index b = 0; b < Eigen::Index(p); ++b) {
        for (Eigen::Index a = b; a < Eigen::Index(p); ++a) G(a, b) = -G(a, b);
        G(b, b) += Wp[std::size_t(b)];
    }
    invertSymmetric(G, p, [&](std::size_t row) { return patchAt[row]; });
    completeOthers(G, p);
}

std::size_t PatchConductance::memoryBytes(std::size_t patches) {
    // G, and V (|P| x |Q|, at most n^2 / 4) while the others are completed; Eigen's kernels hold a
    // copy of M and its inverse besides.
    const std::size_t square = patches * patches * sizeof(double);
    return square + square / 4 + (usesLapack() ? 0 : 2 * square);
}

bool PatchConductance::pays(std::size_t patches, std::size_t columns, std::size_t nonZeros) {
    // Measured on two cores: a column solve by SOR's batched sweeps costs about 1.2 ns per nonzero of
    // F (every sweep included); the factorisation and inverse about 1.2e-11 s per n^3 flop with
    // OpenBLAS and three times that in Eigen.
    const double n = double(patches);
    const double dense = n * n * n * (usesLapack() ? 1.2e-11 : 3.6e-11);
    const double byColumns = double(columns) * double(nonZeros) * 1.2e-9;
    return patches <= 2000 || dense < byColumns;
}

bool PatchConductance::usesLapack() {
#ifdef HEMIRAD_HAVE_LAPACK
    return true;
#else
    return false;
#endif
}

}  // namespace hemirad::thermal
