// The form-factor job: back end on a worker thread, progress polled from the caller's thread.
#include "preprocess/form_factor_job.hpp"

#include "engine/error.hpp"

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

FormFactorRun computeFormFactors(const Scene& scene, const std::string& method, const BackendOptions& options,
                                 const std::vector<PatchId>& rows, const ProgressCallback& progress,
                                 const std::atomic<bool>* cancel) {
    using Clock = std::chrono::steady_clock;
    FormFactorRun run;
    auto backend = makeBackend(method, options);
    const auto t0 = Clock::now();
    backend->prepare(scene);
    const auto t1 = Clock::now();
    run.prepareSeconds = std::chrono::duration<double>(t1 - t0).count();

    FormFactorBuilder builder(scene.size());
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
    // Wake every 100 ms for progress and cancellation, and at once when the rows are done.
    while (finished.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
        if (cancel && cancel->load()) builder.cancel();
        if (progress) progress(builder.rowsDone(), rows.size(), std::chrono::duration<double>(Clock::now() - t1).count());
    }
    worker.join();
    if (failure) std::rethrow_exception(failure);
    if (builder.cancelled()) throw Error("form factors: cancelled");
    run.computeSeconds = std::chrono::duration<double>(Clock::now() - t1).count();
    if (progress) progress(rows.size(), rows.size(), run.computeSeconds);

    run.counts = builder.counts();
    run.stageSeconds = builder.stageSeconds();
    run.F = builder.finish();
    run.F.sceneHash = scene.geometryHash();
    run.F.parameters = backend->parameters();
    run.rowsComputed = rows.size();
    run.rowsSkipped = scene.size() - rows.size();
    const auto t2 = Clock::now();
    run.stats = computeStats(run.F, scene);
    run.statsSeconds = std::chrono::duration<double>(Clock::now() - t2).count();
    return run;
}

}  // namespace hemirad
