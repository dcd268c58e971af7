// The channels of a many-channel stationary solve in tiles (Block), SOR's adaptive factor
// (OverRelaxation) and the residual of every channel in one pass over F: shared by the double sweeps
// (iterative_solvers.cpp) and the float correction sweeps of iterative refinement (refined_sweeps.cpp).
#pragma once

#include "solve/solver_detail.hpp"

#include "engine/interleaved_rows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace hemirad::detail {

/// Channels in tiles of at most interleaved::kChunk, each tile interleaved per patch: tile t's value
/// (i, c) at [offset_t + i * width_t + c - first_t]. One pass over F reads each entry once for all
/// channels, and a tile's gathers by F's columns (width_t values a patch, next to each other) stay
/// within its own n x width_t values: on street64k's ray F, 157 hours in one stride-157 array took
/// 12.7 ms a pass and hour, in tiles of 16 about 5 ms (the hours' values of a patch then sit in
/// whole cache lines, and a tile fits in the cache a core shares). Up to three channels make one
/// tile, as before.
struct Block {
    struct Tile {
        int first = 0, width = 0;
        std::size_t offset = 0;
    };
    int m = 0;
    std::size_t n = 0;
    std::vector<int> widths;  ///< the tiles' widths, as multiplyTiled takes them
    std::vector<Tile> tiles;
    std::vector<double> rho, E, B;
    std::vector<double> normE;

    /// `pairs`: the tiles come in an even number (for two threads to split), as even as can be. The
    /// tiles follow the number of channels alone, never the thread count: a channel meets the same
    /// code (the same fixed-width loops) on any number of threads, so its bits cannot depend on it
    /// (they did under -O2 with sanitizers when the tiles followed the threads).
    Block(const std::vector<Channel*>& channels, bool pairs)
        : m(static_cast<int>(channels.size())), n(static_cast<std::size_t>(channels[0]->rho.size())),
          widths(interleaved::tileWidths(m, interleaved::kChunk, pairs)) {
        for (int t = 0, first = 0; t < int(widths.size()); first += widths[std::size_t(t)], ++t)
            tiles.push_back({first, widths[std::size_t(t)], std::size_t(first) * n});
        rho.resize(n * m);
        E.resize(n * m);
        B.resize(n * m);
        forEach([&](std::size_t i, int c, std::size_t at) {
            rho[at] = channels[c]->rho[Eigen::Index(i)];
            E[at] = channels[c]->E[Eigen::Index(i)];
            B[at] = channels[c]->B[Eigen::Index(i)];
        });
        for (const Channel* ch : channels) normE.push_back(ch->E.norm());
    }
    /// f(i, c, at) for every value: patch i, channel c, its place.
    template <class Visit>
    void forEach(Visit&& f) const {
        for (const Tile& t : tiles)
            for (std::size_t i = 0, at = t.offset; i < n; ++i)
                for (int c = t.first; c < t.first + t.width; ++c, ++at) f(i, c, at);
    }
    void store(std::vector<Channel*>& channels) const {
        forEach([&](std::size_t i, int c, std::size_t at) { channels[c]->B[Eigen::Index(i)] = B[at]; });
    }
};

/// Successive over-relaxation's factor from the sweeps' own convergence, adaptively (after Hageman
/// & Young, Applied Iterative Methods, 1981, ch. 9): Gauss-Seidel sweeps first (omega = 1); then,
/// whenever two sweeps at the same omega shrink the step by lambda, the Jacobi radius squared it
/// implies for a consistently ordered system, mu^2 = (lambda + omega - 1)^2 / (lambda omega^2),
/// and Young's optimum for the largest mu^2 seen, omega = 2 / (1 + sqrt(1 - mu^2)). The estimates
/// come from below, so omega only grows; a ratio within (omega - 1)^0.75 says omega is already
/// large enough (at and past the optimum the steps shrink by about omega - 1, unevenly).
/// I - R F scaled by rows is symmetric positive definite for a reciprocal F with rho < 1 and row
/// sums <= 1, where any omega in (0, 2) converges. Where, from the third sweep after a new omega on,
/// a step is above the step it was chosen at or twice the smallest since (a non-reciprocal F, where
/// Young's factor can diverge), the factor goes back to 1 for good.
/// Measured (sweeps to a residual of 1e-10, Gauss-Seidel -> SOR): cornell13k 26 -> 15, a week of
/// street64k's hours on its ray F 15 -> 11; a stand-alone sweep found the best fixed factors there
/// at 14 and 10 sweeps.
class OverRelaxation {
public:
    /// The factor for the next sweep, given this sweep's step.
    double next(double step) {
        ++m_sweeps;
        ++m_atOmega;
        const double lambda = m_last > 0.0 ? step / m_last : 0.0;
        m_last = step;
        if (m_fallback) return m_omega;
        m_smallest = m_atOmega == 1 ? step : std::min(m_smallest, step);
        if (m_omega > 1.0 && m_atOmega >= 3 && (step > m_chosenAt || step > 2.0 * m_smallest)) {
            m_fallback = true;
            m_omega = 1.0;
            return m_omega;
        }
        if (m_sweeps < 3 || m_atOmega < 2 || !(lambda > 0.0 && lambda < 1.0)) return m_omega;
        if (m_omega > 1.0 && lambda <= std::pow(m_omega - 1.0, 0.75)) return m_omega;
        const double mu2 = (lambda + m_omega - 1.0) * (lambda + m_omega - 1.0) / (lambda * m_omega * m_omega);
        if (mu2 > m_mu2 && mu2 < 1.0) {
            m_mu2 = mu2;
            const double omega = std::min(kMaxOmega, 2.0 / (1.0 + std::sqrt(1.0 - mu2)));
            if (omega > m_omega + 1e-3) {
                m_omega = omega;
                m_atOmega = 0;
                m_chosenAt = step;
            }
        }
        return m_omega;
    }
    /// A new system with the same matrix (iterative refinement's next correction): the factor and
    /// the radius estimate stay; the steps start over (the first ones are far smaller than the last).
    void restart() {
        m_atOmega = 0;
        m_last = 0.0;
        m_chosenAt = std::numeric_limits<double>::infinity();
    }
    /// "relaxation factor 1.094", and why it went back to 1 if it did.
    std::string describe() const {
        char factor[32];
        std::snprintf(factor, sizeof factor, "%.3f", m_omega);
        return std::string("relaxation factor ") + factor +
               (m_fallback ? " (over-relaxation made the steps grow: Gauss-Seidel sweeps from then on)" : "");
    }

private:
    static constexpr double kMaxOmega = 1.95;
    int m_sweeps = 0, m_atOmega = 0;
    double m_omega = 1.0, m_mu2 = 0.0, m_last = 0.0, m_chosenAt = 0.0, m_smallest = 0.0;
    bool m_fallback = false;
};

/// r = E - (I - R F) B for every value of `b` (into `r` when given, in b's layout) and each
/// channel's ||r||, in one pass over F for all tiles.
inline std::vector<double> residualNorms(const FormFactors& F, const Block& b, std::vector<double>* r = nullptr) {
    std::vector<double> FB(b.B.size()), norms(std::size_t(b.m), 0.0);
    multiplyTiled(F, b.widths, b.B.data(), FB.data());
    if (r) r->resize(b.B.size());
    b.forEach([&](std::size_t, int c, std::size_t at) {
        const double value = b.E[at] - b.B[at] + b.rho[at] * FB[at];
        norms[std::size_t(c)] += value * value;
        if (r) (*r)[at] = value;
    });
    for (double& norm : norms) norm = std::sqrt(norm);
    return norms;
}

}  // namespace hemirad::detail
