// hemirad-gui's thermal run: F's rows by the radiosity pipeline, then the library's solar band, IR
// solve and exchange matrix; the report lines are those of `hemirad thermal`.
#include "ui/thermal_job.hpp"

#include "thermal/gebhart.hpp"

namespace hemirad::ui {

ThermalJob::ThermalJob(Scene scene, std::shared_ptr<const FormFactors> F, ThermalInputs inputs, PipelineSettings settings)
    : WorkerJob(std::move(scene), std::move(F), std::move(settings), "thermal"), m_inputs(std::move(inputs)) {
    start();
}

ThermalJob::~ThermalJob() { stop(); }

void ThermalJob::work() {
    std::shared_ptr<const FormFactors> F = completeRows(m_scene, m_F, true);
    if (F != m_F) newF = F;
    checkCancel();
    thermal::ThermalModel model = m_inputs.model;
    const SolverOptions solver = thermal::thermalSolverOptions(m_settings.solver, m_scene.size());
    // A band whose mirrors differ from the scene's (the IR ones) gets its own extended F, shared by
    // bands with the same reflectances (as hemirad thermal).
    std::vector<std::pair<std::vector<double>, std::shared_ptr<const FormFactors>>> own;
    auto formFactorsFor = [&](const std::vector<double>& specular, const std::string& why) {
        for (const auto& [s, ownF] : own)
            if (s == specular) return ownF;
        messages.push_back(why + ", so it has its own F");
        Scene bandScene = m_scene;
        for (PatchId i = 0; i < m_scene.size(); ++i) bandScene.patches[i].specular = specular[i];
        own.emplace_back(specular, completeRows(bandScene, nullptr, false));
        checkCancel();
        return own.back().second;
    };
    if (m_inputs.solar.active()) {
        std::shared_ptr<const FormFactors> solarF = F;
        if (m_inputs.solar.needsOwnFormFactors(m_scene)) {
            std::vector<double> specular(m_scene.size());
            for (PatchId i = 0; i < m_scene.size(); ++i) specular[i] = m_inputs.solar.surface[i].specular;
            solarF = formFactorsFor(specular, "solar band: its specular reflectances differ from the IR ones");
        }
        result.solar = timed("solar band", [&] { return thermal::solveSolar(m_scene, *solarF, m_inputs.solar, model.metresPerUnit, solver); });
        model.absorbedExternal = result.solar->absorbed;
        messages.push_back("solar band: " + jobFigure(result.solar->incidentPower) + " W arrive, " +
                           jobFigure(result.solar->absorbedPower) + " W absorbed, " + jobFigure(result.solar->escapedPower) +
                           " W leave; balance " + jobFigure(result.solar->balance, 3));
    }
    checkCancel();
    std::vector<const FormFactors*> bandF;
    for (std::size_t k = 0; k < model.bandSpecular.size(); ++k)
        bandF.push_back(thermal::bandNeedsOwnFormFactors(m_scene, model, k)
                            ? formFactorsFor(model.bandSpecular[k], "IR band " + std::to_string(k + 1) +
                                                                        ": its specular reflectances differ from the scene's")
                                  .get()
                            : nullptr);
    result.solution = timed("thermal solve", [&] { return thermal::solveThermal(m_scene, *F, model, solver, bandF); });
    const thermal::ThermalSolution& s = result.solution;
    const SolveReport& r = s.report;
    messages.push_back("thermal solve: " + r.solver + (r.iterations ? ", " + std::to_string(r.iterations) + " iterations" : "") +
                       ", relative residual " + jobFigure(r.residualOriginal, 3));
    messages.push_back("energy balance: |sum Q + Q_env| / max |Q| = " + jobFigure(s.balance, 3) + "; environment gives " +
                       jobFigure(s.environmentPower) + " W");
    for (std::size_t k = 0; k < model.isothermal.size(); ++k)
        messages.push_back("isothermal '" + model.isothermal[k].name + "': T = " + jobFigure(s.isothermalT[k]) + " K (" +
                           jobFigure(s.isothermalT[k] - thermal::kCelsiusZero) + " C) at a net power of " +
                           jobFigure(model.isothermal[k].power) + " W");
    checkCancel();
    thermal::setEmissivitiesAt(model, s.T);  // emissivities against temperature: the exchange at the solution's
    std::vector<std::vector<PatchId>> members;
    thermal::makeNodes(m_scene, thermal::Lumping::Objects, result.objects, members);
    result.exchange = timed("exchange matrix", [&] { return thermal::exchangeMatrix(m_scene, *F, model, s, members, solver); });
    checkCancel();
    // The conductors per object, for File > Export radiative conductors (as hemirad thermal --conductors).
    result.conductors = timed("conductors", [&] { return thermal::computeConductors(m_scene, *F, model, thermal::GebhartOptions{}, solver); });
    messages.push_back("conductors: " + std::to_string(result.conductors.couplings.size()) + " couplings between " +
                       std::to_string(result.conductors.nodes.size()) + " objects and the environment; asymmetry before symmetrising " +
                       jobFigure(result.conductors.asymmetry, 3));
    result.model = std::move(model);
    result.geometryHash = m_scene.geometryHash();
}

}  // namespace hemirad::ui
