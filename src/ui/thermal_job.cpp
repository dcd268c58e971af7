// hemirad-gui's thermal run: F's rows by the radiosity pipeline, then the library's solar band, IR
// solve and exchange matrix; the report lines are those of `hemirad thermal`.
#include "ui/thermal_job.hpp"

#include "engine/error.hpp"
#include "pipeline/radiosity_pipeline.hpp"
#include "thermal/gebhart.hpp"

#include <chrono>
#include <exception>
#include <sstream>

namespace hemirad::ui {
namespace {

using Clock = std::chrono::steady_clock;

std::string figure(double v, int digits = 6) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    return s.str();
}

}  // namespace

ThermalJob::ThermalJob(Scene scene, std::shared_ptr<const FormFactors> F, ThermalInputs inputs, PipelineSettings settings)
    : m_scene(std::move(scene)), m_F(std::move(F)), m_inputs(std::move(inputs)), m_settings(std::move(settings)) {
    m_status.running = true;
    m_status.stage = "thermal";
    m_thread = std::thread([this] { run(); });
}

ThermalJob::~ThermalJob() {
    m_cancel = true;
    wait();
}

void ThermalJob::wait() {
    if (m_thread.joinable()) m_thread.join();
}

JobStatus ThermalJob::status() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    JobStatus s = m_status;
    s.running = !m_finished;
    s.elapsed = std::chrono::duration<double>(Clock::now() - m_start).count();
    return s;
}

void ThermalJob::setStage(const std::string& stage, double progress) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_status.stage = stage;
    m_status.progress = progress;
}

void ThermalJob::checkCancel() const {
    if (m_cancel) throw Error("cancelled");
}

std::shared_ptr<const FormFactors> ThermalJob::completeRows(const Scene& scene, std::shared_ptr<const FormFactors> current,
                                                            bool keepStats) {
    FormFactorPolicy policy;
    policy.backend = m_settings.formFactors;
    policy.allRows = true;  // every patch's irradiance and escape are needed (as hemirad thermal's --all-rows)
    policy.statistics = keepStats;
    if (current && policy.allRows && RadiosityPipeline(policy, {}).missingRows(scene, current.get()).empty()) return current;
    PipelineEvents events;
    events.cancel = &m_cancel;
    events.timing = [this](const std::string& stage, double seconds) { timings.emplace_back(stage, seconds); };
    events.message = [this](const std::string& text) { messages.push_back(text); };
    events.progress = [this](const std::string& label, double, const std::string&) -> ProgressCallback {
        setStage(label, 0.0);
        return [this, label](std::size_t done, std::size_t total, double) {
            setStage(label, total ? double(done) / double(total) : 1.0);
        };
    };
    events.formFactorsComputed = [this](const FormFactorRun& run, const Scene&, const MethodSettings& method) {
        messages.push_back("form factors: " + method.method + ", " + std::to_string(run.rowsComputed) +
                           " rows (every row, for thermal) in " +
                           figure(run.computeSeconds, 3) + " s");
    };
    const RadiosityPipeline pipeline(policy, std::move(events));
    FormFactorUpdate update = pipeline.updateFormFactors(scene, current ? FormFactors(*current) : FormFactors());
    if (keepStats) stats = update.stats;
    return std::make_shared<FormFactors>(std::move(update.F));
}

void ThermalJob::run() {
    try {
        std::shared_ptr<const FormFactors> F = completeRows(m_scene, m_F, true);
        if (F != m_F) newF = F;
        checkCancel();
        thermal::ThermalModel model = m_inputs.model;
        const SolverOptions solver = thermal::thermalSolverOptions(m_settings.solver, m_scene.size());
        if (m_inputs.solar.active()) {
            std::shared_ptr<const FormFactors> solarF = F;
            if (m_inputs.solar.needsOwnFormFactors(m_scene)) {
                // The solar band's mirrors differ from the IR ones: its own extended F (as hemirad thermal).
                messages.push_back("solar band: its specular reflectances differ from the IR ones, so it has its own F");
                Scene solarScene = m_scene;
                for (PatchId i = 0; i < m_scene.size(); ++i) solarScene.patches[i].specular = m_inputs.solar.surface[i].specular;
                solarF = completeRows(solarScene, nullptr, false);
                checkCancel();
            }
            setStage("solar band", 0.0);
            const auto start = Clock::now();
            result.solar = thermal::solveSolar(m_scene, *solarF, m_inputs.solar, model.metresPerUnit, solver);
            timings.emplace_back("solar band", std::chrono::duration<double>(Clock::now() - start).count());
            model.absorbedExternal = result.solar->absorbed;
            messages.push_back("solar band: " + figure(result.solar->incidentPower) + " W arrive, " +
                               figure(result.solar->absorbedPower) +
                               " W absorbed, " + figure(result.solar->escapedPower) + " W leave; balance " +
                               figure(result.solar->balance, 3));
        }
        checkCancel();
        setStage("thermal solve", 0.0);
        auto start = Clock::now();
        result.solution = thermal::solveThermal(m_scene, *F, model, solver);
        timings.emplace_back("thermal solve", std::chrono::duration<double>(Clock::now() - start).count());
        const thermal::ThermalSolution& s = result.solution;
        const SolveReport& r = s.report;
        messages.push_back("thermal solve: " + r.solver + (r.iterations ? ", " + std::to_string(r.iterations) + " iterations" : "") +
                           ", relative residual " + figure(r.residualOriginal, 3));
        messages.push_back("energy balance: |sum Q + Q_env| / max |Q| = " + figure(s.balance, 3) + "; environment gives " +
                           figure(s.environmentPower) + " W");
        for (std::size_t k = 0; k < model.isothermal.size(); ++k)
            messages.push_back("isothermal '" + model.isothermal[k].name + "': T = " + figure(s.isothermalT[k]) + " K (" +
                               figure(s.isothermalT[k] - thermal::kCelsiusZero) + " C) at a net power of " +
                               figure(model.isothermal[k].power) + " W");
        checkCancel();
        setStage("exchange matrix", 0.0);
        start = Clock::now();
        std::vector<std::vector<PatchId>> members;
        thermal::makeNodes(m_scene, thermal::Lumping::Objects, result.objects, members);
        result.exchange = thermal::exchangeMatrix(m_scene, *F, model, s, members, solver);
        timings.emplace_back("exchange matrix", std::chrono::duration<double>(Clock::now() - start).count());
        result.model = std::move(model);
        result.geometryHash = m_scene.geometryHash();
    } catch (const std::exception& e) {
        error = e.what();
    }
    m_finished = true;
}

}  // namespace hemirad::ui
