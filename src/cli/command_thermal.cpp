// `hemirad thermal SCENE --bc CONDITIONS.toml [--properties P.toml] -o T.csv [--objects O.csv]
// [--conductors GR.esatan] [--exchange Q.csv]`: gray radiative exchange on F (src/thermal).
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "cli/thermal_command.hpp"
#include "thermal/conductor_writers.hpp"
#include "thermal/gebhart.hpp"
#include "thermal/patch_conductance.hpp"
#include "thermal/thermal_files.hpp"
#include "thermal/thermal_solver.hpp"

#include <cmath>
#include <memory>
#include <sstream>

namespace hemirad {
namespace {

std::string figure(double v, int digits = 6) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    return s.str();
}

/// Metres per scene unit: the OBJ's "# hemirad unit", else --unit, else metres (said).
double sceneMetres(const Scene& scene, const Options& options, Warnings& warnings) {
    if (!scene.unit.empty()) {
        if (!options.lengthUnit.empty() && options.lengthUnit != scene.unit)
            throw UsageError("--unit " + options.lengthUnit + " contradicts the scene's own unit '" + scene.unit + "' (" +
                             scene.path + ")");
        return metresPerUnit(scene.unit);
    }
    if (!options.lengthUnit.empty()) return metresPerUnit(options.lengthUnit);
    warnings.add("unit", "the scene states no length unit: lengths are taken as metres (give --unit or a "
                         "'# hemirad unit mm' line in the OBJ)");
    return 1.0;
}

// What needs F whole in one process: reasons thermalNeedsWholeF lists and solveThermalModel names
// when it lacks F whole.
constexpr const char* kOwnIrMirrors = "an IR band with mirrors of its own";
constexpr const char* kOwnSolarMirrors = "a solar band with mirrors of its own";

}  // namespace

ThermalInputs readThermalModel(Scene& scene, const Options& options, const Reporter& reporter, Warnings& warnings) {
    ThermalInputs inputs;
    thermal::ThermalModel& model = inputs.model;
    model.metresPerUnit = sceneMetres(scene, options, warnings);
    thermal::BandProperties bands;
    model.surface = thermal::applyProperties(options.propertiesPath, scene, model.propertySource, &inputs.solar.surface, &bands);
    thermal::takeBandProperties(model, std::move(bands));
    thermal::Conditions conditions = thermal::readConditions(options.conditionsPath, scene, model.metresPerUnit);
    inputs.solar.incident = conditions.solarIncident;
    if (!inputs.solar.active()) inputs.solar = {};
    model.condition = std::move(conditions.perPatch);
    model.environment = conditions.environment;
    model.isothermal = std::move(conditions.isothermal);
    model.conditionSource = std::move(conditions.sources);
    thermal::checkModel(scene, model);
    for (const std::string& s : model.propertySource) reporter.line("properties  " + s);
    for (const std::string& s : model.conditionSource) reporter.line("condition   " + s);
    if (!model.bandEmissivity.empty()) {
        std::string limits;
        for (const double l : model.bandLimitsUm) limits += (limits.empty() ? "" : ", ") + figure(l);
        reporter.line("IR bands: " + std::to_string(model.bandEmissivity.size()) + " split at " + limits +
                      " um (conductors use each surface's emissivity weighted at " + figure(model.referenceTemperature) + " K)");
    }
    if (thermal::hasEmissivityCurves(model))
        reporter.line("emissivity against temperature: " + std::to_string(model.emissivityCurves.size()) +
                      " curves (piecewise linear); the solve iterates on the unknown temperatures, the conductors use "
                      "each surface's emissivity at its solved temperature");
    reporter.line(model.environment ? "environment " + figure(*model.environment) + " K"
                                    : "environment none (a closed scene: what escapes is lost at 0 K)");
    return inputs;
}

std::string thermalNeedsWholeF(const Options& options, const Scene& scene, const ThermalInputs& inputs) {
    std::string why;
    auto add = [&](const char* reason) { why += (why.empty() ? "" : ", ") + std::string(reason); };
    for (std::size_t k = 0; k < inputs.model.bandSpecular.size(); ++k)
        if (thermal::bandNeedsOwnFormFactors(scene, inputs.model, k)) {
            add(kOwnIrMirrors);
            break;
        }
    if (inputs.solar.active() && inputs.solar.needsOwnFormFactors(scene)) add(kOwnSolarMirrors);
    if (!options.conductorsPath.empty()) add("--conductors");
    if (!options.exchangePath.empty()) add("--exchange");
    return why;
}

ThermalResults solveThermalModel(const Options& options, const Scene& scene, const ThermalInputs& inputs,
                                 const thermal::ExchangeRows& rows, const FormFactors* whole, Timings& timings,
                                 const Reporter& reporter, Warnings& warnings) {
    auto wholeF = [&](const char* why) -> const FormFactors& {
        if (!whole) throw Error(std::string("thermal: ") + why + " needs F whole in one process");
        return *whole;
    };
    ThermalResults results;
    thermal::ThermalModel& model = results.model;
    model = inputs.model;
    // A band whose mirrors differ from the scene's (the IR ones) gets its own extended F, in this
    // process; bands with the same reflectances share it.
    std::vector<std::pair<std::vector<double>, std::unique_ptr<FormFactors>>> own;
    auto formFactorsFor = [&](const std::vector<double>& specular, const std::string& why) -> const FormFactors& {
        for (const auto& [s, ownF] : own)
            if (s == specular) return *ownF;
        Scene bandScene = scene;
        for (PatchId i = 0; i < scene.size(); ++i) bandScene.patches[i].specular = specular[i];
        Options bandOptions = thermalFormFactorOptions(options);
        bandOptions.ffPath.clear();
        bandOptions.shards = bandOptions.recomputeFf = bandOptions.reuseFfAnyway = false;
        reporter.line(why + ", so it has its own F");
        own.emplace_back(specular, std::make_unique<FormFactors>(obtainFormFactors(bandScene, bandOptions, timings, reporter, warnings)));
        return *own.back().second;
    };
    if (inputs.solar.active()) {
        const FormFactors* solarF = nullptr;  // its own, else `rows`
        if (inputs.solar.needsOwnFormFactors(scene)) {
            wholeF(kOwnSolarMirrors);
            std::vector<double> specular(scene.size());
            for (PatchId i = 0; i < scene.size(); ++i) specular[i] = inputs.solar.surface[i].specular;
            solarF = &formFactorsFor(specular, "solar band: its specular reflectances differ from the IR ones");
        }
        timings.start("solar band");
        const thermal::SolarSolution solar =
            solarF ? thermal::solveSolar(scene, *solarF, inputs.solar, model.metresPerUnit, options.solver)
                   : thermal::solveSolar(scene, rows, inputs.solar, model.metresPerUnit, options.solver);
        timings.stop();
        model.absorbedExternal = solar.absorbed;
        reporter.line("solar band: " + figure(solar.incidentPower) + " W arrive, " + figure(solar.absorbedPower) +
                      " W absorbed, " + figure(solar.escapedPower) + " W leave; balance " + figure(solar.balance, 3));
    }
    // Each IR band with mirrors of its own on its own F (in this process), the others on `rows`.
    std::vector<std::unique_ptr<thermal::LocalRows>> ownRows;
    std::vector<const thermal::ExchangeRows*> bandF;
    for (std::size_t k = 0; k < model.bandSpecular.size(); ++k) {
        bandF.push_back(nullptr);
        if (!thermal::bandNeedsOwnFormFactors(scene, model, k)) continue;
        wholeF(kOwnIrMirrors);
        ownRows.push_back(std::make_unique<thermal::LocalRows>(
            formFactorsFor(model.bandSpecular[k], "IR band " + std::to_string(k + 1) +
                                                      ": its specular reflectances differ from the scene's (the bands' "
                                                      "weighted at the reference temperature)")));
        bandF.back() = ownRows.back().get();
    }
    timings.start("thermal solve");
    results.solution = thermal::solveThermal(scene, rows, model, options.solver, bandF);
    timings.stop();
    const thermal::ThermalSolution& solution = results.solution;
    // Emissivities against temperature: the outputs, the exchange and the conductors at the solution's.
    thermal::setEmissivitiesAt(model, solution.T);
    const SolveReport& r = solution.report;
    reporter.line("thermal solve: " + r.solver + (r.iterations ? ", " + std::to_string(r.iterations) + " iterations" : "") +
                  ", relative residual " + figure(r.residualOriginal, 3));
    reporter.line("energy balance: |sum Q + Q_env| / max |Q| = " + figure(solution.balance, 3) +
                  "; environment gives " + figure(solution.environmentPower) + " W");
    for (std::size_t k = 0; k < model.isothermal.size(); ++k)
        reporter.line("isothermal '" + model.isothermal[k].name + "': T = " + figure(solution.isothermalT[k]) + " K (" +
                      figure(solution.isothermalT[k] - thermal::kCelsiusZero) + " C) at a net power of " +
                      figure(model.isothermal[k].power) + " W");
    if (solution.reciprocityImbalance > 1e-6)
        reporter.line("note: F's reciprocity defect moves " + figure(solution.reciprocityImbalance, 3) +
                      " of max |Q| between the environment's emission and absorption views");

    if (!options.conductorsPath.empty()) {
        const FormFactors& F = wholeF("--conductors");
        timings.start("Gebhart factors");
        thermal::GebhartOptions g;
        g.lumping = options.lumping == "patches" ? thermal::Lumping::Patches : thermal::Lumping::Objects;
        g.threshold = options.couplingThreshold;
        g.method = options.gebhartMethod == "dense"     ? thermal::GebhartMethod::Dense
                   : options.gebhartMethod == "columns" ? thermal::GebhartMethod::Columns
                                                        : thermal::GebhartMethod::Auto;
        results.conductors = thermal::computeConductors(scene, F, model, g, options.solver);
        timings.stop();
        const thermal::Conductors& conductors = results.conductors;
        reporter.line("conductors: " + std::to_string(conductors.couplings.size()) + " couplings between " +
                      std::to_string(conductors.nodes.size()) + " " + options.lumping + " and the environment" +
                      (conductors.dropped ? "; " + std::to_string(conductors.dropped) + " below --gr-threshold dropped (GR sum " +
                                                figure(conductors.droppedSum, 4) + " m^2)"
                                          : "") +
                      (conductors.method == thermal::GebhartMethod::Dense ? "; F's reciprocity defect (symmetrised) "
                                                                          : "; asymmetry before symmetrising ") +
                      figure(conductors.asymmetry, 3) + "; " +
                      (conductors.method == thermal::GebhartMethod::Dense
                           ? std::string("one dense factorisation of every patch pair") +
                                 (thermal::PatchConductance::usesLapack() ? " (LAPACK)" : " (Eigen)")
                           : "a column solve per node (" + conductors.report.solver + ")"));
    }
    if (!options.exchangePath.empty()) {
        const FormFactors& F = wholeF("--exchange");
        timings.start("exchange matrix");
        std::vector<std::vector<PatchId>> members;
        thermal::makeNodes(scene, thermal::Lumping::Objects, results.objectNodes, members);
        results.exchange = thermal::exchangeMatrix(scene, F, model, solution, members, options.solver);
        timings.stop();
    }
    return results;
}

void writeThermalResults(const Options& options, const Scene& scene, const ThermalResults& results, Timings& timings,
                         const Reporter& reporter) {
    timings.start("write thermal results");
    if (!options.output.empty()) thermal::writePatchTable(options.output, scene, results.model, results.solution);
    if (!options.objectsPath.empty()) thermal::writeObjectThermalTable(options.objectsPath, scene, results.solution);
    if (!options.conductorsPath.empty())
        thermal::writeConductors(options.conductorsPath,
                                 options.conductorFormat.empty() ? thermal::conductorFormatFor(options.conductorsPath)
                                                                 : options.conductorFormat,
                                 results.conductors);
    if (!options.exchangePath.empty()) thermal::writeExchangeMatrix(options.exchangePath, results.objectNodes, results.exchange);
    timings.stop();
    if (!options.output.empty()) reporter.line("wrote " + outputName(options.output) + " (per patch: T, J, H, q, Q)");
    if (!options.objectsPath.empty()) reporter.line("wrote " + outputName(options.objectsPath) + " (per object: T, q, Q)");
    if (!options.conductorsPath.empty()) reporter.line("wrote " + outputName(options.conductorsPath) + " (radiative conductors GR, m^2)");
    if (!options.exchangePath.empty()) reporter.line("wrote " + outputName(options.exchangePath) + " (net power between objects, W)");
}

void solveThermalAndWrite(const Options& options, const Scene& scene, const ThermalInputs& inputs, const FormFactors& F,
                          Timings& timings, const Reporter& reporter, Warnings& warnings) {
    const ThermalResults results =
        solveThermalModel(options, scene, inputs, thermal::LocalRows(F), &F, timings, reporter, warnings);
    writeThermalResults(options, scene, results, timings, reporter);
}

int runThermal(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    Scene scene = loadScene(options, timings, reporter, warnings);
    // The model first: every input mistake is found before F is computed, and nothing is written.
    const ThermalInputs inputs = readThermalModel(scene, options, reporter, warnings);
    const FormFactors F = obtainFormFactors(scene, thermalFormFactorOptions(options), timings, reporter, warnings);
    solveThermalAndWrite(options, scene, inputs, F, timings, reporter, warnings);
    finishCommand(reporter, timings, warnings);
    return 0;
}

Options thermalFormFactorOptions(const Options& options) {
    Options withRows = options;
    withRows.allRows = true;  // every patch's irradiance and escape are needed
    return withRows;
}

}  // namespace hemirad
