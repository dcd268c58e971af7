// The form-factor job: back end on a worker thread, progress polled from the caller's thread.
#include "preprocess/form_factor_job.hpp"

#include "engine/error.hpp"
#include "engine/memory.hpp"
#include "engine/threads.hpp"
#include "preprocess/backend_registry.hpp"

#include <algorithm>
#include <cstdio>

#include <chrono>
#include <exception>
#include <future>
#include <thread>

namespace hemirad {

std::vector<PatchId> neededRows(const Scene& scene, bool allRows) {
    std::vector<PatchId> rows;
    rows.reserve(scene.size());
    for (PatchId i = 0; i < scene.size(); ++i)
        if (allRows || (scene.patches[i].rho > 0.0).any()) rows.push_back(i);
    return rows;
}

namespace {

std::string gib(double bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f GiB", bytes / double(1ull << 30));
    return text;
}

}  // namespace

double expectedWorkPerRow(const Scene& scene, const MethodSettings& settings) {
    return findBackend(settings.method).workPerRow(scene, settings);
}

namespace {
// F is 12 bytes per nonzero; while it is built the row lists (12 bytes an entry) are released
// (and trimmed) as the CSR arrays fill (FormFactors::fromRows), and the analytic estimator's pairs
// handed between rows (pair_exchange.hpp, 12 bytes an entry) peak mid-run, next to the rows built
// so far. The cube n = 32 peaked at 1.29 x F and cornell13k at 1.40 x F; 1.5 x F with margin.
constexpr double kBytesPerNonzero = 18.0;
/// What does not grow with F: its row starts and flags, and every worker thread's scratch (the back
/// end's O(N) workspaces, one per thread).
double fixedBytes(const Scene& scene, const MethodSettings& settings) {
    const BackendDescriptor& backend = findBackend(settings.method);
    const double threads = double(resolveThreads(settings.common.threads));
    const double workspaces = backend.bytesPerThread ? threads * backend.bytesPerThread(scene, settings) : 0.0;
    return 9.0 * double(scene.size()) + workspaces;
}
}  // namespace

double formFactorMemoryBound(const Scene& scene, const MethodSettings& settings, std::size_t rows) {
    const double raysPerRow = expectedWorkPerRow(scene, settings);
    const double chain = scene.hasMirrors() ? double(settings.common.maxDepth) + 1.0 : 1.0;
    return fixedBytes(scene, settings) + kBytesPerNonzero * double(rows) * std::min(double(scene.size()), raysPerRow * chain);
}

MemoryPrediction predictFormFactorMemory(const Scene& scene, const MethodSettings& settings, const std::vector<PatchId>& rows,
                                         double budget) {
    MemoryPrediction p;
    p.bytes = formFactorMemoryBound(scene, settings, rows.size());
    p.nonzerosPerRow = rows.empty() ? 0.0 : (p.bytes - fixedBytes(scene, settings)) / kBytesPerNonzero / double(rows.size());
    if (p.bytes <= budget) return p;
    // The bound is loose (rays hit the same patches, walls hide most of a city): measure 64 rows
    // spread over the list.
    std::vector<PatchId> sample;
    const std::size_t step = std::max<std::size_t>(1, rows.size() / 64);
    for (std::size_t k = 0; k < rows.size() && sample.size() < 64; k += step) sample.push_back(rows[k]);
    const FormFactorRun probe = computeFormFactors(scene, settings, sample);
    p.sampledRows = sample.size();
    p.nonzerosPerRow = sample.empty() ? 0.0 : double(probe.F.nonZeros()) / double(sample.size());
    p.secondsPerRow = sample.empty() ? 0.0 : probe.computeSeconds / double(sample.size());
    p.bytes = fixedBytes(scene, settings) + 1.1 * kBytesPerNonzero * p.nonzerosPerRow * double(rows.size());
    return p;
}

MethodSettings resolveSettings(const Scene& scene, const MethodSettings& settings, const std::vector<PatchId>& rows,
                               std::string& note, std::size_t available) {
    note.clear();
    MethodSettings resolved = settings;
    const BackendDescriptor& backend = findBackend(settings.method);
    if (!backend.resolve) return resolved;
    if (!available) available = availableMemory();
    const double budget = 0.8 * double(available);
    note = backend.resolve(
        scene, resolved, [&](const MethodSettings& s) { return predictFormFactorMemory(scene, s, rows, budget); }, budget);
    return resolved;
}

std::size_t checkFormFactorMemory(const Scene& scene, const MethodSettings& settings, const std::vector<PatchId>& rows,
                                  std::size_t available) {
    if (!available) available = availableMemory();
    if (!available) return 0;  // unknown: nothing to compare with
    const double budget = 0.8 * double(available);
    const MemoryPrediction p = predictFormFactorMemory(scene, settings, rows, budget);
    if (p.bytes > budget) {
        char perRowText[32];
        std::snprintf(perRowText, sizeof perRowText, "%.0f", p.nonzerosPerRow);
        throw Error("form factors: F for " + std::to_string(rows.size()) + " rows needs about " + gib(p.bytes) +
                    " while it is built (" + perRowText + " nonzeros per row, measured on " +
                    std::to_string(p.sampledRows) + " rows), more than the " + gib(budget) +
                    " available; lower --samples/--origins/--resolution, subdivide less, or pass --no-memory-check");
    }
    return std::size_t(p.bytes);
}

FormFactors formFactorsWithoutRows(const Scene& scene, const MethodSettings& settings) {
    FormFactors F(scene.size());
    F.sceneHash = scene.geometryHash();
    F.provenance.method = settings.method;
    F.parameters["settings"] = formFactorSettingsText(settings);
    return F;
}

FormFactorRun computeFormFactors(const Scene& scene, const MethodSettings& settings, const std::vector<PatchId>& rows,
                                 const ProgressCallback& progress, const std::atomic<bool>* cancel) {
    using Clock = std::chrono::steady_clock;
    FormFactorRun run;
    auto backend = makeBackend(settings);
    const auto t0 = Clock::now();
    backend->prepare(scene);
    const auto t1 = Clock::now();
    run.prepareSeconds = std::chrono::duration<double>(t1 - t0).count();

    FormFactorBuilder builder(scene);
    std::exception_ptr failure;
    std::promise<void> done;
    std::future<void> finished = done.get_future();
    std::thread worker([&] {
        try {
            backend->computeRows(rows, builder);
        } catch (...) {
            failure = std::current_exception();
        }
        done.set_value();
    });
    // Wake every 20 ms for cancellation (the GUI's Cancel stops the rows within a frame or two), every
    // 100 ms for progress, and at once when the rows are done.
    auto reported = t1;
    while (finished.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready) {
        if (cancel && cancel->load()) builder.cancel();
        const auto now = Clock::now();
        if (progress && now - reported >= std::chrono::milliseconds(100)) {
            reported = now;
            progress(builder.rowsDone(), rows.size(), std::chrono::duration<double>(now - t1).count());
        }
    }
    worker.join();
    if (failure) std::rethrow_exception(failure);
    if (builder.cancelled()) throw Error("form factors: cancelled");
    run.computeSeconds = std::chrono::duration<double>(Clock::now() - t1).count();
    if (progress) progress(rows.size(), rows.size(), run.computeSeconds);

    run.counts = builder.counts();
    run.stageSeconds = builder.stageSeconds();
    run.device = backend->device();
    const auto assembling = Clock::now();
    run.F = builder.finish();
    if (backend->pairsFromEmitters()) {
        run.F.provenance = backend->provenance();  // the row-sum bound the pass keeps
        run.emittedPairs = takePairsFromEmitters(run.F, scene);
    }
    run.F.sceneHash = scene.geometryHash();
    run.F.provenance = backend->provenance();
    run.F.parameters = backend->parameters();
    run.F.parameters["settings"] = formFactorSettingsText(settings);  // what a reuse compares
    run.rowsComputed = rows.size();
    run.rowsSkipped = scene.size() - rows.size();
    const auto t2 = Clock::now();
    run.assembleSeconds = std::chrono::duration<double>(t2 - assembling).count();
    run.stats = computeStats(run.F, scene);
    run.statsSeconds = std::chrono::duration<double>(Clock::now() - t2).count();
    return run;
}

}  // namespace hemirad
