// Jacobi, Gauss-Seidel and SOR (Gauss-Seidel over-relaxed, the factor adapted to the sweeps'
// convergence) on all distinct channels at once (one pass over F serves every right-hand side), and
// Southwell progressive refinement (Cohen, Chen, Wallace & Greenberg 1988).
#include "solve/channel_block.hpp"
#include "solve/refined_sweeps.hpp"
#include "solve/solver_detail.hpp"
#include "solve/solver_registry.hpp"

#include "engine/interleaved_rows.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <omp.h>

namespace hemirad::detail {
namespace {

/// The channels a kernel handles: M when fixed (1..3, unrolled), else the block's (any number: a
/// year's hours solved together read F once a sweep for all of them).
template <int M>
int widthOf(const Block& b) {
    return M > 0 ? M : b.m;
}

/// Jacobi's rows [first, last) of many channels, tile by tile.
HEMIRAD_WIDE_KERNEL void jacobiRows(const FormFactors& F, const Block& b, std::size_t first, std::size_t last, double* next) {
    double sum[interleaved::kChunk];
    for (const Block::Tile& t : b.tiles) {
        const std::size_t w = std::size_t(t.width);
        for (std::size_t i = first; i < last; ++i) {
            interleaved::rowSums(F, i, F.rowEnd(i), b.B.data() + t.offset, w, t.width, sum);
            for (std::size_t c = 0; c < w; ++c) {
                const std::size_t at = t.offset + i * w + c;
                next[at] = b.E[at] + b.rho[at] * sum[c];
            }
        }
    }
}

template <int M>
void jacobiSweep(const FormFactors& F, const Block& b, std::vector<double>& next) {
    if constexpr (M == 0) {  // many channels: row blocks, the tiles in each (interleaved_rows.hpp)
        const auto blocks = std::ptrdiff_t((F.size() + interleaved::kBlockRows - 1) / interleaved::kBlockRows);
#pragma omp parallel for schedule(dynamic, 1)
        for (std::ptrdiff_t block = 0; block < blocks; ++block)
            jacobiRows(F, b, std::size_t(block) * interleaved::kBlockRows,
                       std::min(F.size(), std::size_t(block + 1) * interleaved::kBlockRows), next.data());
        return;
    }
    const auto n = static_cast<std::ptrdiff_t>(F.size());
    const std::uint32_t* col = F.columns();
    const double* val = F.values();
#pragma omp parallel
    {
        double sum[M > 0 ? M : 1];
#pragma omp for schedule(dynamic, 256)
        for (std::ptrdiff_t i = 0; i < n; ++i) {
            std::fill(sum, sum + M, 0.0);
            for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
                const double v = val[k];
                const double* x = &b.B[std::size_t(col[k]) * M];
                for (int c = 0; c < M; ++c) sum[c] += v * x[c];
            }
            for (int c = 0; c < M; ++c) next[i * M + c] = b.E[i * M + c] + b.rho[i * M + c] * sum[c];
        }
    }
}

/// A Gauss-Seidel step at value `at` from its row's sum over the others: the self factor solved
/// for exactly, the step moved omega times (SOR), its square added to `change`.
HEMIRAD_INLINE_KERNEL void update(Block& b, std::size_t at, double sum, double self, double omega, double& change) {
    const double exact = (b.E[at] + b.rho[at] * sum) / (1.0 - b.rho[at] * self);
    const double value = omega == 1.0 ? exact : b.B[at] + omega * (exact - b.B[at]);
    change += (value - b.B[at]) * (value - b.B[at]);
    b.B[at] = value;
}

/// One in-place sweep of channels [c0, c1) of a fixed number M (1..3); the self factor F_ii is
/// solved for exactly. With omega != 1, each value moves omega times the Gauss-Seidel step
/// (successive over-relaxation). Adds the squared changes per channel to change[c].
template <int M>
void gaussSeidelChannels(const FormFactors& F, Block& b, double omega, double* change) {
    const std::uint32_t* col = F.columns();
    const double* val = F.values();
    double changes[M] = {};
    double sum[M];
    for (std::size_t i = 0; i < F.size(); ++i) {
        std::fill(sum, sum + M, 0.0);
        double self = 0.0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) {
            const std::size_t j = col[k];
            if (j == i) {
                self = val[k];
                continue;
            }
            const double* x = &b.B[j * M];
            const double v = val[k];
            for (int c = 0; c < M; ++c) sum[c] += v * x[c];
        }
        for (int c = 0; c < M; ++c) update(b, i * M + std::size_t(c), sum[c], self, omega, changes[c]);
    }
    for (int c = 0; c < M; ++c) change[c] += changes[c];
}

/// The same for tiles [t0, t1) of any number of channels: rows in blocks, each block's tiles one
/// after the other (interleaved_rows.hpp). Each channel still meets the rows in order with its own
/// running sums, the very sweep it would get alone.
HEMIRAD_WIDE_KERNEL void gaussSeidelMany(const FormFactors& F, Block& b, std::size_t t0, std::size_t t1, double omega,
                                         double* change) {
    const std::size_t n = F.size();
    const double* val = F.values();
    const int c0 = b.tiles[t0].first, c1 = b.tiles[t1 - 1].first + b.tiles[t1 - 1].width;
    std::vector<double> changes(std::size_t(c1 - c0), 0.0);  // the thread's own
    std::uint64_t selfAt[interleaved::kBlockRows];
    double selfOf[interleaved::kBlockRows], sum[interleaved::kChunk];
    for (std::size_t r0 = 0; r0 < n; r0 += interleaved::kBlockRows) {
        const std::size_t r1 = std::min(n, r0 + interleaved::kBlockRows);
        for (std::size_t i = r0; i < r1; ++i) {
            selfAt[i - r0] = interleaved::selfEntry(F, i);
            selfOf[i - r0] = selfAt[i - r0] < F.rowEnd(i) ? double(val[selfAt[i - r0]]) : 0.0;
        }
        for (std::size_t k = t0; k < t1; ++k) {
            const Block::Tile& t = b.tiles[k];
            const std::size_t w = std::size_t(t.width);
            double* tileChanges = changes.data() + (t.first - c0);
            for (std::size_t i = r0; i < r1; ++i) {
                interleaved::rowSums(F, i, selfAt[i - r0], b.B.data() + t.offset, w, t.width, sum);
                const double self = selfOf[i - r0];
                for (std::size_t c = 0; c < w; ++c) update(b, t.offset + i * w + c, sum[c], self, omega, tileChanges[c]);
            }
        }
    }
    for (int c = c0; c < c1; ++c) change[c] += changes[std::size_t(c - c0)];
}

/// One in-place sweep of every channel. Up to three channels sweep on one thread: measured here,
/// two threads splitting the rows (Jacobi between the halves) needed 50% more sweeps and ran slower
/// on a memory-bound 2-core machine. Many channels (a year's hours) split among the threads by
/// channel instead: each thread sweeps every row for its own channels, the very sweep one thread
/// would make, so the result does not depend on the thread count. (Here the channels go to the
/// threads a tile at a time.)
template <int M>
void gaussSeidelSweep(const FormFactors& F, Block& b, double omega, double* change) {
    if constexpr (M > 0) {
        gaussSeidelChannels<M>(F, b, omega, change);
    } else if (b.m < kSplitChannels) {
        gaussSeidelMany(F, b, 0, b.tiles.size(), omega, change);
    } else {
#pragma omp parallel
        {
            const std::size_t threads = std::size_t(omp_get_num_threads()), t = std::size_t(omp_get_thread_num());
            const std::size_t t0 = b.tiles.size() * t / threads, t1 = b.tiles.size() * (t + 1) / threads;
            if (t1 > t0) gaussSeidelMany(F, b, t0, t1, omega, change);
        }
    }
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
        const std::vector<double> norms = residualNorms(F, b);  // every channel's, one pass over F
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
    Block b(channels, false);  // Jacobi splits the rows among the threads
    const int m = widthOf<M>(b);
    std::vector<double> next(b.B.size());
    iterate(F, channels, options, hook, b, [&] {
        jacobiSweep<M>(F, b, next);
        double worst = 0.0;  // ||B' - B|| / ||E|| is exactly the residual of B
        std::vector<double> steps(std::size_t(m), 0.0);
        b.forEach([&](std::size_t, int c, std::size_t at) { steps[std::size_t(c)] += (next[at] - b.B[at]) * (next[at] - b.B[at]); });
        for (int c = 0; c < m; ++c) worst = std::max(worst, std::sqrt(steps[std::size_t(c)]) / b.normE[std::size_t(c)]);
        b.B.swap(next);
        return worst;
    });
}

template <int M>
void gaussSeidel(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options,
                 const SweepHook& hook, bool relax) {
    if (M == 0 && int(channels.size()) >= kSplitChannels && !hook)  // a sweep hook shows B after each sweep: in double
        return gaussSeidelRefined(F, channels, options, relax);
    Block b(channels, M == 0 && int(channels.size()) >= kSplitChannels);
    const int m = widthOf<M>(b);
    std::vector<double> change(static_cast<std::size_t>(m));
    OverRelaxation relaxation;
    double omega = 1.0;
    iterate(F, channels, options, hook, b, [&] {
        std::fill(change.begin(), change.end(), 0.0);
        gaussSeidelSweep<M>(F, b, omega, change.data());
        double worst = 0.0;
        for (int c = 0; c < m; ++c) worst = std::max(worst, std::sqrt(change[std::size_t(c)]) / b.normE[std::size_t(c)]);
        if (relax) omega = relaxation.next(worst);
        return worst;
    });
    if (relax)
        for (Channel* ch : channels) ch->report.note = relaxation.describe();
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
                      const SweepHook& afterSweep, bool relax) {
    switch (channels.size()) {
    case 1: gaussSeidel<1>(F, channels, options, afterSweep, relax); break;
    case 2: gaussSeidel<2>(F, channels, options, afterSweep, relax); break;
    case 3: gaussSeidel<3>(F, channels, options, afterSweep, relax); break;
    default: gaussSeidel<0>(F, channels, options, afterSweep, relax); break;  // any number of channels
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

/// Jacobi, Gauss-Seidel and SOR solve all channels in one pass over F a sweep.
template <class Sweeps>
void solveTogether(Sweeps&& sweeps, const SolveProblem& p, std::vector<Channel*>& active) {
    const auto start = std::chrono::steady_clock::now();
    sweeps(p.F, active, p.options, p.afterSweep);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (Channel* ch : active) {
        ch->report.seconds = seconds;
        if (active.size() > 1)
            ch->report.note += (ch->report.note.empty() ? "" : "; ") + std::string("channels ") + std::to_string(active.size()) +
                               " solved together";
    }
}

}  // namespace

}  // namespace hemirad::detail

namespace hemirad {

const std::vector<SolverDescriptor>& stationarySolvers() {
    using namespace detail;
    static const std::vector<SolverDescriptor> family = [] {
        std::vector<SolverDescriptor> solvers(4);
        for (SolverDescriptor& d : solvers) d.flags = {"--tolerance", "--max-iterations"};
        for (int k = 0; k < 3; ++k) solvers[std::size_t(k)].residualOnPosedSystem = true;  // iterate's last check
        solvers[0].name = "jacobi";
        solvers[0].summary = "Jacobi sweeps B <- E + R F B, all channels in one pass over F";
        solvers[0].solve = [](const SolveProblem& p, std::vector<Channel*>& active) { solveTogether(solveJacobi, p, active); };
        solvers[1].name = "gauss-seidel";
        solvers[1].summary = "Gauss-Seidel sweeps in place, all channels in one pass over F";
        solvers[1].solve = [](const SolveProblem& p, std::vector<Channel*>& active) {
            solveTogether([](auto&&... a) { solveGaussSeidel(a..., false); }, p, active);
        };
        solvers[2].name = "sor";
        solvers[2].summary = "successive over-relaxation: Gauss-Seidel sweeps, the factor from their convergence (Young)";
        solvers[2].solve = [](const SolveProblem& p, std::vector<Channel*>& active) {
            solveTogether([](auto&&... a) { solveGaussSeidel(a..., true); }, p, active);
        };
        solvers[3].name = "southwell";
        solvers[3].summary = "Southwell iteration: progressive refinement, shooting the largest unshot power";
        solvers[3].needsTranspose = true;
        solvers[3].solve = [](const SolveProblem& p, std::vector<Channel*>& active) {
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
