// hemirad-gui's worker thread: status, cancel, and F's rows by the radiosity pipeline.
#include "ui/worker_job.hpp"

#include "engine/error.hpp"
#include "pipeline/radiosity_pipeline.hpp"

#include <exception>
#include <sstream>

namespace hemirad::ui {

std::string jobFigure(double v, int digits) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    return s.str();
}

PipelineEvents workerEvents(std::atomic<bool>* cancel, std::vector<std::pair<std::string, double>>& timings,
                            std::vector<std::string>& messages, std::function<void(const std::string&, double)> setStage) {
    PipelineEvents events;
    events.cancel = cancel;
    events.timing = [&timings](const std::string& stage, double seconds) { timings.emplace_back(stage, seconds); };
    events.message = [&messages](const std::string& text) { messages.push_back(text); };
    events.progress = [setStage](const std::string& label, double, const std::string&) -> ProgressCallback {
        setStage(label, 0.0);
        return [setStage, label](std::size_t done, std::size_t total, double) {
            setStage(label, total ? double(done) / double(total) : 1.0);
        };
    };
    return events;
}

WorkerJob::WorkerJob(Scene scene, std::shared_ptr<const FormFactors> F, PipelineSettings settings, std::string purpose)
    : m_scene(std::move(scene)), m_F(std::move(F)), m_settings(std::move(settings)), m_purpose(std::move(purpose)) {
    m_status.running = true;
    m_status.stage = m_purpose;
}

WorkerJob::~WorkerJob() { stop(); }

void WorkerJob::start() { m_thread = std::thread([this] { run(); }); }

void WorkerJob::stop() {
    m_cancel = true;
    wait();
}

void WorkerJob::wait() {
    if (m_thread.joinable()) m_thread.join();
}

JobStatus WorkerJob::status() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    JobStatus s = m_status;
    s.running = !m_finished;
    s.elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    return s;
}

void WorkerJob::setStage(const std::string& stage, double progress) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_status.stage = stage;
    m_status.progress = progress;
}

void WorkerJob::checkCancel() const {
    if (m_cancel) throw Error("cancelled");
}

std::shared_ptr<const FormFactors> WorkerJob::completeRows(const Scene& scene, std::shared_ptr<const FormFactors> current,
                                                           bool keepStats) {
    FormFactorPolicy policy;
    policy.backend = m_settings.formFactors;
    policy.allRows = true;  // every patch's irradiance and escape are needed (as the command line's --all-rows)
    policy.statistics = keepStats;
    if (current && RadiosityPipeline(policy, {}).missingRows(scene, current.get()).empty()) return current;
    PipelineEvents events =
        workerEvents(&m_cancel, timings, messages, [this](const std::string& stage, double progress) { setStage(stage, progress); });
    events.formFactorsComputed = [this](const FormFactorRun& run, const Scene&, const MethodSettings& method) {
        messages.push_back("form factors: " + method.method + ", " + std::to_string(run.rowsComputed) + " rows (every row, for " +
                           m_purpose + ") in " + jobFigure(run.computeSeconds, 3) + " s");
    };
    const RadiosityPipeline pipeline(policy, std::move(events));
    FormFactorUpdate update = pipeline.updateFormFactors(scene, current ? FormFactors(*current) : FormFactors());
    if (keepStats) stats = update.stats;
    return std::make_shared<FormFactors>(std::move(update.F));
}

void WorkerJob::run() {
    try {
        work();
    } catch (const std::exception& e) {
        error = e.what();
    }
    m_finished = true;
}

}  // namespace hemirad::ui
