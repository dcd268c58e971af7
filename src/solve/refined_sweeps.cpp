// Gauss-Seidel and SOR over many channels (a year's hours, a sky's cells) by iterative refinement:
// the residual r = E - (I - R F) B in double, the correction d of (I - R F) d = r by sweeps in
// float, B += d, until every channel's residual meets the tolerance in double. A float sweep reads
// F once for up to 48 channels a tile where a double one reads it for 16, and its channels' values
// take half the bytes: on street64k's ray F it took about 0.45 of a double sweep per channel (when
// F's values were float too; they are read as doubles and rounded now). The corrections stop at
// float's precision (about 1e-6 of their residual), so a solve to 1e-10 takes two or three of
// them; the answer meets the same residual as the double sweeps', checked the same way.
#include "solve/refined_sweeps.hpp"

#include "solve/channel_block.hpp"

#include "engine/interleaved_rows.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <omp.h>

namespace hemirad::detail {
namespace {

/// A correction's sweeps stop when each channel's step is below this share of its residual, or
/// lower where the tolerance asks: float's rounding (about 1e-7 of a row's sum) leaves the steps
/// no further to go.
constexpr double kFloatFloor = 1e-6;
constexpr int kLanes = 8, kMostLanes = 48;

/// The tiles' (width, lanes) for m channels: lanes in whole vectors of 8, in two halves of equal
/// lanes (two threads split the tiles in halves), each half in as few tiles of at most 48 lanes as
/// can be; the channels fill the tiles in order, so the padding (under 16 lanes) is at the end. A
/// sweep costs about the same per lane from 24 to 48 lanes a tile (street64k's ray F, 2 threads:
/// 4.1-4.4 ms a lane and thread), so what counts is the padding and the halves' balance: 157
/// hours take 160 lanes, where tiles of even widths rounded up to 8 took 192.
std::vector<std::pair<int, int>> tilePlan(int m) {
    const int half = (m + 2 * kLanes - 1) / (2 * kLanes), most = kMostLanes / kLanes;  // in vectors
    const int perHalf = (half + most - 1) / most;
    std::vector<std::pair<int, int>> plan;
    for (int h = 0, left = m; h < 2; ++h)
        for (int t = 0; t < perHalf; ++t) {
            const int lanes = kLanes * (half * (t + 1) / perHalf - half * t / perHalf), width = std::min(lanes, left);
            if (width > 0) plan.push_back({width, lanes});
            left -= width;
        }
    return plan;
}

/// The corrections in float tiles of up to 48 channels, padded to whole vectors of 8 lanes: tile
/// t's value (i, c) at [offset_t + i * lanes_t + c - first_t]. A padded lane's residual and
/// reflectance are 0, so its correction stays 0.
struct Corrections {
    struct Tile {
        int first = 0, width = 0, lanes = 0;
        std::size_t offset = 0;
    };
    std::size_t n = 0;
    std::vector<Tile> tiles;
    std::vector<float> rho, r, d;
    std::vector<std::size_t> tileOf;  ///< per channel

    explicit Corrections(const Block& b) : n(b.n) {
        std::size_t offset = 0;
        int first = 0;
        for (const auto& [width, lanes] : tilePlan(b.m)) {
            tiles.push_back({first, width, lanes, offset});
            tileOf.insert(tileOf.end(), std::size_t(width), tiles.size() - 1);
            first += width;
            offset += n * std::size_t(lanes);
        }
        rho.assign(offset, 0.0f);
        r.assign(offset, 0.0f);
        d.assign(offset, 0.0f);
        b.forEach([&](std::size_t i, int c, std::size_t at) { rho[place(i, c)] = float(b.rho[at]); });
    }
    std::size_t place(std::size_t i, int c) const {
        const Tile& t = tiles[tileOf[std::size_t(c)]];
        return t.offset + i * std::size_t(t.lanes) + std::size_t(c - t.first);
    }
};

/// One in-place sweep of tiles [t0, t1) of (I - R F) d = r in float, rows in blocks and each
/// block's tiles one after the other (as the double sweeps); the self factor solved for exactly,
/// each step moved omega times. Adds the squared steps per channel to change[c].
HEMIRAD_WIDE_KERNEL void correctionSweep(const FormFactors& F, Corrections& x, std::size_t t0, std::size_t t1, float omega,
                                         double* change) {
    const std::size_t n = F.size();
    const double* val = F.values();
    std::uint64_t selfAt[interleaved::kBlockRows];
    float selfOf[interleaved::kBlockRows], sum[kMostLanes];
    for (std::size_t r0 = 0; r0 < n; r0 += interleaved::kBlockRows) {
        const std::size_t r1 = std::min(n, r0 + interleaved::kBlockRows);
        for (std::size_t i = r0; i < r1; ++i) {
            selfAt[i - r0] = interleaved::selfEntry(F, i);
            selfOf[i - r0] = selfAt[i - r0] < F.rowEnd(i) ? float(val[selfAt[i - r0]]) : 0.0f;
        }
        for (std::size_t k = t0; k < t1; ++k) {
            const Corrections::Tile& t = x.tiles[k];
            const std::size_t lanes = std::size_t(t.lanes);
            double changes[kMostLanes] = {};
            for (std::size_t i = r0; i < r1; ++i) {
                interleaved::floatRowSums(F, i, selfAt[i - r0], x.d.data() + t.offset, t.lanes, sum);
                const float self = selfOf[i - r0];
                // Every lane, the padded ones too (their steps are 0): one loop the compiler vectorises.
                float* d = x.d.data() + t.offset + i * lanes;
                const float* r = x.r.data() + t.offset + i * lanes;
                const float* rho = x.rho.data() + t.offset + i * lanes;
                for (std::size_t c = 0; c < lanes; ++c) {
                    const float step = omega * ((r[c] + rho[c] * sum[c]) / (1.0f - rho[c] * self) - d[c]);
                    changes[c] += double(step) * double(step);
                    d[c] += step;
                }
            }
            for (std::size_t c = 0; c < std::size_t(t.width); ++c) change[std::size_t(t.first) + c] += changes[c];
        }
    }
}

/// One sweep of every channel, the tiles split among the threads (each thread's channels get the
/// very sweep one thread would make: the bits do not depend on the thread count).
void correctionSweeps(const FormFactors& F, Corrections& x, double omega, std::vector<double>& change) {
    std::fill(change.begin(), change.end(), 0.0);
#pragma omp parallel
    {
        const std::size_t threads = std::size_t(omp_get_num_threads()), t = std::size_t(omp_get_thread_num());
        const std::size_t t0 = x.tiles.size() * t / threads, t1 = x.tiles.size() * (t + 1) / threads;
        if (t1 > t0) correctionSweep(F, x, t0, t1, float(omega), change.data());  // tiles own their channels
    }
}

/// True when B is E everywhere (the solvers' start) or 0: the residual is then known without a
/// pass over F, by starting from B = 0 (r = E) with the first correction from B in float.
bool startsAtSource(const Block& b) {
    return std::equal(b.B.begin(), b.B.end(), b.E.begin()) ||
           std::all_of(b.B.begin(), b.B.end(), [](double v) { return v == 0.0; });
}

}  // namespace

void gaussSeidelRefined(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options, bool relax) {
    Block b(channels, true);
    Corrections x(b);
    const std::size_t m = std::size_t(b.m);
    std::vector<double> r = b.E, normR = b.normE, change(m);
    const bool fromSource = startsAtSource(b);
    if (fromSource) {
        b.forEach([&](std::size_t i, int c, std::size_t at) { x.d[x.place(i, c)] = float(b.B[at]); });
        std::fill(b.B.begin(), b.B.end(), 0.0);
    } else {
        normR = residualNorms(F, b, &r);
    }
    double worst = 0.0;  // the worst channel's relative residual (infinite when not a number)
    auto report = [&] {  // true when every channel meets the tolerance
        worst = 0.0;
        for (std::size_t c = 0; c < m; ++c) {
            SolveReport& rep = channels[c]->report;
            rep.residual = b.normE[c] > 0 ? normR[c] / b.normE[c] : 0.0;
            rep.converged = rep.residual <= options.tolerance;
            worst = std::max(worst, std::isnan(rep.residual) ? std::numeric_limits<double>::infinity() : rep.residual);
        }
        return worst <= options.tolerance;
    };
    OverRelaxation relaxation;
    double omega = 1.0;
    int sweeps = 0, corrections = 0, stalled = 0;
    bool finite = true;
    // Each correction must lower the worst residual; three in a row that do not (steps that grow
    // while SOR falls back, then nothing) end the solve, unconverged, as do steps that are not finite.
    while (!report() && finite && stalled < 3 && sweeps < options.maxIterations) {
        ++corrections;
        const double before = worst;
        // Each channel's steps, as a share of its residual, down to what the tolerance needs of
        // this correction (or float's floor).
        std::vector<double> target(m, std::numeric_limits<double>::infinity());
        b.forEach([&](std::size_t i, int c, std::size_t at) { x.r[x.place(i, c)] = float(r[at]); });
        for (std::size_t c = 0; c < m; ++c)
            if (normR[c] > 0.0) target[c] = std::max(kFloatFloor, 0.5 * options.tolerance * b.normE[c] / normR[c]);
        double best = std::numeric_limits<double>::infinity();
        for (int stale = 0; sweeps < options.maxIterations;) {
            correctionSweeps(F, x, omega, change);
            ++sweeps;
            double step = 0.0, share = 0.0, ratio = 0.0;  // worst: ||d' - d|| / ||E||, / ||r||, / target
            for (std::size_t c = 0; c < m; ++c) {
                const double s = std::sqrt(change[c]);
                finite = finite && std::isfinite(s);
                if (b.normE[c] > 0.0) step = std::max(step, s / b.normE[c]);
                if (normR[c] > 0.0) {
                    share = std::max(share, s / normR[c]);
                    ratio = std::max(ratio, s / normR[c] / target[c]);
                }
            }
            if (!finite) break;
            if (relax) omega = relaxation.next(step);
            if (ratio <= 1.0) break;
            // Float's floor (or steps that grow): three sweeps without a step 5 % below the
            // smallest so far. The next correction goes on from there. A slow convergence still
            // shrinks its steps by more than 5 % a sweep.
            if (share < 0.95 * best) {
                best = share;
                stale = 0;
            } else if (++stale == 3) {
                break;
            }
        }
        b.forEach([&](std::size_t i, int c, std::size_t at) { b.B[at] += double(x.d[x.place(i, c)]); });
        std::fill(x.d.begin(), x.d.end(), 0.0f);
        normR = residualNorms(F, b, &r);
        report();
        stalled = worst < before ? 0 : stalled + 1;
        relaxation.restart();
    }
    if (corrections > 0 || !fromSource) b.store(channels);  // else B is still the start (no sweep allowed)
    const std::string note = (relax ? relaxation.describe() + "; " : std::string()) + "iterative refinement: " +
                             std::to_string(corrections) + " corrections swept in float, residuals in double";
    for (Channel* ch : channels) {
        ch->report.iterations = sweeps;
        ch->report.note = note;
    }
}

}  // namespace hemirad::detail
