// `hemirad bench`: time against error over a sweep of methods and sample counts. Each measurement
// runs in a child process (`hemirad bench-run`), so its peak memory is its own and runs cannot
// disturb each other; the reference F (a high-resolution hemisphere run) and its radiosity are
// computed once and cached by scene hash.
#include "cli/bench_records.hpp"
#include "cli/bench_run.hpp"
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "engine/atomic_file.hpp"
#include "engine/console.hpp"
#include "engine/error_metrics.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/hash.hpp"
#include "engine/scene_loader.hpp"
#include "engine/reciprocal_closure.hpp"
#include "engine/subdivide.hpp"
#include "solve/solver_registry.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

extern char** environ;

namespace hemirad {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// This process's peak resident memory. VmHWM, not getrusage: ru_maxrss survives exec, so a child
/// would report its parent's peak.
}  // namespace

double peakRssMiB() {
    std::ifstream status("/proc/self/status");
    std::string key;
    while (status >> key) {
        if (key == "VmHWM:") {
            double kib = 0;
            status >> kib;
            return kib / 1024.0;
        }
        std::getline(status, key);
    }
    return 0.0;
}

namespace {

// Reference radiosity cache: "HEMIRADB", N (uint64), then N x 3 doubles.
void saveRadiosity(const std::vector<Rgb>& B, const std::string& path) {
    AtomicFile file(path);
    const std::uint64_t n = B.size();
    file.stream().write("HEMIRADB", 8);
    file.stream().write(reinterpret_cast<const char*>(&n), 8);
    for (const Rgb& b : B) file.stream().write(reinterpret_cast<const char*>(b.data()), 3 * sizeof(double));
    file.commit();
}

std::vector<Rgb> loadRadiosity(const std::string& path, std::size_t expected) {
    std::ifstream in(path, std::ios::binary);
    char magic[8];
    std::uint64_t n = 0;
    if (!in.read(magic, 8) || std::memcmp(magic, "HEMIRADB", 8) != 0 || !in.read(reinterpret_cast<char*>(&n), 8))
        throw Error(path, 0, "not a Hemirad reference radiosity file");
    if (n != expected) throw Error(path, 0, "holds " + std::to_string(n) + " patches, the scene has " + std::to_string(expected));
    std::vector<Rgb> B(n);
    for (Rgb& b : B)
        if (!in.read(reinterpret_cast<char*>(b.data()), 3 * sizeof(double))) throw Error(path, 0, "truncated");
    return B;
}

}  // namespace

Scene loadBenchScene(const Options& o) {
    Warnings warnings(nullptr);
    Scene scene = loadScene(o.inputs.at(0), warnings, {o.materials});
    if (o.subdivide > 0) scene = subdivide(scene, o.subdivide);
    return scene;
}

namespace {

struct ChildResult {
    int status = -1;
    std::string out, err;
};

/// Runs argv[0] with argv, capturing stdout and stderr.
ChildResult runChild(const std::vector<std::string>& args) {
    int outPipe[2], errPipe[2];
    if (pipe(outPipe) != 0 || pipe(errPipe) != 0) throw Error("bench: cannot create pipes");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, outPipe[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, errPipe[1], STDERR_FILENO);
    posix_spawn_file_actions_addclose(&actions, outPipe[0]);
    posix_spawn_file_actions_addclose(&actions, errPipe[0]);
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(outPipe[1]);
    close(errPipe[1]);
    if (rc != 0) {
        close(outPipe[0]);
        close(errPipe[0]);
        throw Error(std::string("bench: cannot start ") + argv[0] + ": " + std::strerror(rc));
    }
    ChildResult result;
    // Read both pipes to the end (stderr is small; read stdout first, then stderr).
    char buffer[4096];
    ssize_t got;
    while ((got = read(outPipe[0], buffer, sizeof buffer)) > 0) result.out.append(buffer, std::size_t(got));
    while ((got = read(errPipe[0], buffer, sizeof buffer)) > 0) result.err.append(buffer, std::size_t(got));
    close(outPipe[0]);
    close(errPipe[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    result.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return result;
}

std::string selfPath() {
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw Error("bench: cannot find the hemirad binary (/proc/self/exe)");
    return p.string();
}

std::string shortNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

}  // namespace

void recordScene(BenchRecord& r, const Options& o, const Scene& scene, double loadSeconds) {
    r.set("scene", o.label.empty() ? fs::path(o.inputs.at(0)).stem().string() : o.label);
    r.set("t_load", loadSeconds);
    r.set("patches", double(scene.size()));
    r.set("method", o.formFactors.method);
    for (const auto& [key, value] : findBackend(o.formFactors.method).describe(scene, o.formFactors).record) {
        char* end = nullptr;
        const double number = std::strtod(value.c_str(), &end);
        if (!value.empty() && *end == '\0') r.set(key, number);
        else r.set(key, value);
    }
}

void recordFormFactors(BenchRecord& r, const Options& o, const FormFactorRun& run) {
    r.set("postprocess", std::string(o.enforceReciprocity ? "reciprocity" : "") +
                             (o.normalizeRows ? (o.enforceReciprocity ? "+normalised" : "normalised") : ""));
    r.set("t_bvh", run.prepareSeconds);
    r.set("t_ff", run.computeSeconds);
    r.set("t_assemble", run.assembleSeconds);
    r.set("t_stats", run.statsSeconds);
    r.set("rows", double(run.rowsComputed));
    r.set("rows_skipped", double(run.rowsSkipped));
    r.set("rays", double(run.counts.rays));
    r.set("rays_per_s", run.computeSeconds > 0 ? double(run.counts.rays) / run.computeSeconds : 0.0);
    r.set("nnz", double(run.F.nonZeros()));
    r.set("f_mib", run.F.memoryBytes() / 1048576.0);
    r.set("row_sum_min", run.stats.rowSumMin);
    r.set("row_sum_mean", run.stats.rowSumMean);
    r.set("row_sum_max", run.stats.rowSumMax);
    r.set("reciprocity_mean", run.stats.reciprocityMean);
    r.set("lost_fraction", run.counts.lostFraction());  // area-weighted over the computed rows
    if (!run.device.empty()) r.set("device", run.device);
    if (const auto batch = run.F.parameters.find("batch"); batch != run.F.parameters.end()) r.set("batch", batch->second);
    for (const auto& [stage, seconds] : run.stageSeconds) {
        std::string key = "ms_per_row_" + stage;
        for (char& c : key)
            if (c == ' ') c = '_';
        r.set(key, run.rowsComputed ? 1e3 * seconds / double(run.rowsComputed) : 0.0);
    }
}

void recordSolve(BenchRecord& r, const Radiosity& B, const std::string& solver, double seconds, const FormFactorRun& run) {
    r.set("t_solve", seconds);
    r.set("solver", solver);
    int iterations = 0;
    for (const SolveReport& rep : B.reports) iterations = std::max(iterations, rep.iterations);
    r.set("solve_iterations", double(iterations));
    r.set("t_total", run.prepareSeconds + run.computeSeconds + run.assembleSeconds + seconds);
}

void recordErrors(BenchRecord& r, const Options& o, const Scene& scene, const FormFactors& F, const std::vector<Rgb>& B) {
    if (!o.referencePath.empty()) {
        const FormFactors reference = loadFormFactors(o.referencePath);
        checkFormFactorsMatch(reference, scene.geometryHash(), scene.size(), o.referencePath);
        const FormFactorError e = compareFormFactors(F, reference);
        r.set("err_rows", double(e.rows));
        r.set("err_mean", e.mean);
        r.set("err_worst_mean", e.worstMean);
        r.set("err_max", e.max);
        r.set("err_worst_max", e.worstMax);
        r.set("err_rms", e.rms);
        r.set("err_worst_rms", e.worstRms);
        r.set("err_row_l1", e.rowL1);
        r.set("err_worst_row_l1", e.worstRowL1);
    }
    if (!o.referenceRadiosityPath.empty()) {
        const RadiosityError e = compareRadiosity(B, loadRadiosity(o.referenceRadiosityPath, scene.size()));
        r.set("b_err_mean", e.mean);
        r.set("b_err_max", e.max);
        r.set("b_err_rms", e.rms);
        r.set("b_rel_mean", e.relativeMean);
        r.set("b_rel_max", e.relativeMax);
        r.set("b_rel_rms", e.relativeRms);
    }
}

int runBenchRun(const Options& o) {
    BenchRecord r;
    auto t0 = Clock::now();
    const Scene scene = loadBenchScene(o);
    recordScene(r, o, scene, since(t0));
    FormFactorRun run = computeFormFactors(scene, o.formFactors, neededRows(scene, o.allRows));
    if (o.enforceReciprocity) {
        const auto t = Clock::now();
        enforceReciprocity(run.F, scene);
        r.set("t_reciprocity", since(t));
    }
    if (o.normalizeRows) normalizeRows(run.F);
    recordFormFactors(r, o, run);
    t0 = Clock::now();
    SolverOptions solver = o.solver;
    if (solver.solver == "auto") solver.solver = chooseSolver(scene.size(), scene);
    const Radiosity B = solveRadiosity(scene, run.F, solver);
    recordSolve(r, B, solver.solver, since(t0), run);
    r.set("peak_rss_mib", peakRssMiB());  // before the reference is loaded
    recordErrors(r, o, scene, run.F, B.B);
    writeWhole(std::cout, r.json() + '\n');
    return 0;
}

int runBench(const Options& o) {
    Reporter reporter(o.quiet, reportsToStandardError(o));
    const std::string scenePath = o.inputs.at(0);
    const std::string label = o.label.empty() ? fs::path(scenePath).stem().string() : o.label;
    const Scene scene = loadBenchScene(o);
    reporter.line("bench: " + label + ", " + std::to_string(scene.size()) + " patches");

    // The reference: a high-resolution hemisphere F over every row, and its radiosity.
    fs::create_directories(o.cacheDir);
    const bool analyticReference = o.referenceEstimator == "analytic";
    const std::string key = hexHash(scene.geometryHash()) + (analyticReference ? "-analytic-jittered-" : "-hemisphere-jittered-") +
                            std::to_string(o.referenceSamples) + "x" + std::to_string(o.referenceOrigins);
    const std::string referencePath = (fs::path(o.cacheDir) / (key + ".hff")).string();
    if (!fs::exists(referencePath)) {
        const BackendDescriptor& reference = findBackend("hemisphere");
        if (!reference.notBuilt.empty())
            throw Error("bench: the reference F (not in " + o.cacheDir + ") is computed by the hemisphere back end, which is " +
                        reference.notBuilt);
        reporter.line("bench: computing the reference F (" +
                      (analyticReference ? "Lambert factors, shadow rays to random points, "
                                         : std::to_string(o.referenceSamples) + " jittered directions x ") +
                      std::to_string(o.referenceOrigins) + " origins, every row) into " + referencePath);
        // The reference is the hemisphere's estimator with jittered directions and a seed of its own:
        // it shares no discretisation with the runs.
        MethodSettings b = defaultSettings(reference.name);
        b.common = o.formFactors.common;
        reference.option("--estimator")->set(b, o.referenceEstimator);
        reference.option("--samples")->set(b, std::to_string(o.referenceSamples));
        reference.option("--origins")->set(b, std::to_string(o.referenceOrigins));
        reference.option("--jitter")->set(b, "yes");
        reference.option("--seed")->set(b, std::to_string(0x5eed));
        const FormFactorRun run = computeFormFactors(scene, b, neededRows(scene, true),
                                                     reporter.progress("reference", expectedWorkPerRow(scene, b)));
        saveFormFactors(run.F, referencePath);
        reporter.line("bench: reference computed in " + formatSeconds(run.computeSeconds) + " s");
    } else {
        reporter.line("bench: reference F from the cache: " + referencePath);
    }
    // Radiosity depends on the materials too: key it by the reference and the emission/reflectances.
    Fnv1a materials;
    for (const Patch& p : scene.patches) {
        materials.add(p.rho.data(), 3 * sizeof(double));
        materials.add(p.emission.data(), 3 * sizeof(double));
    }
    const std::string radiosityPath = (fs::path(o.cacheDir) / (key + "-" + hexHash(materials.value()) + ".radiosity")).string();
    if (!fs::exists(radiosityPath)) {
        const FormFactors reference = loadFormFactors(referencePath);
        SolverOptions tight = o.solver;
        tight.solver = chooseSolver(scene.size(), scene);
        tight.tolerance = 1e-10;
        saveRadiosity(solveRadiosity(scene, reference, tight).B, radiosityPath);
    }

    std::vector<std::vector<std::string>> runs;
    const std::string self = selfPath();
    for (const MethodSettings& settings : o.benchMethods) {
        const BackendDescriptor& backend = findBackend(settings.method);
        const MethodSettings defaults = defaultSettings(settings.method);
        auto args = [&](const MethodSettings& run) {
            std::vector<std::string> a = {self, "bench-run", scenePath, "--method", run.method, "--label", label,
                                          "--reference", referencePath, "--reference-radiosity", radiosityPath,
                                          "--solver", o.solver.solver};
            if (o.solver.solver == "auto" || !findSolver(o.solver.solver).flags.empty())
                a.insert(a.end(), {"--tolerance", shortNumber(o.solver.tolerance)});
            if (o.subdivide > 0) {
                // Full precision: a rounded edge length can subdivide into another scene.
                char length[32];
                std::snprintf(length, sizeof length, "%.17g", o.subdivide);
                a.insert(a.end(), {"--subdivide", length});
            }
            if (!o.materials.empty()) a.insert(a.end(), {"--materials", o.materials});
            if (run.common.threads > 0) a.insert(a.end(), {"--threads", std::to_string(run.common.threads)});
            // The back end's options where they differ from its defaults.
            for (const BackendOption& option : backend.options) {
                const std::string value = option.get(run);
                if (value == option.get(defaults)) continue;
                if (option.kind == OptionKind::Switch) a.push_back(option.flag);
                else a.insert(a.end(), {option.flag, value});
            }
            if (o.enforceReciprocity) a.push_back("--enforce-reciprocity");
            if (o.normalizeRows) a.push_back("--normalize-rows");
            return a;
        };
        // The sweeps over the options this back end takes; runs the back end describes alike are
        // the same run (e.g. directions the analytic estimator never casts) and run once.
        std::vector<MethodSettings> sweep = {settings};
        auto sweepOver = [&](const char* flag, const std::vector<std::uint32_t>& values) {
            const BackendOption* option = backend.option(flag);
            if (!option) return;
            std::vector<MethodSettings> next;
            for (const MethodSettings& base : sweep)
                for (std::uint32_t v : values) {
                    MethodSettings m = base;
                    option->set(m, std::to_string(v));
                    next.push_back(m);
                }
            sweep = std::move(next);
        };
        sweepOver("--origins", o.sweepOrigins);
        sweepOver("--samples", o.sweepSamples);
        sweepOver("--resolution", o.sweepResolutions);
        std::set<std::string> described;
        for (const MethodSettings& m : sweep) {
            std::string key;
            for (const BackendOption& option : backend.options)
                if (option.flag != "--samples" && option.flag != "--resolution") key += option.get(m) + ";";
            if (!described.insert(key + backend.describe(scene, m).settings).second) continue;
            runs.push_back(args(m));
        }
    }
    std::vector<BenchRecord> records;
    int failures = 0;
    reporter.line("method       setting        F s    solve s   rays/s     row mean |dF|  row L1    B rel mean   peak MiB");
    for (const auto& args : runs) {
        const ChildResult child = runChild(args);
        if (child.status != 0) {
            ++failures;
            std::string message = "hemirad: bench run failed (" + std::to_string(child.status) + "):";
            for (std::size_t k = 1; k < args.size(); ++k) message += ' ' + args[k];
            writeWhole(std::cerr, message + '\n' + child.err);
            continue;
        }
        const std::size_t start = child.out.rfind('{');
        BenchRecord record = BenchRecord::parse(start == std::string::npos ? child.out : child.out.substr(start));
        std::map<std::string, std::string> f(record.fields().begin(), record.fields().end());
        std::string setting = f.count("resolution") ? "R " + f["resolution"] : f["samples"] + " x " + f["origins"];
        if (f["estimator"] == "\"analytic\"") setting = "analytic x " + f["origins"];
        char line[256];
        std::snprintf(line, sizeof line, "%-12s %-12s %8.3f %8.3f %9.3g %14.4g %9.4g %12.4g %9.0f",
                      f["method"].substr(1, f["method"].size() - 2).c_str(), setting.c_str(), std::stod(f["t_ff"]),
                      std::stod(f["t_solve"]), std::stod(f["rays_per_s"]), std::stod(f["err_mean"]),
                      std::stod(f["err_row_l1"]), std::stod(f["b_rel_mean"]), std::stod(f["peak_rss_mib"]));
        reporter.line(line);
        records.push_back(std::move(record));
    }
    {
        AtomicFile csv(o.output, false);
        csv.stream() << toCsv(records);
        csv.commit();
    }
    if (!o.jsonPath.empty()) {
        AtomicFile json(o.jsonPath, false);
        json.stream() << toJsonArray(records);
        json.commit();
    }
    reporter.line("bench: wrote " + outputName(o.output) + (o.jsonPath.empty() ? "" : " and " + outputName(o.jsonPath)));
    if (failures) throw Error("bench: " + std::to_string(failures) + " run(s) failed");
    return 0;
}

}  // namespace hemirad
