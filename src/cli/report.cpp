// Console reporting.
#include "cli/report.hpp"

#include "engine/console.hpp"
#include "engine/form_factor_notes.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"

#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace hemirad {

std::string formatSeconds(double seconds) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, seconds < 10 ? "%.3f" : "%.1f", seconds);
    return buffer;
}

void Timings::start(std::string stage) {
    stop();
    m_current = std::move(stage);
    m_begin = std::chrono::steady_clock::now();
}

void Timings::stop() {
    if (m_current.empty()) return;
    add(m_current, std::chrono::duration<double>(std::chrono::steady_clock::now() - m_begin).count());
    m_current.clear();
}

std::string Timings::table() const {
    std::ostringstream out;
    double total = 0.0;
    std::size_t width = 5;
    for (const auto& [stage, seconds] : m_stages) width = std::max(width, stage.size());
    out << std::left << std::setw(static_cast<int>(width)) << "stage" << "  seconds\n";
    for (const auto& [stage, seconds] : m_stages) {
        out << std::left << std::setw(static_cast<int>(width)) << stage << "  " << std::right << std::setw(7)
            << formatSeconds(seconds) << '\n';
        total += seconds;
    }
    out << std::left << std::setw(static_cast<int>(width)) << "total" << "  " << std::right << std::setw(7)
        << formatSeconds(total) << '\n';
    return out.str();
}

Reporter::Reporter(bool quiet, bool toStandardError)
    : m_quiet(quiet), m_terminal(::isatty(STDERR_FILENO) == 1), m_out(toStandardError ? &std::cerr : &std::cout) {}

void Reporter::line(const std::string& text) const {
    if (!m_quiet) writeWhole(*m_out, text + '\n');
}

ProgressCallback Reporter::progress(const std::string& label, double raysPerRow, const std::string& unit) const {
    if (m_quiet || !m_terminal) return {};
    return [label, raysPerRow, unit](std::size_t done, std::size_t total, double seconds) {
        const double fraction = total ? double(done) / total : 1.0;
        const int width = 30;
        const int filled = static_cast<int>(fraction * width);
        const double rate = seconds > 0 ? done * raysPerRow / seconds : 0.0;
        const double eta = done > 0 ? seconds * (double(total) / done - 1.0) : 0.0;
        std::fprintf(stderr, "\r%s [%s%s] %zu/%zu rows  %.2f M%s/s  ETA %s s   ", label.c_str(),
                     std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), done, total, rate / 1e6,
                     unit.c_str(),
                     done > 0 ? formatSeconds(eta).c_str() : "?");
        if (done == total) std::fprintf(stderr, "\r%*s\r", 100, "");
        std::fflush(stderr);
    };
}

void Reporter::formFactorSummary(const FormFactorRun& run, const Scene& scene, const MethodSettings& settings) const {
    formFactorRun(run, scene, settings);
    formFactorStats(run.stats, run.F.memoryBytes());
}

void Reporter::formFactorRun(const FormFactorRun& run, const Scene& scene, const MethodSettings& settings) const {
    if (m_quiet) return;
    const RayCounts& c = run.counts;
    const BackendDescriptor& backend = findBackend(settings.method);
    const RunDescription description = backend.describe(scene, settings);
    const char* unit = backend.workUnit.c_str();
    std::ostringstream out;
    out.setf(std::ios::fixed);
    out << "form factors: " << backend.name << ", " << description.settings;
    out << ", " << run.rowsComputed << " rows";
    if (run.rowsSkipped) out << " (" << run.rowsSkipped << " skipped: black patches, B = E)";
    out << "\n  " << unit << " " << std::setprecision(2) << c.rays / 1e6 << " M in " << formatSeconds(run.computeSeconds)
        << " s = " << (run.computeSeconds > 0 ? c.rays / run.computeSeconds / 1e6 : 0.0) << " M " << unit << "/s";
    // Without rays (analytic) no ray tells misses from hidden patches: 1 - row sum reached no patch.
    out << "; " << lostPowerText(c, description.lossFromRays);
    if (c.lostFraction() > 0.01 && c.misses > 0)  // what a newcomer asks first about the open Cornell box
        out << "\n  (lost power left the scene through its openings, e.g. a box without a front wall, or met the "
               "back of a patch: it is gone, not an error; a closed scene loses almost nothing)";
    if (!run.device.empty()) out << "\n  device: " << run.device;
    if (c.rescaledRows)
        out << "\n  analytic rows whose direct factors summed above 1.001 (largest " << std::setprecision(4) << c.largestDirectSum
            << "), scaled to 1: " << c.rescaledRows;
    if (c.shadowTerms)
        out << "\n  point-to-patch terms whose visible part came from shadow polygons (exact partial visibility, no "
               "shadow ray): "
            << c.shadowTerms;
    if (c.shadowProbes)
        out << "\n  shadow-polygon probes of pairs' corners and edges' midpoints (whether a shadow's edge crosses the "
               "emitter; not terms of F): "
            << c.shadowProbes;
    if (c.cutPairs)
        out << "\n  far pairs whose receiver's plane cuts the emitter (a rule over the emitter's part in front of it, "
               "exact visible parts): "
            << c.cutPairs << " (" << c.cutWholePairs << " of them computed whole: a shadow's edge crosses that part)";
    if (c.contactPairs) {
        out << "\n  pairs computed whole, exact by contour integrals: " << c.contactPairs;
        if (run.F.parameters.count("pairs")) {
            out << " (every pair, --pairs whole";
        } else {
            out << " (close pairs, within " << int(kNearDistance) << " radii";
            if (c.straddlingPairs || c.penumbralPairs || c.cutWholePairs) {
                out << ", and farther ones: " << c.straddlingPairs << " across a shadow's edge, " << c.penumbralPairs
                    << " in a penumbra, where the emitter's corners or the rims of its view disagreed with its points";
                if (c.cutWholePairs) out << ", " << c.cutWholePairs << " cut by the receiver's plane and a shadow's edge";
            }
        }
        out << "); with a blocker in their shaft: " << c.contactShafts << " (hidden part adaptive, "
            << c.contactEvaluations << " visible-part evaluations)";
    }
    if (c.convexSolids)
        out << "\n  convex solids among the patches that can obstruct (a block, a faceted sphere; their faces turned "
               "away from a point cast no shadow from it): "
            << c.convexSolids << " (" << c.solidFaces << " faces)";
    if (c.coveredRows)
        out << "\n  rows of patches a solid stands on in part (a block on a floor patch), their rules over the free "
               "part: "
            << c.coveredRows;
    if (run.emittedPairs.changed)
        out << "\n  pairs whose two rows disagreed (a receiver split on a silhouette by one row only), set from "
               "the emitting row: "
            << run.emittedPairs.changed << " of " << run.emittedPairs.pairs << " (" << run.emittedPairs.added
            << " added, " << run.emittedPairs.removed << " removed; largest change " << std::setprecision(6)
            << run.emittedPairs.largestChange << ")";
    if (run.emittedPairs.rescaledRows)
        out << "\n  rows above their bound + 1e-3 with their emitters' values (largest " << std::setprecision(4)
            << run.emittedPairs.largestRowSum << "), scaled to the bound: " << run.emittedPairs.rescaledRows
            << " (their pairs' reciprocity gives way)";
    if (c.bounces) {
        out << "\n  mirror bounces " << c.bounces << "; power cut off by --max-depth " << settings.common.maxDepth
            << " / weight < " << settings.common.minWeight << ": " << std::setprecision(5)
            << (run.rowsComputed ? 100.0 * c.cutoffWeight / double(run.rowsComputed) : 0.0) << "% of the emitted power";
    }
    if (!run.stageSeconds.empty() && run.rowsComputed) {
        out << "\n  per row (thread time):" << std::setprecision(3);
        for (const auto& [stage, seconds] : run.stageSeconds)
            out << ' ' << stage << ' ' << 1e3 * seconds / double(run.rowsComputed) << " ms";
    }
    line(out.str());
}

void Reporter::formFactorStats(const FormFactorStats& s, std::size_t memoryBytes) const {
    if (m_quiet) return;
    std::ostringstream out;
    out.setf(std::ios::fixed);
    out << std::setprecision(4) << "  row sums min " << s.rowSumMin << " mean " << s.rowSumMean << " max " << s.rowSumMax
        << "; reciprocity |A_i F_ij - A_j F_ji| / max: max " << s.reciprocityMax << ", area-weighted mean "
        << s.reciprocityMean;
    if (s.selfFactors) out << "; " << s.selfFactors << " rows with F_ii > 0";
    for (const std::string& note : formFactorStatsNotes(s)) out << "\n  (" << note << ")";
    out << "\n  F: " << s.nonZeros << " nonzeros (" << std::setprecision(1)
        << (s.computedRows ? double(s.nonZeros) / s.computedRows : 0.0) << " per row), " << std::setprecision(1)
        << memoryBytes / 1048576.0 << " MiB";
    line(out.str());
}

void Reporter::solveSummary(const Radiosity& result) const {
    if (m_quiet) return;
    for (const SolveReport& r : result.reports) {
        std::ostringstream out;
        out << "solve: " << r.solver << ", channel(s) " << r.channels << ": "
            << (r.converged ? "converged" : "NOT converged");
        if (r.iterations) out << " in " << r.iterations << " iterations";
        out << std::scientific << std::setprecision(2) << ", relative residual " << r.residual;
        if (std::abs(r.residualOriginal - r.residual) > 1e-3 * std::max(r.residual, 1e-300))
            out << " (on I - RF: " << r.residualOriginal << ")";
        out << ", " << formatSeconds(r.seconds) << " s";
        if (!r.note.empty()) out << "; " << r.note;
        line(out.str());
    }
}

void finishCommand(const Reporter& reporter, const Timings& timings, const Warnings& warnings) {
    reporter.line(timings.table());
    if (warnings.count()) writeWhole(std::cerr, "hemirad: " + warnings.summary() + '\n');
}

}  // namespace hemirad
