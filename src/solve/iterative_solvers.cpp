// Jacobi, Gauss-Seidel and SOR (Gauss-Seidel over-relaxed, the factor adapted to the sweeps'
// convergence) on all distinct channels at once (one pass over F serves every right-hand side), and
// Southwell progressive refinement (Cohen, Chen, Wallace & Greenberg 1988).
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
    std::vector<Tile> tiles;
    std::vector<double> rho, E, B;
    std::vector<double> normE;

    /// `pairs`: the tiles come in an even number (for two threads to split), as even as can be. The
    /// tiles follow the number of channels alone, never the thread count: a channel meets the same
    /// code (the same fixed-width loops) on any number of threads, so its bits cannot depend on it
    /// (they did under -O2 with sanitizers when the tiles followed the threads).
    Block(const std::vector<Channel*>& channels, bool pairs)
        : m(static_cast<int>(channels.size())), n(static_cast<std::size_t>(channels[0]->rho.size())) {
        int count = (m + interleaved::kChunk - 1) / interleaved::kChunk;
        if (pairs && m > 3) count = std::min(m, (count + 1) / 2 * 2);
        for (int t = 0, first = 0; t < count; ++t) {
            const int last = int(std::int64_t(m) * (t + 1) / count);
            tiles.push_back({first, last - first, std::size_t(first) * n});
            first = last;
        }
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
    const float* val = F.values();
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
    const float* val = F.values();
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
    const float* val = F.values();
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

/// Below this many channels, one thread sweeps them all (the threads would share a tile's cache
/// lines row after row).
constexpr int kSplitChannels = 32;

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
        // Every channel's residual in one pass over F.
        std::vector<int> widths;
        for (const Block::Tile& t : b.tiles) widths.push_back(t.width);
        std::vector<double> FB(b.B.size()), norms(std::size_t(b.m), 0.0);
        multiplyTiled(F, widths, b.B.data(), FB.data());
        b.forEach([&](std::size_t, int c, std::size_t at) {
            const double r = b.E[at] - b.B[at] + b.rho[at] * FB[at];
            norms[std::size_t(c)] += r * r;
        });
        for (double& norm : norms) norm = std::sqrt(norm);
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
