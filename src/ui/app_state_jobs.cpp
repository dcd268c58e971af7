// hemirad-gui application state: the worker job (form factors and solve on copies of the scene),
// when F is reused, and applying its results on the UI thread.
#include "ui/app_state.hpp"

#include "engine/error.hpp"
#include "engine/form_factor_notes.hpp"
#include "engine/threads.hpp"
#include "pipeline/radiosity_pipeline.hpp"
#include "preprocess/form_factor_job.hpp"
#include "ui/sun_sky_job.hpp"
#include "ui/worker_job.hpp"
#include "ui/thermal_job.hpp"

#include <algorithm>
#include <exception>
#include <sstream>

#include <omp.h>

namespace hemirad::ui {

using Clock = std::chrono::steady_clock;

/// One background computation: optional form factors (all missing rows), then the solve. It works on
/// copies, so the user may keep editing; results are applied by poll() on the UI thread.
struct AppState::Job {
    std::thread thread;
    std::atomic<bool> cancel{false};
    std::atomic<bool> finished{false};
    mutable std::mutex mutex;
    JobStatus status;
    Clock::time_point start = Clock::now();

    // Inputs.
    Scene scene;
    std::shared_ptr<const FormFactors> F;
    bool computeF = false;
    PipelineSettings settings;
    std::vector<Rgb> warmStart;
    std::uint64_t materialsRevision = 0;
    std::uint64_t meshRevision = 0;
    int workers = 1;  ///< jobWorkers(the panel's threads)

    // Outputs.
    std::shared_ptr<const FormFactors> newF;
    std::optional<FormFactorStats> stats;
    double workPerSecond = 0.0;  ///< rays (or pixels) per second of the rows computed, 0 if none
    Radiosity result;
    std::string error;
    // Intermediate radiosity of a running solve (progressive display), newest only.
    std::vector<Rgb> intermediate;
    bool hasIntermediate = false;
    Clock::time_point lastIntermediate;
    std::vector<std::string> messages;
    std::vector<std::pair<std::string, double>> timings;

    void setStage(const std::string& stage, double progress) {
        std::lock_guard<std::mutex> lock(mutex);
        status.stage = stage;
        status.progress = progress;
    }

    /// The library pipeline with this job's settings; its events land in the job's status and log.
    RadiosityPipeline pipeline() {
        FormFactorPolicy policy;
        policy.backend = settings.formFactors;
        policy.backend.common.threads = workers;  // not part of F's settings: a reuse ignores it
        policy.statistics = true;  // the pipeline panel shows them
        PipelineEvents events =
            workerEvents(&cancel, timings, messages, [this](const std::string& stage, double progress) { setStage(stage, progress); });
        events.formFactorsComputed = [this](const FormFactorRun& run, const Scene& s, const MethodSettings& method) {
            const RunDescription description = findBackend(method.method).describe(s, method);
            std::ostringstream msg;
            msg << "form factors: " << method.method << ", " << description.settings
                << ", " << run.rowsComputed << " rows in " << run.computeSeconds << " s; row sums " << run.stats.rowSumMin
                << ".." << run.stats.rowSumMax << ", reciprocity (mean) " << run.stats.reciprocityMean << "; "
                << lostPowerText(run.counts, description.lossFromRays);
            messages.push_back(msg.str());
            // What a row sum of 0 or a reciprocity max near 1 means, as the CLI's report says it.
            for (const std::string& note : formFactorStatsNotes(run.stats)) messages.push_back("form factors: " + note);
            if (run.rowsComputed > 0 && run.computeSeconds > 0.0)
                workPerSecond = double(run.rowsComputed) * expectedWorkPerRow(s, method) / run.computeSeconds;
        };
        return RadiosityPipeline(std::move(policy), std::move(events));
    }

    void run() {
        // The solver's OpenMP team gets the job's count too (this thread's own setting). The job
        // keeps its priority: with nice 10 its one worker lost the CPU to a compiler on a shared
        // 2-core machine (F of the 20 mm Cornell box 52.7 s, against 7.0 s on two normal workers).
        omp_set_num_threads(workers);
        try {
            const RadiosityPipeline radiosity = pipeline();
            std::shared_ptr<const FormFactors> F = this->F;
            if (computeF) {
                // Rows the materials need that F lacks (all of them when there is no usable F).
                FormFactorUpdate update = radiosity.updateFormFactors(scene, F ? FormFactors(*F) : FormFactors());
                stats = update.stats;
                F = std::make_shared<FormFactors>(std::move(update.F));
                newF = F;
            }
            if (cancel) throw Error("cancelled");
            setStage("solve", 0.0);
            SolverOptions solver = settings.solver;
            solver.progress = [this](int sweep, const std::vector<Rgb>& B) {
                if (cancel) throw Error("cancelled");  // between sweeps
                // At most ten updates a second reach the view.
                const auto now = Clock::now();
                if (now - lastIntermediate < std::chrono::milliseconds(100)) return;
                lastIntermediate = now;
                std::lock_guard<std::mutex> lock(mutex);
                intermediate = B;
                hasIntermediate = true;
                status.stage = "solve (sweep " + std::to_string(sweep) + ")";
            };
            result = radiosity.solve(scene, *F, solver, &warmStart);
        } catch (const std::exception& e) {
            error = e.what();
        }
        finished = true;
    }
};

AppState::AppState() : m_start(Clock::now()) {}

AppState::~AppState() {
    if (m_job) {
        m_job->cancel = true;
        if (m_job->thread.joinable()) m_job->thread.join();
    }
}

int jobWorkers(int requested) { return requested > 0 ? requested : std::max(1, resolveThreads(0) - 1); }

JobStatus AppState::job() const {
    if (m_thermalJob && (!m_job || m_job->finished)) return m_thermalJob->status();
    if (m_sunSkyJob && (!m_job || m_job->finished)) return m_sunSkyJob->status();
    if (!m_job) return {};
    std::lock_guard<std::mutex> lock(m_job->mutex);
    JobStatus s = m_job->status;
    s.running = !m_job->finished;
    s.cancelling = m_job->cancel;
    s.workers = m_job->workers;
    s.elapsed = std::chrono::duration<double>(Clock::now() - m_job->start).count();
    return s;
}

bool AppState::busy() const {
    return (m_job && !m_job->finished) || (m_thermalJob && !m_thermalJob->finished()) || (m_sunSkyJob && !m_sunSkyJob->finished());
}

void AppState::startJob(bool computeF, std::shared_ptr<const FormFactors> F) {
    if (!hasScene()) return;
    if (busy()) {
        error("a computation is running; cancel it first");
        return;
    }
    if (m_job && m_job->thread.joinable()) m_job->thread.join();
    m_job = std::make_unique<Job>();
    m_job->scene = *m_scene;
    m_job->F = std::move(F);
    m_job->computeF = computeF;
    m_job->settings = settings;
    m_job->warmStart = m_B;
    m_job->materialsRevision = m_materialsRevision;
    m_job->meshRevision = m_meshRevision;
    m_job->workers = jobWorkers(settings.formFactors.common.threads);
    m_framesSinceCancel.reset();
    m_job->thread = std::thread([job = m_job.get()] { job->run(); });
}

FormFactorEstimate AppState::formFactorEstimate() const {
    FormFactorEstimate e;
    if (!hasScene()) return e;
    const MethodSettings& method = settings.formFactors;
    const BackendDescriptor& backend = findBackend(method.method);
    e.workUnit = backend.workUnit;
    e.workPerRow = backend.workPerRow(*m_scene, method);
    const RunDescription description = backend.describe(*m_scene, method);
    e.analytic = std::find(description.record.begin(), description.record.end(),
                           std::pair<std::string, std::string>("estimator", "analytic")) != description.record.end();
    // The rows Run would compute: the missing ones of a reusable F, else every row needed.
    FormFactorPolicy policy;
    policy.backend = method;
    const bool reuse = m_F && !m_fStale && formFactorsMatchSettings();
    e.rows = RadiosityPipeline(policy, {}).missingRows(*m_scene, reuse ? m_F.get() : nullptr).size();
    e.reusesF = reuse;
    e.description = description.settings;
    e.memoryBound = formFactorMemoryBound(*m_scene, method, e.rows);
    if (const auto it = m_workPerSecond.find({method.method, m_meshRevision}); it != m_workPerSecond.end())
        e.seconds = double(e.rows) * e.workPerRow / it->second;
    return e;
}

bool AppState::formFactorsMatchSettings() const {
    return m_F && m_fSettings && sameFormFactorSettings(*m_fSettings, settings.formFactors);
}

void AppState::runPipeline() {
    if (!hasScene()) return;
    // Only an F made with the panel's settings is reused (or completed with missing rows).
    const bool reuse = m_F && !m_fStale && formFactorsMatchSettings();
    if (m_F && !m_fStale && !reuse) info("the form-factor settings changed since F was made: computing F again");
    FormFactorPolicy policy;
    policy.backend = settings.formFactors;
    const bool needF = !reuse || !RadiosityPipeline(policy, {}).missingRows(*m_scene, m_F.get()).empty();
    const int threads = settings.formFactors.common.threads, workers = jobWorkers(threads);
    info(std::string(needF ? "running: form factors and solve" : "running: solve (form factors are current)") + ", " +
         std::to_string(workers) + (workers == 1 ? " thread" : " threads") +
         (threads == 0 ? " (all cores but one, left for the window)" : ""));
    startJob(needF, reuse ? m_F : nullptr);
}

void AppState::recomputeFormFactors() {
    if (!hasScene()) return;
    info("running: form factors (recomputed) and solve");
    startJob(true, nullptr);
}

void AppState::refreshRadiosity() {
    if (m_job && !m_job->finished) m_pendingResolve = true;
    else resolve();
}

void AppState::resolve() {
    if (!hasScene()) return;
    if (!m_F || m_fStale) {
        error("no current form factors: run the pipeline first");
        return;
    }
    // Every re-solve (an edit, undo, the one queued while a job ran) goes through here: rows the
    // materials now need that F lacks (a black patch made reflective) are computed first.
    for (PatchId i : neededRows(*m_scene, false))
        if (!m_F->rowComputed(i)) return runPipeline();
    startJob(false, m_F);
}

void AppState::cancel() {
    if (m_job && !m_job->finished && !m_job->cancel) {
        m_job->cancel = true;
        m_framesSinceCancel = 0;
        info("cancelling...");
    }
    if (m_thermalJob && !m_thermalJob->finished()) {
        m_thermalJob->cancel();
        info("cancelling...");
    }
    if (m_sunSkyJob && !m_sunSkyJob->finished()) {
        m_sunSkyJob->cancel();
        info("cancelling...");
    }
}

void AppState::wait() {
    if (m_job && m_job->thread.joinable()) m_job->thread.join();
    if (m_thermalJob) m_thermalJob->wait();
    if (m_sunSkyJob) m_sunSkyJob->wait();
}

bool AppState::poll() {
    if (m_framesSinceCancel) ++*m_framesSinceCancel;
    if (m_thermalJob && m_thermalJob->finished()) pollThermal();
    if (m_sunSkyJob && m_sunSkyJob->finished()) pollSunSky();
    if (m_job && !m_job->finished) {
        // Progressive display: show the solve's newest intermediate radiosity.
        std::lock_guard<std::mutex> lock(m_job->mutex);
        if (!m_job->hasIntermediate || m_job->intermediate.size() != m_B.size()) return false;
        m_B.swap(m_job->intermediate);
        m_job->hasIntermediate = false;
        bump();
        return true;
    }
    if (!m_job) return false;
    if (m_job->thread.joinable()) m_job->thread.join();
    std::unique_ptr<Job> job = std::move(m_job);
    for (const std::string& m : job->messages) info(m);
    if (!job->error.empty()) {
        if (job->error.find("cancelled") != std::string::npos)
            info("cancelled: the job stopped " + std::to_string(m_framesSinceCancel.value_or(0)) + " frame(s) after Cancel");
        else error(job->error);
        m_framesSinceCancel.reset();
        return false;
    }
    if (job->newF) {
        m_F = job->newF;
        m_fSettings = job->settings.formFactors;
        m_stats = job->stats;
        m_fGeometryHash = job->scene.geometryHash();
        m_fStale = m_fGeometryHash != m_scene->geometryHash();
    }
    if (job->scene.size() == m_scene->size()) m_B = job->result.B;
    m_reports = job->result.reports;
    m_timings = job->timings;
    if (job->workPerSecond > 0.0) m_workPerSecond[{job->settings.formFactors.method, job->meshRevision}] = job->workPerSecond;
    for (const SolveReport& r : m_reports) {
        std::ostringstream msg;
        msg << "solve: " << r.solver << " (" << r.channels << ") " << (r.converged ? "converged" : "NOT converged") << " in "
            << r.iterations << " iterations, residual " << r.residual << ", " << r.seconds << " s";
        info(msg.str());
    }
    m_bStale = job->materialsRevision != m_materialsRevision;
    bump();
    if ((m_bStale && autoResolve) || m_pendingResolve) {
        m_pendingResolve = false;
        if (m_F && !m_fStale) resolve();
    }
    return true;
}

}  // namespace hemirad::ui
