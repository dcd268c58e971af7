// Console output of the CLI: stage timings, a progress bar on a terminal, F and solver summaries.
#pragma once

#include "engine/warnings.hpp"
#include "solve/solver.hpp"
#include "preprocess/backend_registry.hpp"
#include "preprocess/form_factor_job.hpp"

#include <chrono>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace hemirad {

/// Wall-clock time per pipeline stage, printed as a table at the end of a command.
class Timings {
public:
    /// Measures from now until the next mark() / stop().
    void start(std::string stage);
    void stop();
    void add(std::string stage, double seconds) { m_stages.emplace_back(std::move(stage), seconds); }
    std::string table() const;

private:
    std::vector<std::pair<std::string, double>> m_stages;
    std::string m_current;
    std::chrono::steady_clock::time_point m_begin;
};

/// Messages on stdout unless quiet (on stderr when stdout carries a result: -o -); the progress bar
/// on stderr only when it is a terminal.
class Reporter {
public:
    explicit Reporter(bool quiet, bool toStandardError = false);
    bool quiet() const { return m_quiet; }
    void line(const std::string& text) const;
    /// Progress callback for computeFormFactors (work per row, in `unit`, for the rate figure).
    ProgressCallback progress(const std::string& label, double raysPerRow, const std::string& unit = "rays") const;
    /// The run's method (as its back end describes it), ray or pixel counts, losses and F statistics.
    void formFactorSummary(const FormFactorRun& run, const Scene& scene, const MethodSettings& settings) const;
    /// formFactorSummary without the statistics (run.F and run.stats are not read).
    void formFactorRun(const FormFactorRun& run, const Scene& scene, const MethodSettings& settings) const;
    void formFactorStats(const FormFactorStats& stats, std::size_t memoryBytes) const;
    void solveSummary(const Radiosity& result) const;

private:
    bool m_quiet;
    bool m_terminal;
    std::ostream* m_out;
};

std::string formatSeconds(double seconds);

/// A command's last words: the timing table on the report, the warnings' summary on stderr.
void finishCommand(const Reporter& reporter, const Timings& timings, const Warnings& warnings);

}  // namespace hemirad
