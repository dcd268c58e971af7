// The MPI driver: the CLI's commands with F spread over ranks (distributed_form_factors) and solved
// there (petsc_solve). Rank 0 reports and writes; every step runs inside Context::collectively.
#include "mpi/mpi_driver.hpp"

#include "cli/bench_run.hpp"
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "cli/thermal_command.hpp"
#include "engine/atomic_file.hpp"
#include "engine/console.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/form_factor_shards.hpp"
#include "engine/memory.hpp"
#include "engine/threads.hpp"
#include "mpi/distributed_form_factors.hpp"
#include "mpi/distributed_reciprocity.hpp"
#include "mpi/distributed_shards.hpp"
#include "mpi/distributed_thermal.hpp"
#include "mpi/petsc_solve.hpp"

#include <mpi.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

namespace hemirad::mpi {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// One command's state on one rank.
struct Job {
    /// Rank 0 alone reports and prints warnings (every rank loads the same files and finds the same).
    Job(const Context& c, const Options& o)
        : context(c), options(o), reporter(o.quiet || !c.root(), reportsToStandardError(o)),
          warnings(c.root() ? Warnings::stderrSink() : Warnings::Sink([](const std::string&) {})) {}
    const Context& context;
    const Options& options;
    Reporter reporter;
    Timings timings;
    Warnings warnings;
    Scene scene;
    DistributedFormFactors F;
    FormFactorRun run;      ///< on rank 0: the rows' computation (counts, times; its F stays empty)
    bool computed = false;  ///< rows were computed in this run (a reused F gained them)
};

void reportBalance(Job& job, const DistributedFormFactors& F) {
    if (!job.context.root()) return;
    std::ostringstream out;
    out.setf(std::ios::fixed);
    out << std::setprecision(2) << "  ranks " << job.context.size() << ": rows";
    for (std::uint64_t rows : F.rowsPerRank) out << ' ' << rows;
    out << "; busy";
    for (double s : F.busySeconds) out << ' ' << s;
    out << " s of " << F.computeSeconds << " s";
    job.reporter.line(out.str());
}

/// Throws AgreedFailure on every rank, naming the first rank whose `hash` differs from rank 0's and
/// saying `what` it did ("was given other options"), when any does. Collective.
void requireSameOnEveryRank(const Context& context, std::uint64_t hash, const std::string& what) {
    const std::vector<int> differing = context.ranksDiffering(hash);
    if (differing.empty()) return;
    std::string who = "rank " + std::to_string(differing[0]) + " of " + std::to_string(context.size());
    if (differing.size() > 1) who += " (and " + std::to_string(differing.size() - 1) + " more)";
    throw AgreedFailure(1, who + " " + what);
}

/// Loads the scene on every rank and checks what can be checked before any row is computed; every
/// rank must have loaded the same scene (a node's other copy of a file gave a silently wrong F or B).
void loadScene(Job& job, const RadiosityPipeline& pipeline) {
    job.context.collectively([&] {
        job.scene = pipeline.load(job.options.inputs.at(0), job.options.subdivide, job.warnings, {job.options.materials});
        try {
            pipeline.checkBeforeComputing(job.scene);
        } catch (const Error& e) {
            throw UsageError(e.what());
        }
    });
    std::string files = job.options.inputs.at(0);
    if (!job.options.materials.empty()) files += " and " + job.options.materials;
    requireSameOnEveryRank(job.context, job.scene.contentHash(),
                           "loaded another scene than rank 0 from " + files +
                               " (geometry, materials or subdivision differ): every rank must read the same files");
}

/// F's rows spread over the ranks: reused from `reusePath` (each rank reads its own shards, or a
/// contiguous share of one file's rows) when the stored-F rule takes it, and completed by the work queue. Returns that
/// rule (StoredFormFactorRule, the pipeline's) for storing F at `storePath`.
StoredFormFactorRule obtainFormFactors(Job& job, const std::string& reusePath, const std::string& storePath) {
    const Context& context = job.context;
    const Options& options = job.options;
    const std::size_t n = job.scene.size();
    StoredFormFactorRule rule = StoredFormFactorRule::computed(storePath);
    // No row held yet: N x N with the scene's hash and settings, as one process records it (a scene
    // that needs no row keeps it; issue 35 #18: it had hash 0 and could not serve --ff).
    job.F.owner.assign(n, -1);
    job.F.local = formFactorsWithoutRows(job.scene, options.formFactors);
    if (!reusePath.empty()) {
        const auto t0 = std::chrono::steady_clock::now();
        const bool sharded = context.rootDecides(context.root() && isShardManifest(reusePath));
        // Each rank its own shards, or its own share of one file's rows.
        job.F = sharded ? readShards(context, reusePath) : readOwnRows(context, reusePath, n, options.memoryCheck);
        context.collectively([&] {
            checkStoredFormFactors(job.F.local, job.scene, options.formFactors, options.reuseFfAnyway, reusePath, job.warnings);
        });
        job.timings.add("load F", secondsSince(t0));
        // Every rank holds the file's parameters and the owners of all rows: the same rule on each.
        const auto rowsHeld = std::size_t(
            std::count_if(job.F.owner.begin(), job.F.owner.end(), [](std::int32_t r) { return r >= 0; }));
        std::size_t missing = 0;
        for (PatchId i : neededRows(job.scene, options.allRows)) missing += job.F.owner[i] < 0;
        rule = StoredFormFactorRule::reused(job.F.local, rowsHeld, missing, reusePath);
        for (const std::string& line : rule.lines()) job.reporter.line(line);
        if (sharded && rule.reuse()) job.reporter.line("form factors: each rank reading its own shards of " + reusePath);
        if (!rule.reuse()) {
            job.F.owner.assign(n, -1);
            job.F.local = formFactorsWithoutRows(job.scene, options.formFactors);
        }
    }
    std::vector<PatchId> rows;
    for (PatchId i : neededRows(job.scene, options.allRows))
        if (job.F.owner[i] < 0) rows.push_back(i);
    if (rows.empty()) {
        if (!rule.reuse()) job.reporter.line(kNoRowsNeeded);
        return rule;
    }
    // This rank's share of the rows against its share of the node's memory; --estimator auto
    // decides on the smallest share of any rank, so that every rank decides alike.
    std::vector<PatchId> share;
    for (std::size_t k = std::size_t(context.rank()); k < rows.size(); k += std::size_t(context.size()))
        share.push_back(rows[k]);
    std::uint64_t myMemory = availableMemory() / std::size_t(context.ranksOnNode()), leastMemory = 0;
    MPI_Allreduce(&myMemory, &leastMemory, 1, MPI_UINT64_T, MPI_MIN, MPI_COMM_WORLD);
    MethodSettings method;
    std::string note;
    context.collectively([&] {
        std::vector<PatchId> largestShare;  // rank 0's share is the largest: the same list on every rank
        for (std::size_t k = 0; k < rows.size(); k += std::size_t(context.size())) largestShare.push_back(rows[k]);
        // Unknown on some rank: as one process with unknown memory (the exact estimator).
        const std::size_t budget = leastMemory ? std::size_t(leastMemory) : std::size_t(1) << 62;
        method = resolveSettings(job.scene, options.formFactors, largestShare, note, budget);
        if (!options.memoryCheck) return;
        checkFormFactorMemory(job.scene, method, share, std::size_t(myMemory));
    });
    if (context.root() && !note.empty()) job.reporter.line("form factors: " + note);
    const BackendDescriptor& backend = findBackend(method.method);
    const ProgressCallback progress =
        job.reporter.progress("form factors", backend.workPerRow(job.scene, method), backend.workUnit);
    DistributedFormFactors added = computeDistributed(context, job.scene, method, rows, progress);
    added.local.parameters["settings"] = formFactorSettingsText(options.formFactors);  // as one process records it
    job.timings.add("acceleration structure", added.prepareSeconds);
    job.timings.add("form factors", added.computeSeconds);
    job.timings.add("assemble F", added.assembleSeconds);
    if (context.root()) {
        FormFactorRun& run = job.run;
        run.counts = added.counts;
        run.computeSeconds = added.computeSeconds;
        run.assembleSeconds = added.assembleSeconds;
        run.prepareSeconds = added.prepareSeconds;
        run.rowsComputed = rows.size();
        run.rowsSkipped = n - rows.size();
        run.stageSeconds = added.stageSeconds;
        run.device = added.device;
        run.emittedPairs = added.emittedPairs;
        job.reporter.line("form factors: " + std::to_string(rows.size()) + " rows on " + std::to_string(context.size()) +
                          " MPI ranks");
        // The one-process summary; the statistics follow, from every rank's rows (reportStatistics).
        job.reporter.formFactorRun(run, job.scene, method);
    }
    reportBalance(job, added);
    // Every rank merges alike (rank 0's provenance and parameters are the ones written).
    if (rule.reuse()) mergeAddedRows(job.F.local, added.local, rows.size(), job.scene, method);
    else job.F.local = std::move(added.local);
    for (std::size_t i = 0; i < n; ++i)
        if (added.owner[i] >= 0) job.F.owner[i] = added.owner[i];
    job.computed = true;
    return rule;
}

/// The post-processing the policy asks that F does not record (pendingPostProcessing, the pipeline's
/// rule), decided on rank 0 so that every rank takes the same collective steps.
PostProcessing pendingSteps(const Job& job, const FormFactorPolicy& policy) {
    PostProcessing steps = pendingPostProcessing(policy, job.F.local);
    const Context& context = job.context;
    steps.dropBelow = context.rootDecides(steps.dropBelow > 0.0) ? policy.dropBelow : 0.0;
    steps.enforceReciprocity = context.rootDecides(steps.enforceReciprocity);
    steps.normalizeRows = context.rootDecides(steps.normalizeRows);
    return steps;
}

/// --enforce-reciprocity (or --drop-below, which ends with it): pairs of rows on any two ranks,
/// scaled to closure as one process scales them.
void reciprocity(Job& job, const PostProcessing& steps) {
    if (!steps.enforceReciprocity && !(steps.dropBelow > 0.0)) return;
    const auto t0 = std::chrono::steady_clock::now();
    std::string line;
    job.context.collectively([&] {
        line = steps.dropBelow > 0.0 ? describe(dropBelowDistributed(job.context, job.scene, job.F, steps.dropBelow))
                                     : describe(enforceReciprocityDistributed(job.context, job.scene, job.F));
    });
    job.timings.add(steps.dropBelow > 0.0 ? "drop below" : "enforce reciprocity", secondsSince(t0));
    job.reporter.line("form factors: " + line);
}

/// --normalize-rows on each rank's rows (row-local), the largest correction reported.
void normalise(Job& job, const PostProcessing& steps) {
    if (!steps.normalizeRows) return;
    double worst = normalizeRows(job.F.local), largest = 0;
    MPI_Reduce(&worst, &largest, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    job.reporter.line("form factors: rows normalised to sum 1 (largest correction " + std::to_string(largest) + ")");
}

void reportStatistics(Job& job) {
    const FormFactorStats stats = distributedRowStats(job.context, job.F);
    if (!job.context.root()) return;
    std::ostringstream out;
    out.setf(std::ios::fixed);
    out << std::setprecision(4) << "  row sums min " << stats.rowSumMin << " mean " << stats.rowSumMean << " max "
        << stats.rowSumMax << "; F: " << stats.nonZeros << " nonzeros (" << std::setprecision(1)
        << (stats.computedRows ? double(stats.nonZeros) / double(stats.computedRows) : 0.0)
        << " per row) over the ranks; reciprocity pairs rows of different ranks: `hemirad info` on the stored F";
    job.reporter.line(out.str());
}

/// F as shards, each written by its rank, or as one file on rank 0 streamed from the ranks (the same
/// bytes as one process writes).
void storeFormFactors(Job& job, const std::string& path, bool sharded, FormFactorFormat format) {
    const auto t0 = std::chrono::steady_clock::now();
    if (sharded) {
        const std::uint64_t bytes = writeShards(job.context, job.F, path);
        job.timings.add("write F", secondsSince(t0));
        std::ostringstream line;
        line << "wrote " << path << " (a shard manifest; " << job.context.size() << " shards of "
             << std::setprecision(4) << double(bytes) / 1048576.0 << " MiB in all, one per rank; scene hash "
             << hexHash(job.F.local.sceneHash) << ")";
        job.reporter.line(line.str());
        return;
    }
    FormFactors all = gatherFormFactors(job.context, job.F);
    job.context.collectively([&] {
        if (!job.context.root()) return;
        saveFormFactors(all, path, format);
        job.timings.add("write F", secondsSince(t0));
        job.reporter.line("wrote " + outputName(path) + " (scene hash " + hexHash(all.sceneHash) + ")");
    });
}

void finish(Job& job) {
    if (job.context.root()) finishCommand(job.reporter, job.timings, job.warnings);
}

void runFormFactors(Job& job) {
    const RadiosityPipeline pipeline = makePipeline(job.options, job.timings, job.reporter);
    loadScene(job, pipeline);
    obtainFormFactors(job, "", "");
    const PostProcessing steps = pendingSteps(job, pipeline.policy());
    reciprocity(job, steps);
    normalise(job, steps);
    reportStatistics(job);
    storeFormFactors(job, job.options.output, job.options.shards, formFactorOutputFormat(job.options));
    finish(job);
}

/// F's rows for solve, render and thermal: reused from --ff (or computed), stored there as the
/// pipeline's rule says, post-processed, reported.
void formFactorsWithStore(Job& job, const RadiosityPipeline& pipeline) {
    const Options& options = job.options;
    // Decided by rank 0, so that every rank takes the same collective path.
    const bool root = job.context.root();
    const bool reuse = job.context.rootDecides(root && !options.ffPath.empty() && !options.recomputeFf &&
                                               std::filesystem::exists(options.ffPath));
    // A manifest stays one; --shards makes one.
    const bool sharded = job.context.rootDecides(
        root && !options.ffPath.empty() && (options.shards || isShardManifest(options.ffPath)));
    // The pipeline's rule for a stored F (StoredFormFactorRule): a reused file gains the rows it lacked
    // and gets only the post-processing it does not record; a new file stores F as post-processed.
    const StoredFormFactorRule rule = obtainFormFactors(job, reuse ? options.ffPath : "", options.ffPath);
    if (rule.storeBeforePostProcessing(job.computed))
        storeFormFactors(job, options.ffPath, sharded, formFactorFormatFor(options.ffPath));
    const PostProcessing steps = pendingSteps(job, pipeline.policy());
    reciprocity(job, steps);
    normalise(job, steps);
    if (rule.storeAfterPostProcessing()) storeFormFactors(job, options.ffPath, sharded, formFactorFormatFor(options.ffPath));
    reportStatistics(job);
}

void runSolveOrRender(Job& job, bool render) {
    const Options& options = job.options;
    job.context.collectively([&] { checkDistributedSolver(options.solver.solver); });
    const RadiosityPipeline pipeline = makePipeline(options, job.timings, job.reporter);
    loadScene(job, pipeline);
    formFactorsWithStore(job, pipeline);
    Radiosity result;
    job.context.collectively([&] {
        const auto t0 = std::chrono::steady_clock::now();
        result = solveDistributed(job.context, job.scene, job.F, options.solver);
        job.timings.add("solve (" + (options.solver.solver == "auto" ? std::string("bicgstab") : options.solver.solver) +
                            ", PETSc)",
                        secondsSince(t0));
        job.reporter.solveSummary(result);
    });
    job.context.collectively([&] {
        if (!job.context.root()) return;
        if (render) {
            writeRenderOutput(options, job.scene, result, job.timings, job.reporter);
        } else {
            // --sky-view: rank 0 computes the sky view factors alone, as sky-view under mpirun.
            writeSolveOutput(options, job.scene, result, job.timings, job.reporter, job.warnings);
            if (!options.output.empty())
                job.reporter.line("wrote " + outputName(options.output) +
                                  (options.skyView ? " (with each patch's sky_view_factor)" : ""));
        }
    });
    finish(job);
}

/// `thermal` across ranks: every rank reads the model (a specular reflectance in --properties changes
/// the scene F is computed for), F's rows are computed (or read, --ff) across the ranks as for solve.
/// The model (gray or banded, with a solar band on the same F) is then solved where the rows are
/// (PETSc, every rank ending with the whole solution) and rank 0 writes; a step that needs F whole
/// (thermalNeedsWholeF) or a solver that does not run distributed has the rows gathered on rank 0,
/// which solves and writes as one process does.
void runThermal(Job& job) {
    const Options& options = job.options;  // thermalFormFactorOptions: every row
    const RadiosityPipeline pipeline = makePipeline(options, job.timings, job.reporter);
    loadScene(job, pipeline);
    ThermalInputs inputs;
    job.context.collectively([&] { inputs = readThermalModel(job.scene, options, job.reporter, job.warnings); });
    const bool root = job.context.root();
    formFactorsWithStore(job, pipeline);
    const std::vector<std::string>& distributed = distributedSolverNames();
    const std::string whole = thermalNeedsWholeF(options, job.scene, inputs);
    const bool solverRuns = options.solver.solver == "auto" ||
                            std::find(distributed.begin(), distributed.end(), options.solver.solver) != distributed.end();
    if (whole.empty() && solverRuns) {
        ThermalResults results;
        job.context.collectively([&] {
            job.reporter.line("thermal: solved on F's rows where the " + std::to_string(job.context.size()) +
                              " ranks hold them (PETSc)");
            results = solveThermalModel(options, job.scene, inputs, DistributedRows(job.context, job.F), nullptr,
                                        job.timings, job.reporter, job.warnings);
        });
        job.context.collectively([&] {
            if (root) writeThermalResults(options, job.scene, results, job.timings, job.reporter);
        });
        finish(job);
        return;
    }
    job.reporter.line(std::string("thermal: F gathered on rank 0 (") +
                      (!whole.empty() ? whole + ": F whole in one process" : "--solver " + options.solver.solver + " runs in one process") +
                      ")");
    const FormFactors all = gatherFormFactors(job.context, job.F);
    job.context.collectively([&] {
        // (A solar band with mirrors of its own has its F computed by rank 0 alone.)
        if (root) solveThermalAndWrite(options, job.scene, inputs, all, job.timings, job.reporter, job.warnings);
    });
    finish(job);
}

/// `bench-run` across ranks: F computed, post-processed and solved where the rows are, as `solve`
/// does; rank 0 gathers F for the statistics and the errors against the reference and prints the
/// one-process record as one JSON line, with the ranks and their peak memory (the largest rank's as
/// peak_rss_mib, all ranks' together as peak_rss_mib_total).
void runBenchRun(Job& job) {
    const Options& options = job.options;
    const bool root = job.context.root();
    BenchRecord record;
    auto t0 = std::chrono::steady_clock::now();
    job.context.collectively([&] { checkDistributedSolver(options.solver.solver); });
    const RadiosityPipeline pipeline = makePipeline(options, job.timings, job.reporter);
    loadScene(job, pipeline);
    if (root) recordScene(record, options, job.scene, secondsSince(t0));
    obtainFormFactors(job, "", "");
    const PostProcessing steps = pendingSteps(job, pipeline.policy());
    t0 = std::chrono::steady_clock::now();
    reciprocity(job, steps);
    if (root && options.enforceReciprocity) record.set("t_reciprocity", secondsSince(t0));
    normalise(job, steps);
    FormFactors all = gatherFormFactors(job.context, job.F);
    if (root) {
        t0 = std::chrono::steady_clock::now();
        job.run.stats = computeStats(all, job.scene);
        job.run.statsSeconds = secondsSince(t0);
        job.run.F = std::move(all);
        recordFormFactors(record, options, job.run);
    }
    Radiosity result;
    job.context.collectively([&] {
        t0 = std::chrono::steady_clock::now();
        result = solveDistributed(job.context, job.scene, job.F, options.solver);
        if (root)
            recordSolve(record, result, options.solver.solver == "auto" ? "bicgstab" : options.solver.solver, secondsSince(t0),
                        job.run);
    });
    const double mine = peakRssMiB();
    double largest = 0, total = 0;
    MPI_Reduce(&mine, &largest, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    MPI_Reduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    job.context.collectively([&] {
        if (!root) return;
        record.set("ranks", double(job.context.size()));
        record.set("peak_rss_mib", largest);  // before the reference is loaded
        record.set("peak_rss_mib_total", total);
        recordErrors(record, options, job.scene, job.run.F, result.B);
        writeWhole(std::cout, record.json() + '\n');
    });
}

}  // namespace

int runUnderMpi(int argc, char** argv) {
    std::optional<Context> started;
    try {
        started.emplace();
    } catch (const Error& e) {
        // MPI did not start (most libraries end the job themselves then): no rank can tell another.
        printError(e.what());
        return 1;
    }
    const Context& context = *started;
    try {
        started->start();  // its failures are agreed, and ~Context still finalises MPI
        Options options;
        context.collectively([&] {
            options = parseOptions(argc, argv);
            configureProcessThreads(options.formFactors.common.threads);
            // mpirun forwards rank 0's standard output: whether the user's end is a terminal is unknown.
            if (isStandardOutput(options.output) && outputIsBinary(options))
                throw UsageError("-o - under mpirun: mpirun forwards standard output, which cannot be checked for a "
                                 "terminal, so the binary ." + outputFormat(options) + " needs -o FILE (text .mtx "
                                 "and .csv may go to '-')");
        });
        requireSameOnEveryRank(context, optionsHash(options),
                               "was given other options than rank 0: every rank must run the same command "
                               "(--threads alone may differ)");
        const std::string& command = options.command;
        // render --false-color sky_view_factor solves nothing: one process's work, as sky-view's.
        const bool skyViewMap = options.falseColour == FalseColourQuantity::SkyViewFactor;
        if (command == "thermal") {
            const Options withRows = thermalFormFactorOptions(options);
            Job job(context, withRows);
            runThermal(job);
        } else if (command == "formfactors" || command == "solve" || (command == "render" && !skyViewMap)) {
            Job job(context, options);
            if (command == "formfactors") runFormFactors(job);
            else runSolveOrRender(job, command == "render");
        } else if (command == "bench-run") {
            Options quiet = options;  // its output is the JSON line alone
            quiet.quiet = true;
            Job job(context, quiet);
            runBenchRun(job);
        } else {
            // help, info, subdivide, check, sky-view, sun, irradiance, year, sensors, render of the sky view factor:
            // one process's work, done by rank 0.
            int status = 0;
            context.collectively([&] {
                if (command == "bench")
                    throw UsageError("'bench' runs each measurement as a child process of one process; run it "
                                     "without mpirun, or measure across ranks with 'mpirun -np K hemirad bench-run'");
                if (!context.root()) return;
                if (command == "help") std::cout << usageText();
                else if (command == "info") status = runInfo(options);
                else if (command == "subdivide") status = runSubdivide(options);
                else if (command == "check") status = runCheck(options);
                else if (command == "sky-view") status = runSkyView(options);
                else if (command == "render") status = runRender(options);
                else if (command == "sun") status = runSun(options);
                else if (command == "irradiance") status = runIrradiance(options);
                else if (command == "year") status = runYear(options);
                else if (command == "sensors") status = runSensors(options);
                else throw UsageError("unknown command '" + command + "'");
            });
            MPI_Bcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD);
            if (status) AtomicFile::exitQuietlyOnInterrupt(status);  // rank 0 said why
            return status;
        }
        context.agree();
        return 0;
    } catch (const AgreedFailure& e) {
        // Reported once, here: a SIGTERM from mpirun while this rank finalises is no interruption.
        AtomicFile::exitQuietlyOnInterrupt(e.status());
        if (context.root()) printError(e.what(), e.status() == 2);
        return e.status();
    } catch (const std::exception& e) {
        // Outside an agreement point (inside a collective): nothing can be agreed any more.
        context.abort(e.what());
    }
}

}  // namespace hemirad::mpi
