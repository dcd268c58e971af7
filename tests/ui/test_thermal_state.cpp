// hemirad-gui's thermal state, driven without a window: the bundled radiator's files loaded, refused
// files and edits changing nothing, the run on the worker thread against `hemirad thermal`, the
// false-colour T and q with their legend, the exchange table's CSV.
#include "support.hpp"

#include "engine/subdivide.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "ui/app_state.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace hemirad;
using namespace hemirad::test;
using hemirad::ui::AppState;
using hemirad::ui::FalseColourSettings;
using hemirad::ui::ObjectCondition;
using hemirad::ui::ObjectThermalRow;

namespace {

const std::string kProperties = "examples/thermal/radiator_properties.toml";
const std::string kConditions = "examples/thermal/radiator_bc.toml";

bool logged(const AppState& app, const std::string& text) {
    for (const auto& e : app.log())
        if (e.text.find(text) != std::string::npos) return true;
    return false;
}

/// The radiator with both files loaded.
void loadRadiator(AppState& app) {
    REQUIRE(app.loadScene(sourcePath("examples/thermal/radiator.obj")));
    REQUIRE(app.loadThermalProperties(sourcePath(kProperties)));
    REQUIRE(app.loadThermalConditions(sourcePath(kConditions)));
}

void runToEnd(AppState& app) {
    app.wait();
    app.poll();
}

std::vector<ObjectThermalRow> rows(const AppState& app) {
    std::optional<double> environment;
    std::string error;
    std::vector<ObjectThermalRow> r = app.thermalObjects(environment, error);
    INFO(error);
    REQUIRE(error.empty());
    return r;
}

/// `hemirad thermal` on the bundled files: its report and the exchange CSV it wrote.
struct CliRun {
    std::string output, exchangeCsv;
};
/// `hemirad thermal` on the radiator's files into tempDir(name), with `extra` options.
CliRun cliThermal(const std::string& name, const std::string& extra = "") {
    const auto dir = tempDir(name);
    const std::string exchange = (dir / "Q.csv").string();
    const CommandResult cli = runCommand(std::string(HEMIRAD_BINARY) + " thermal " + sourcePath("examples/thermal/radiator.obj") +
                                         " --properties " + sourcePath(kProperties) + " --bc " + sourcePath(kConditions) + " -o " +
                                         (dir / "T.csv").string() + " --exchange " + exchange + extra + " 2>&1");
    INFO(cli.output);
    REQUIRE(cli.status == 0);
    return {cli.output, readText(exchange)};
}

/// The number after `prefix` in `text`.
double numberAfter(const std::string& text, const std::string& prefix) {
    const std::size_t at = text.find(prefix);
    INFO(prefix);
    REQUIRE(at != std::string::npos);
    return std::stod(text.substr(at + prefix.size()));
}

}  // namespace

TEST_CASE("hemirad-gui loads the radiator's thermal files: per object emissivity, specular and condition") {
    AppState app;
    loadRadiator(app);
    const std::vector<ObjectThermalRow> r = rows(app);
    REQUIRE(r.size() == 3);
    CHECK(r[0].name == "radiator");
    CHECK(r[0].emissivity == doctest::Approx(0.88));
    REQUIRE(r[0].condition);
    CHECK(r[0].condition->kind == ObjectCondition::Kind::Power);
    CHECK(r[0].condition->value == 250.0);
    CHECK(r[1].specular == doctest::Approx(0.9));  // the properties file's s became the scene's
    CHECK(r[1].condition->kind == ObjectCondition::Kind::Adiabatic);
    CHECK(r[1].solar == 1361.0);
    CHECK(r[2].condition->kind == ObjectCondition::Kind::Temperature);
    CHECK(r[2].condition->value == doctest::Approx(253.15));  // temperature_C = -20
    CHECK(app.thermalLoadError().empty());
}

TEST_CASE("hemirad-gui refuses an invalid boundary-condition file with its file:line and keeps the loaded one") {
    AppState app;
    loadRadiator(app);
    const auto dir = tempDir("gui-thermal-bad-bc");
    const std::string bad = (dir / "bad_bc.toml").string();
    std::ofstream(bad) << "[environment]\ntemperature_K = 3\n[objects.radiator]\ntemperature_K = -5\n";
    const std::uint64_t revision = app.thermalRevision();
    CHECK_FALSE(app.loadThermalConditions(bad));
    CHECK(app.thermalLoadError().find(bad + ":4:") != std::string::npos);
    CHECK(logged(app, bad + ":4:"));
    CHECK(app.thermalRevision() != revision);  // the panel reloads its fields
    CHECK(app.thermalSetup().conditionsPath == sourcePath(kConditions));
    const std::vector<ObjectThermalRow> r = rows(app);
    CHECK(r[0].condition->kind == ObjectCondition::Kind::Power);  // unchanged
    CHECK(r[2].condition->value == doctest::Approx(253.15));
    // A good load clears the error.
    CHECK(app.loadThermalConditions(sourcePath(kConditions)));
    CHECK(app.thermalLoadError().empty());
}

TEST_CASE("hemirad-gui refuses thermal edits the library refuses and keeps the values in effect") {
    AppState app;
    loadRadiator(app);
    std::vector<ObjectThermalRow> r = rows(app);
    const std::uint32_t radiator = r[0].object, shield = r[1].object, baffle = r[2].object;
    const std::uint64_t revision = app.thermalRevision();
    CHECK_FALSE(app.setObjectEmissivity(radiator, 1.5));
    CHECK(app.thermalRevision() != revision);  // the panel's field reloads the value in effect
    CHECK(logged(app, "emissivity of 'radiator' refused"));
    CHECK_FALSE(app.setObjectEmissivity(shield, 0.2));  // the shield's s = 0.9: eps + s > 1
    CHECK(logged(app, "emissivity of 'shield' refused"));
    CHECK_FALSE(app.setObjectCondition(baffle, {ObjectCondition::Kind::Temperature, -5.0}));
    CHECK(logged(app, "condition of 'baffle' refused"));
    CHECK_FALSE(app.setThermalEnvironment(-1.0));
    CHECK_FALSE(app.setObjectEmissivity(std::uint32_t(app.scene().objects.size()), 0.5));  // no such object
    r = rows(app);
    CHECK(r[0].emissivity == doctest::Approx(0.88));
    CHECK(r[1].emissivity == doctest::Approx(0.05));
    CHECK(r[2].condition->value == doctest::Approx(253.15));
    CHECK_FALSE(r[0].emissivityEdited);
    // Accepted edits show.
    CHECK(app.setObjectEmissivity(radiator, 0.5));
    CHECK(app.setObjectCondition(baffle, {ObjectCondition::Kind::Flux, -20.0}));
    r = rows(app);
    CHECK(r[0].emissivity == doctest::Approx(0.5));
    CHECK(r[0].emissivityEdited);
    CHECK(r[2].condition->kind == ObjectCondition::Kind::Flux);
    CHECK(r[2].condition->value == -20.0);
}

TEST_CASE("hemirad-gui's thermal run with specular reflectances per IR band: each band on its own F, hemirad thermal's T") {
    const auto dir = tempDir("gui-thermal-bands");
    const std::string properties =
        writeFile(dir / "bands.toml", "[bands]\nlimits_um = [4.0]\n[materials.white_paint]\nemissivity = 0.88\n"
                                      "[materials.aluminium]\nemissivity = [0.05, 0.2]\nspecular = [0.9, 0.6]\n"
                                      "[materials.black_paint]\nemissivity = 0.9\n");
    const CommandResult cli = runCommand(std::string(HEMIRAD_BINARY) + " thermal " + sourcePath("examples/thermal/radiator.obj") +
                                         " --properties " + properties + " --bc " + sourcePath(kConditions) + " -o " +
                                         (dir / "T.csv").string() + " 2>&1");
    INFO(cli.output);
    REQUIRE(cli.status == 0);
    AppState app;
    REQUIRE(app.loadScene(sourcePath("examples/thermal/radiator.obj")));
    REQUIRE(app.loadThermalProperties(properties));
    REQUIRE(app.loadThermalConditions(sourcePath(kConditions)));
    app.runThermal();
    runToEnd(app);
    const ui::ThermalResult* result = app.thermalResult();
    REQUIRE(result != nullptr);
    REQUIRE(result->solution.isothermalT.size() == 1);
    CHECK(result->solution.isothermalT[0] == doctest::Approx(numberAfter(cli.output, "isothermal 'radiator': T = ")).epsilon(1e-5));
    CHECK(logged(app, "IR band 1: its specular reflectances differ from the scene's"));
    CHECK(logged(app, "IR band 2: its specular reflectances differ from the scene's"));
    CHECK(result->solution.balance < 1e-9);
}

TEST_CASE("hemirad-gui's thermal run gives the radiator's T of hemirad thermal, the balance, T and q in false colour") {
    const CliRun cli = cliThermal("gui-thermal-cli");
    AppState app;
    loadRadiator(app);
    app.falseColour.thermal = FalseColourSettings::Thermal::Temperature;
    CHECK_FALSE(app.falseColourView().error.empty());  // no result yet
    app.runThermal();
    CHECK(app.job().running);
    runToEnd(app);
    const ui::ThermalResult* result = app.thermalResult();
    REQUIRE(result != nullptr);
    REQUIRE(result->solution.isothermalT.size() == 1);
    const double cliT = numberAfter(cli.output, "isothermal 'radiator': T = ");
    CHECK(result->solution.isothermalT[0] == doctest::Approx(cliT).epsilon(1e-5));
    CHECK(logged(app, "isothermal 'radiator': T = "));
    CHECK(logged(app, "energy balance: "));
    CHECK(logged(app, "solar band: "));
    CHECK(result->solution.balance < 1e-9);
    CHECK(app.formFactors() != nullptr);  // F with every row serves the radiosity too
    CHECK(app.formFactors()->computedRows() == app.scene().size());
    // T in false colour: the range spans the solved temperatures, the legend says K.
    ui::FalseColourView view = app.falseColourView();
    CHECK(view.error.empty());
    CHECK(view.range.max >= result->solution.isothermalT[0] - 1e-9);
    CHECK(app.falseColourLegend().first == "temperature T");
    CHECK(app.falseColourLegend().second == "K");
    app.falseColour.thermal = FalseColourSettings::Thermal::HeatFlux;
    view = app.falseColourView();
    CHECK(view.error.empty());
    CHECK(app.falseColourLegend().second.find("W/m^2") == 0);
    // An accepted edit makes the result out of date.
    CHECK_FALSE(app.thermalStale());
    CHECK(app.setObjectEmissivity(rows(app)[0].object, 0.7));
    CHECK(app.thermalStale());
}

TEST_CASE("hemirad-gui undoes and redoes thermal edits (files, emissivity, condition, environment), which leave the scene clean") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("examples/thermal/radiator.obj")));
    const std::uint32_t shieldPatch = [&] {
        for (PatchId i = 0; i < app.scene().size(); ++i)
            if (app.scene().objects[app.scene().patches[i].object] == "shield") return std::uint32_t(i);
        return std::uint32_t(0);
    }();
    const double sBefore = app.scene().patches[shieldPatch].specular;
    REQUIRE(app.loadThermalProperties(sourcePath(kProperties)));
    const double sFile = app.scene().patches[shieldPatch].specular;
    CHECK(sFile == 0.9);  // aluminium: the file's specular reflectance becomes the scene's
    REQUIRE(app.loadThermalConditions(sourcePath(kConditions)));
    CHECK_FALSE(app.dirty());  // thermal inputs are not saved with the scene
    const std::vector<ObjectThermalRow> loaded = rows(app);
    const std::uint32_t radiator = loaded[0].object;
    REQUIRE(app.setObjectEmissivity(radiator, 0.7));
    ObjectCondition hot;
    hot.kind = ObjectCondition::Kind::Temperature;
    hot.value = 350.0;
    REQUIRE(app.setObjectCondition(radiator, hot));
    REQUIRE(app.setThermalEnvironment(250.0));
    CHECK_FALSE(app.dirty());
    CHECK(rows(app)[0].emissivity == doctest::Approx(0.7));
    // Back, one edit at a time.
    app.undo();  // the environment
    std::optional<double> environment;
    std::string error;
    app.thermalObjects(environment, error);
    CHECK(environment != std::optional<double>(250.0));
    app.undo();  // the condition
    REQUIRE(rows(app)[0].condition);
    CHECK(rows(app)[0].condition->kind == loaded[0].condition->kind);
    app.undo();  // the emissivity
    CHECK(rows(app)[0].emissivity == doctest::Approx(0.88));
    CHECK_FALSE(rows(app)[0].emissivityEdited);
    app.undo();  // the conditions file: no condition left
    CHECK_FALSE(rows(app)[0].condition);
    app.undo();  // the properties file and the mirror reflectance it set
    CHECK(app.scene().patches[shieldPatch].specular == sBefore);
    CHECK(app.thermalSetup().propertiesPath.empty());
    CHECK_FALSE(app.canUndo());
    CHECK_FALSE(app.dirty());
    // And forward again.
    for (int k = 0; k < 5; ++k) app.redo();
    CHECK(app.scene().patches[shieldPatch].specular == sFile);
    CHECK(rows(app)[0].emissivity == doctest::Approx(0.7));
    app.thermalObjects(environment, error);
    CHECK(environment == std::optional<double>(250.0));
    CHECK_FALSE(app.canRedo());
    // Saved here; two thermal edits undone below the saved depth and a new one made: the saved
    // state is still what the scene holds (only thermal steps were dropped from the redo history).
    REQUIRE(app.saveScene((tempDir("gui-thermal-undo") / "saved.obj").string()));
    app.undo();
    app.undo();
    CHECK_FALSE(app.dirty());
    REQUIRE(app.setThermalEnvironment(260.0));
    CHECK_FALSE(app.dirty());
    // A material edit does make the scene dirty; undoing it (past no thermal edit) cleans it.
    app.select(0, false);
    ui::MaterialEdit edit;
    edit.emission = Rgb::Constant(1.0);
    REQUIRE(app.editMaterial(edit));
    CHECK(app.dirty());
    REQUIRE(app.setObjectEmissivity(radiator, 0.5));
    app.undo();
    CHECK(app.dirty());
    app.undo();
    CHECK_FALSE(app.dirty());
    // A thermal edit after undoing back to the saved state keeps it reachable (nothing in the scene changed).
    app.redo();
    app.undo();
    REQUIRE(app.setObjectEmissivity(radiator, 0.6));
    CHECK_FALSE(app.dirty());
}

TEST_CASE("hemirad-gui exports the radiative conductors per object as hemirad thermal --conductors writes them, in its formats") {
    const auto dir = tempDir("gui-thermal-conductors");
    // The command's conductors for the same files (objects lumped, the environment last).
    const std::string reference = (dir / "cli.esatan").string();
    cliThermal("gui-thermal-conductors-cli", " --conductors " + reference);
    AppState app;
    loadRadiator(app);
    CHECK_FALSE(app.exportThermalConductors((dir / "none.esatan").string()));  // no result yet
    app.runThermal();
    runToEnd(app);
    const std::string esatan = (dir / "gui.esatan").string();
    REQUIRE(app.exportThermalConductors(esatan));
    // The same lines: the node names in the comments, then GR(a, b) = v; per coupling.
    const std::string gui = readText(esatan), ref = readText(reference);
    auto couplings = [](const std::string& text) {
        std::vector<std::pair<std::string, double>> out;
        std::istringstream lines(text);
        for (std::string line; std::getline(lines, line);)
            if (line.rfind("GR(", 0) == 0) out.emplace_back(line.substr(0, line.find('=')), std::stod(line.substr(line.find('=') + 1)));
        return out;
    };
    const auto a = couplings(gui), b = couplings(ref);
    REQUIRE(a.size() == b.size());
    CHECK(a.size() == 6);  // radiator, shield, baffle and the environment: 3 + 3
    for (std::size_t k = 0; k < a.size(); ++k) {
        CHECK(a[k].first == b[k].first);
        CHECK(a[k].second == doctest::Approx(b[k].second).epsilon(1e-9));
    }
    CHECK(gui.substr(0, gui.find("GR(")) == ref.substr(0, ref.find("GR(")));
    // The other formats by extension; an unknown one is refused and writes nothing.
    REQUIRE(app.exportThermalConductors((dir / "gr.csv").string()));
    CHECK(readText(dir / "gr.csv").rfind("node_a,node_b,GR", 0) == 0);
    REQUIRE(app.exportThermalConductors((dir / "gr.inp").string()));
    CHECK(readText(dir / "gr.inp").find("CONDUCTOR DATA") != std::string::npos);
    CHECK_FALSE(app.exportThermalConductors((dir / "gr.txt").string()));
    CHECK_FALSE(std::filesystem::exists(dir / "gr.txt"));
}

TEST_CASE("hemirad-gui exports the object exchange table as hemirad thermal --exchange writes it, units in the header") {
    const CliRun cli = cliThermal("gui-thermal-exchange-cli");
    AppState app;
    loadRadiator(app);
    CHECK_FALSE(app.exportThermalExchange((tempDir("gui-thermal-none") / "Q.csv").string()));  // no result yet
    app.runThermal();
    runToEnd(app);
    const std::string path = (tempDir("gui-thermal-exchange") / "Q.csv").string();
    REQUIRE(app.exportThermalExchange(path));
    const std::string csv = readText(path);
    std::istringstream lines(csv);
    std::string header;
    std::getline(lines, header);
    CHECK(header == "Q from \\ to (W),radiator,shield,baffle,environment,total");
    // The same numbers as the command's (same F settings, same solve).
    std::istringstream cliLines(cli.exchangeCsv);
    std::string gui, ref;
    std::getline(cliLines, ref);
    CHECK(ref == header);
    int objects = 0;
    while (std::getline(lines, gui) && std::getline(cliLines, ref)) {
        CHECK(gui.substr(0, gui.find(',')) == ref.substr(0, ref.find(',')));
        const double a = std::stod(gui.substr(gui.rfind(',') + 1)), b = std::stod(ref.substr(ref.rfind(',') + 1));
        CHECK(a == doctest::Approx(b).epsilon(1e-5));  // each object's total Q
        ++objects;
    }
    CHECK(objects == 3);
    // The radiator's row sums to the IR it gives off: its 250 W and the sunlight it absorbs.
    const ui::ThermalResult* r = app.thermalResult();
    double total = 0.0, solar = 0.0;
    for (const double q : r->exchange[0]) total += q;
    REQUIRE(r->model.absorbedExternal.size() == app.scene().size());
    for (PatchId i = 0; i < app.scene().size(); ++i)
        if (app.scene().objects[app.scene().patches[i].object] == "radiator")
            solar += r->solution.areaM2[i] * r->model.absorbedExternal[i];
    CHECK(solar > 0.0);
    CHECK(total == doctest::Approx(250.0 + solar).epsilon(1e-6));
}

TEST_CASE("hemirad-gui's thermal run is refused without conditions and names the objects that lack one") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("examples/thermal/radiator.obj")));
    app.runThermal();
    CHECK_FALSE(app.job().running);
    CHECK(logged(app, "no boundary condition for 'radiator', 'shield', 'baffle'"));
    CHECK(app.thermalResult() == nullptr);
}

TEST_CASE("hemirad-gui's thermal run is cancelled during a long form-factor computation and keeps the state") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/unit_cube.obj")));
    app.setScene(subdivide(app.scene(), 0.05), "fine cube");  // 2,400 patches
    app.settings.formFactors.as<HemisphereOptions>().samples = 3072;
    app.settings.formFactors.as<HemisphereOptions>().origins = 64;
    // Conditions set per object in the panel (no file): every object held at 300 K.
    for (const ObjectThermalRow& r : rows(app)) REQUIRE(app.setObjectCondition(r.object, {ObjectCondition::Kind::Temperature, 300.0}));
    app.runThermal();
    CHECK(app.job().running);
    app.cancel();
    runToEnd(app);
    CHECK_FALSE(app.job().running);
    CHECK(logged(app, "cancelled"));
    CHECK(app.thermalResult() == nullptr);
    CHECK(app.formFactors() == nullptr);
}

TEST_CASE("hemirad-gui shows an object's emissivity against temperature, and says when a typed value replaces it") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("examples/thermal/radiator.obj")));
    const auto dir = tempDir("gui-thermal-curve");
    const std::string properties = (dir / "curve.toml").string();
    std::ofstream(properties) << readText(sourcePath(kProperties))
                              << "\n[objects.radiator]\nemissivity = [[200, 0.8], [300, 0.85], [400, 0.9]]\n";
    REQUIRE(app.loadThermalProperties(properties));
    REQUIRE(app.loadThermalConditions(sourcePath(kConditions)));
    std::vector<ObjectThermalRow> r = rows(app);
    REQUIRE(r[0].name == "radiator");
    CHECK(r[0].emissivity == doctest::Approx(0.85));  // the curve at the reference temperature, 300 K
    CHECK(r[0].emissivityCurve == "eps(T) from the properties file: 0.8 at 200 K, 0.85 at 300 K, 0.9 at 400 K "
                                  "(shown: the value at 300 K)");
    CHECK(r[1].emissivityCurve.empty());  // the shield's constant 0.05
    CHECK(app.setObjectEmissivity(r[0].object, 0.5));
    CHECK(logged(app, "emissivity of 'radiator': the constant 0.5 replaces its eps(T) from the properties file: 0.8 at 200 K"));
    r = rows(app);
    CHECK(r[0].emissivity == doctest::Approx(0.5));
    CHECK(r[0].emissivityCurve.empty());
    CHECK(app.setObjectEmissivity(r[1].object, 0.06));
    CHECK_FALSE(logged(app, "emissivity of 'shield': the constant"));
}
