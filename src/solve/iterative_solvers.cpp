// Jacobi and Gauss-Seidel on all distinct channels at once (one pass over F serves up to three
// right-hand sides), and Southwell progressive refinement (Cohen, Chen, Wallace & Greenberg 1988).
#include "solve/solver_detail.hpp"
#include "solve/solver_registry.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <omp.h>

namespace hemirad::detail {
namespace {

/// Channels interleaved per patch: value (i, c) at [i * M + c], so one pass over F reads each
/// entry once for all channels.
struct Block {
    int m = 0;
    std::vector<double> rho, E, B;
    std::vector<double> normE;

    explicit Block(const std::vector<Channel*>& channels) : m(static_cast<int>(channels.size())) {
        const auto n = static_cast<std::size_t>(channels[0]->rho.size());
        rho.resize(n * m);
        E.resize(n * m);
        B.resize(n * m);
        for (int c = 0; c < m; ++c) {
            for (std::size_t i = 0; i < n; ++i) {
                rho[i * m + c] = channels[c]->rho[i];
                E[i * m + c] = channels[c]->E[i];
                B[i * m + c] = channels[c]->B[i];
            }
            normE.push_back(channels[c]->E.norm());
        }
    }
    void store(std::vector<Channel*>& channels) const {
        for (int c = 0; c < m; ++c)
            for (Eigen::Index i = 0; i < channels[c]->B.size(); ++i) channels[c]->B[i] = B[i * m + c];
    }
};

/// The channels a kernel handles: M when fixed (1..3, unrolled), else the block's (any number: a
/// year's hours solved together read F once a sweep for all of them).
template <int M>
int widthOf(const Block& b) {
    return M > 0 ? M : b.m;
}

template <int M>
void jacobiSweep(const FormFactors& F, const Block& b, std::vector<double>& next) {
    const auto n = static_cast<std::ptrdiff_t>(F.size());
    const std::uint32_t* col = F.columns();
    const float* val = F.values();
    const int m = widthOf<M>(b);
#pragma omp parallel
    {
        std::vector<double> dynamic(M > 0 ? 0 : std::size_t(m));
        double fixed[M > 0 ? M : 1];
        double* sum = M > 0 ? fixed : dynamic.data();
#pragma omp for schedule(dynamic, 256)
        for (std::ptrdiff_t i = 0; i < n; ++i) {
            std::fill(sum, sum + m, 0.0);
            for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
                const double v = val[k];
                const double* x = &b.B[std::size_t(col[k]) * m];
                for (int c = 0; c < m; ++c) sum[c] += v * x[c];
            }
            for (int c = 0; c < m; ++c) next[i * m + c] = b.E[i * m + c] + b.rho[i * m + c] * sum[c];
        }
    }
}

/// One in-place sweep of channels [c0, c1); the self factor F_ii is solved for exactly. Adds the
/// squared changes per channel to change[c].
template <int M>
HEMIRAD_INLINE_KERNEL void gaussSeidelChannels(const FormFactors& F, Block& b, int c0, int c1, double* change) {
    const std::uint32_t* col = F.columns();
    const float* val = F.values();
    const std::size_t m = std::size_t(widthOf<M>(b));
    const int w = M > 0 ? M : c1 - c0;
    std::vector<double> dynamic(M > 0 ? 0 : std::size_t(w)), changes(std::size_t(w), 0.0);  // changes: the thread's own
    double fixed[M > 0 ? M : 1];
    double* sum = M > 0 ? fixed : dynamic.data();
    for (std::size_t i = 0; i < F.size(); ++i) {
        std::fill(sum, sum + w, 0.0);
        double self = 0.0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            const std::size_t j = col[k];
            if (j == i) {
                self = val[k];
                continue;
            }
            const double* x = &b.B[j * m + std::size_t(c0)];
            const double v = val[k];
            for (int c = 0; c < w; ++c) sum[c] += v * x[c];
        }
        for (int c = 0; c < w; ++c) {
            const std::size_t at = i * m + std::size_t(c0 + c);
            const double value = (b.E[at] + b.rho[at] * sum[c]) / (1.0 - b.rho[at] * self);
            changes[std::size_t(c)] += (value - b.B[at]) * (value - b.B[at]);
            b.B[at] = value;
        }
    }
    for (int c = 0; c < w; ++c) change[c0 + c] += changes[std::size_t(c)];
}

/// gaussSeidelChannels for any number of channels, compiled for wide vectors too (chosen at run time).
HEMIRAD_WIDE_KERNEL void gaussSeidelMany(const FormFactors& F, Block& b, int c0, int c1, double* change) {
    gaussSeidelChannels<0>(F, b, c0, c1, change);
}

/// One in-place sweep of every channel. Up to three channels sweep on one thread: measured here,
/// two threads splitting the rows (Jacobi between the halves) needed 50% more sweeps and ran slower
/// on a memory-bound 2-core machine. Many channels (a year's hours) split among the threads by
/// channel instead: each thread sweeps every row for its own channels, the very sweep one thread
/// would make, so the result does not depend on the thread count.
template <int M>
void gaussSeidelSweep(const FormFactors& F, Block& b, double* change) {
    const int m = widthOf<M>(b);
    if (M == 0 && m >= 32) {  // fewer: the threads' channels would share cache lines row after row
#pragma omp parallel
        {
            const std::int64_t threads = omp_get_num_threads(), t = omp_get_thread_num();
            const int c0 = int(m * t / threads), c1 = int(m * (t + 1) / threads);
            if (c1 > c0) gaussSeidelMany(F, b, c0, c1, change);
        }
        return;
    }
    gaussSeidelChannels<M>(F, b, 0, m, change);
}

/// Decides when a sweep's step (||B' - B|| / ||E||, cheap) justifies computing the true residuals
/// (one product with F per channel). After a check that fails, the step threshold is lowered by the
/// observed residual/step ratio, so a slowly converging solve pays for few checks.
class ConvergenceCheck {
public:
    explicit ConvergenceCheck(double tolerance) : m_tolerance(tolerance), m_threshold(tolerance) {}

    /// True when every channel's true residual meets the tolerance (reports updated then).
    bool operator()(double step, const FormFactors& F, std::vector<Channel*>& channels, const Block& b) {
        if (step > m_threshold) return false;
        return check(step, F, channels, b);
    }
    bool check(double step, const FormFactors& F, std::vector<Channel*>& channels, const Block& b) {
        b.store(channels);
        // Every channel's residual in one pass over F (the block is interleaved already).
        std::vector<double> norms(std::size_t(b.m));
        interleavedResidualNorms(F, b.m, b.rho.data(), b.E.data(), b.B.data(), norms.data());
        double worst = 0.0;
        for (std::size_t c = 0; c < channels.size(); ++c) {
            Channel* ch = channels[c];
            ch->report.residual = b.normE[c] > 0 ? norms[c] / b.normE[c] : 0.0;
            ch->report.converged = ch->report.residual <= m_tolerance;
            worst = std::max(worst, ch->report.residual);
        }
        if (worst <= m_tolerance) return true;
        if (step > 0.0 && worst > 0.0) m_threshold = std::min(m_threshold, 0.9 * m_tolerance * step / worst);
        return false;
    }

private:
    double m_tolerance, m_threshold;
};

/// The sweep loop of Jacobi and Gauss-Seidel: `sweep` advances `b` by one sweep and returns the
/// worst channel's step ||B' - B|| / ||E||.
template <class Sweep>
void iterate(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options,
             const SweepHook& hook, Block& b, Sweep&& sweep) {
    ConvergenceCheck converged(options.tolerance);
    for (int it = 1; it <= options.maxIterations; ++it) {
        const double worst = sweep();
        for (Channel* ch : channels) ch->report.iterations = it;
        if (!std::isfinite(worst)) break;
        if (converged(worst, F, channels, b)) return;
        if (hook) {
            b.store(channels);
            hook(it);
        }
    }
    converged.check(0.0, F, channels, b);
}

template <int M>
void jacobi(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options, const SweepHook& hook) {
    Block b(channels);
    const int m = widthOf<M>(b);
    std::vector<double> next(b.B.size());
    iterate(F, channels, options, hook, b, [&] {
        jacobiSweep<M>(F, b, next);
        double worst = 0.0;  // ||B' - B|| / ||E|| is exactly the residual of B
        for (int c = 0; c < m; ++c) {
            double step = 0.0;
            for (std::size_t i = std::size_t(c); i < next.size(); i += std::size_t(m)) step += (next[i] - b.B[i]) * (next[i] - b.B[i]);
            worst = std::max(worst, std::sqrt(step) / b.normE[std::size_t(c)]);
        }
        b.B.swap(next);
        return worst;
    });
}

template <int M>
void gaussSeidel(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options,
                 const SweepHook& hook) {
    Block b(channels);
    const int m = widthOf<M>(b);
    std::vector<double> change(static_cast<std::size_t>(m));
    iterate(F, channels, options, hook, b, [&] {
        std::fill(change.begin(), change.end(), 0.0);
        gaussSeidelSweep<M>(F, b, change.data());
        double worst = 0.0;
        for (int c = 0; c < m; ++c) worst = std::max(worst, std::sqrt(change[std::size_t(c)]) / b.normE[std::size_t(c)]);
        return worst;
    });
}

void solveJacobi(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options,
                 const SweepHook& afterSweep) {
    switch (channels.size()) {
    case 1: jacobi<1>(F, channels, options, afterSweep); break;
    case 2: jacobi<2>(F, channels, options, afterSweep); break;
    case 3: jacobi<3>(F, channels, options, afterSweep); break;
    default: jacobi<0>(F, channels, options, afterSweep); break;  // any number of channels
    }
}

void solveGaussSeidel(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options,
                      const SweepHook& afterSweep) {
    switch (channels.size()) {
    case 1: gaussSeidel<1>(F, channels, options, afterSweep); break;
    case 2: gaussSeidel<2>(F, channels, options, afterSweep); break;
    case 3: gaussSeidel<3>(F, channels, options, afterSweep); break;
    default: gaussSeidel<0>(F, channels, options, afterSweep); break;  // any number of channels
    }
}

void solveSouthwell(const Scene& scene, const FormFactors& F, const Transposed& Ft, Channel& ch,
                    const SolverOptions& options) {
    const auto n = static_cast<Eigen::Index>(F.size());
    Vector& B = ch.B;
    Vector FB;
    multiplyF(F, B, FB);
    // Solve for the correction x = B* - B of the start: (I - R F) x = r, shot like an emission.
    Vector unshot = ch.E + ch.rho.cwiseProduct(FB) - B;
    B += unshot;
    Vector area(n);
    for (Eigen::Index i = 0; i < n; ++i) area[i] = scene.patches[i].area;
    Vector power = area.cwiseProduct(unshot.cwiseAbs());
    // Block maxima (64 patches a block) make "find the largest unshot power" O(N/64 + 64).
    constexpr Eigen::Index kBlock = 64;
    const Eigen::Index blocks = (n + kBlock - 1) / kBlock;
    Vector blockMax(blocks);
    auto refresh = [&](Eigen::Index blk) {
        const Eigen::Index lo = blk * kBlock, len = std::min(kBlock, n - lo);
        blockMax[blk] = power.segment(lo, len).maxCoeff();
    };
    for (Eigen::Index blk = 0; blk < blocks; ++blk) refresh(blk);
    const double normE = ch.E.norm();
    for (int sweep = 1; sweep <= options.maxIterations; ++sweep) {
        for (Eigen::Index shot = 0; shot < n; ++shot) {
            Eigen::Index blk;
            if (blockMax.maxCoeff(&blk) <= 0.0) break;
            Eigen::Index i;
            const Eigen::Index lo = blk * kBlock;
            power.segment(lo, std::min(kBlock, n - lo)).maxCoeff(&i);
            i += lo;
            const double dB = unshot[i];
            unshot[i] = 0.0;
            power[i] = 0.0;
            for (std::uint64_t k = Ft.start[i]; k < Ft.start[i + 1]; ++k) {
                const std::uint32_t j = Ft.rows[k];
                const double received = ch.rho[j] * Ft.values[k] * dB;
                B[j] += received;
                unshot[j] += received;
                power[j] = area[j] * std::abs(unshot[j]);
                blockMax[j / kBlock] = std::max(blockMax[j / kBlock], power[j]);
            }
            refresh(blk);  // the shooter's block lost its maximum
        }
        ch.report.iterations = sweep;
        Vector Fu;
        multiplyF(F, unshot, Fu);
        ch.report.residual = ch.rho.cwiseProduct(Fu).norm() / normE;  // the residual is R F (unshot)
        if (!std::isfinite(ch.report.residual)) return;
        if (ch.report.residual <= options.tolerance) {
            ch.report.converged = true;
            return;
        }
        // Stale block maxima (|unshot| can shrink with a warm start) are refreshed once a sweep.
        for (Eigen::Index blk = 0; blk < blocks; ++blk) refresh(blk);
    }
    ch.report.note = "iterations count sweeps of N shots";
}

/// Jacobi and Gauss-Seidel solve all channels in one pass over F a sweep.
void solveTogether(void (*sweeps)(const FormFactors&, std::vector<Channel*>&, const SolverOptions&, const SweepHook&),
                   const SolveProblem& p, std::vector<Channel*>& active) {
    const auto start = std::chrono::steady_clock::now();
    sweeps(p.F, active, p.options, p.afterSweep);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (Channel* ch : active) {
        ch->report.seconds = seconds;
        if (active.size() > 1) ch->report.note = "channels " + std::to_string(active.size()) + " solved together";
    }
}

}  // namespace

}  // namespace hemirad::detail

namespace hemirad {

const std::vector<SolverDescriptor>& stationarySolvers() {
    using namespace detail;
    static const std::vector<SolverDescriptor> family = [] {
        std::vector<SolverDescriptor> solvers(3);
        for (SolverDescriptor& d : solvers) d.flags = {"--tolerance", "--max-iterations"};
        solvers[0].name = "jacobi";
        solvers[0].summary = "Jacobi sweeps B <- E + R F B, all channels in one pass over F";
        solvers[0].solve = [](const SolveProblem& p, std::vector<Channel*>& active) { solveTogether(solveJacobi, p, active); };
        solvers[1].name = "gauss-seidel";
        solvers[1].summary = "Gauss-Seidel sweeps in place, all channels in one pass over F (the default above 2000 patches)";
        solvers[1].solve = [](const SolveProblem& p, std::vector<Channel*>& active) {
            solveTogether(solveGaussSeidel, p, active);
        };
        solvers[2].name = "southwell";
        solvers[2].summary = "Southwell iteration: progressive refinement, shooting the largest unshot power";
        solvers[2].needsTranspose = true;
        solvers[2].solve = [](const SolveProblem& p, std::vector<Channel*>& active) {
            for (Channel* ch : active) {
                const auto t0 = std::chrono::steady_clock::now();
                solveSouthwell(p.scene, p.F, *p.Ft, *ch, p.options);
                ch->report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            }
        };
        return solvers;
    }();
    return family;
}

}  // namespace hemirad
