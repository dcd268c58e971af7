// hemirad-gui's application state, driven without a window: loading, selection, edits that re-solve
// with the existing F, the stale-F rules, undo/redo, F import checks, cancellation.
#include "support.hpp"

#include "engine/form_factor_file.hpp"
#include "engine/form_factor_shards.hpp"
#include "engine/object_table.hpp"
#include "engine/subdivide.hpp"
#include "engine/tone_map.hpp"
#include "preprocess/backend_registry.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "ui/app_state.hpp"
#include "ui/run_estimate.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

using namespace hemirad;
using namespace hemirad::test;
using hemirad::ui::AppState;
using hemirad::ui::MaterialEdit;
using hemirad::ui::SelectionMode;
using hemirad::ui::SelectionSummary;
using hemirad::ui::FormFactorEstimate;

namespace {

bool logged(const AppState& app, const std::string& text) {
    for (const auto& e : app.log())
        if (e.text.find(text) != std::string::npos) return true;
    return false;
}

void runToEnd(AppState& app) {
    app.wait();
    app.poll();
    app.wait();  // a re-solve the results may have queued
    app.poll();
}

/// The unit cube with a small F (fast), solved.
void solvedCube(AppState& app) {
    REQUIRE(app.loadScene(sourcePath("scenes/unit_cube.obj")));
    app.settings.formFactors.as<HemisphereOptions>().samples = 384;
    app.settings.formFactors.as<HemisphereOptions>().origins = 4;
    app.runPipeline();
    runToEnd(app);
    REQUIRE(app.formFactors() != nullptr);
}

/// Patch 0 made black (no row of F needed), then Run with 384 directions (the job started).
void runWithBlackPatch0(AppState& app) {
    app.select(0, false);
    MaterialEdit black;
    black.rho = Rgb::Zero();
    app.editMaterial(black);
    app.settings.formFactors.as<HemisphereOptions>().samples = 384;
    app.runPipeline();
}

/// Patch 0 (selected) made reflective again: its row of F is needed.
void makePatch0Grey(AppState& app) {
    MaterialEdit grey;
    grey.rho = Rgb::Constant(0.5);
    app.editMaterial(grey);
}

}  // namespace

TEST_CASE("GUI state: a bad file keeps the loaded scene and logs the error with its location") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    CHECK(app.scene().size() == 20);
    const auto dir = tempDir("gui-bad");
    CHECK_FALSE(app.loadScene(writeFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n")));
    CHECK(app.scene().size() == 20);
    CHECK(logged(app, "bad.obj:3: vertex z 'nan' is not a finite number"));
    CHECK(app.log().back().error);
}

TEST_CASE("GUI state: picking in object mode selects the whole object") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    app.setScene(subdivide(app.scene(), 200.0), "cornell");
    const PatchId first = 0;
    const std::uint32_t object = app.scene().patches[first].object;
    std::size_t inObject = 0;
    for (const Patch& p : app.scene().patches) inObject += p.object == object;
    app.selectionMode = SelectionMode::Object;
    app.select(first, false);
    CHECK(app.selection().size() == inObject);
    app.selectionMode = SelectionMode::Patch;
    app.select(first, false);
    CHECK(app.selection().size() == 1);
    app.select(1, true);
    CHECK(app.selection().size() == 2);
    app.clearSelection();
    CHECK(app.selection().empty());
}

TEST_CASE("GUI state: an emission edit re-solves with the same F (no new rays)") {
    AppState app;
    solvedCube(app);
    const FormFactors* before = app.formFactors();
    const double floorB = app.radiosity()[0][0];
    app.select(0, false);
    MaterialEdit edit;
    edit.emission = Rgb::Constant(2.0);  // the floor emitted 1
    app.editMaterial(edit);
    CHECK(app.dirty());
    CHECK(app.radiosityStale());
    runToEnd(app);
    CHECK(app.formFactors() == before);  // the very same F object: no recomputation
    CHECK_FALSE(app.radiosityStale());
    CHECK(app.radiosity()[0][0] == doctest::Approx(2.0 * floorB).epsilon(1e-6));  // linear in E
    CHECK(logged(app, "solve: "));
}

TEST_CASE("GUI state: a mirror edit makes F stale, undo makes it valid again, redo re-applies") {
    AppState app;
    solvedCube(app);
    app.select(2, false);
    MaterialEdit edit;
    edit.specular = 0.3;
    edit.rho = Rgb::Constant(0.4);
    app.editMaterial(edit);
    CHECK(app.formFactorsStale());
    CHECK(app.scene().patches[2].specular == 0.3);
    CHECK(app.canUndo());
    app.undo();
    CHECK_FALSE(app.formFactorsStale());
    CHECK(app.scene().patches[2].specular == 0.0);
    CHECK(app.scene().patches[2].rho[0] == doctest::Approx(0.5));
    app.redo();
    CHECK(app.formFactorsStale());
    CHECK(app.scene().patches[2].rho[0] == doctest::Approx(0.4));
    runToEnd(app);
    app.runPipeline();  // recomputes F for the mirror
    runToEnd(app);
    CHECK_FALSE(app.formFactorsStale());
    CHECK(app.formFactors()->provenance.method == "hemisphere");
}

TEST_CASE("GUI state: invalid material values are refused with a message") {
    AppState app;
    solvedCube(app);
    app.select(1, false);
    MaterialEdit edit;
    edit.rho = Rgb(0.5, 1.5, 0.5);
    app.editMaterial(edit);
    CHECK(app.scene().patches[1].rho[1] == doctest::Approx(0.5));
    CHECK(logged(app, "diffuse reflectance must be finite and in [0, 1]"));
    CHECK_FALSE(app.canUndo());
}

TEST_CASE("GUI state: an edit that would make rho + s > 1 is refused, as the MTL loader refuses it") {
    AppState app;
    solvedCube(app);  // rho 0.5 everywhere
    app.select(1, false);
    MaterialEdit mirror;
    mirror.specular = 0.8;  // 0.5 + 0.8 > 1: saving it would write an MTL the loader rejects
    app.editMaterial(mirror);
    CHECK(app.scene().patches[1].specular == 0.0);
    CHECK(logged(app, "patch 1 would reflect more than it receives: rho + s = 1.3"));
    CHECK_FALSE(app.canUndo());
    MaterialEdit both;  // the same mirror with a darker diffuse part is physical
    both.rho = Rgb::Constant(0.1);
    both.specular = 0.8;
    app.editMaterial(both);
    CHECK(app.scene().patches[1].specular == doctest::Approx(0.8));
    CHECK(app.canUndo());
}

TEST_CASE("GUI state: a black patch made reflective gets its row computed, the others are kept") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/unit_cube.obj")));
    runWithBlackPatch0(app);
    runToEnd(app);
    REQUIRE(app.formFactors() != nullptr);
    CHECK_FALSE(app.formFactors()->rowComputed(0));
    const double kept = app.formFactors()->values()[app.formFactors()->rowBegin(1)];
    makePatch0Grey(app);  // re-solve needs row 0: the pipeline adds just that row
    runToEnd(app);
    REQUIRE(app.formFactors()->rowComputed(0));
    CHECK(app.formFactors()->values()[app.formFactors()->rowBegin(1)] == kept);
    CHECK(logged(app, "1 rows"));
}

TEST_CASE("GUI state: a black patch made reflective while a job runs gets its row once the job ends (issue 35 #9)") {
    // The edit queues a re-solve; it used to start the solve alone, which failed with "row 0 of F was
    // not computed".
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/unit_cube.obj")));
    app.setScene(subdivide(app.scene(), 0.05), "fine cube");  // 2,400 patches: the job outlives the edit
    runWithBlackPatch0(app);
    REQUIRE(app.job().running);
    makePatch0Grey(app);
    runToEnd(app);
    REQUIRE(app.formFactors() != nullptr);
    CHECK(app.formFactors()->rowComputed(0));
    CHECK_FALSE(logged(app, "was not computed"));
    CHECK_FALSE(app.radiosityStale());
    CHECK(app.radiosity()[0][0] > 0.0);
}

TEST_CASE("GUI state: importing F checks that it belongs to the scene") {
    AppState app;
    solvedCube(app);
    const auto dir = tempDir("gui-ff");
    REQUIRE(app.exportFormFactors((dir / "cube.hff").string()));
    // Importing re-solves with the imported F: B is current again without pressing Run.
    app.select(0, false);
    MaterialEdit edit;
    edit.emission = Rgb::Constant(3.0);
    app.autoResolve = false;
    app.editMaterial(edit);
    CHECK(app.radiosityStale());
    app.autoResolve = true;
    CHECK(app.importFormFactors((dir / "cube.hff").string()));
    runToEnd(app);
    CHECK_FALSE(app.radiosityStale());
    CHECK(app.radiosity()[0][0] > 3.0);  // the new emission, solved
    // A sharded F (a manifest and its shards, as MPI ranks write it) imports as one F.
    const FormFactors exported = *app.formFactors();
    saveShardedFormFactors(exported, (dir / "sharded.hff").string(), 3);
    CHECK(app.importFormFactors((dir / "sharded.hff").string()));
    CHECK(app.formFactors()->valueVector() == exported.valueVector());
    REQUIRE(app.loadScene(sourcePath("scenes/parallel_plates.obj")));
    CHECK_FALSE(app.importFormFactors((dir / "cube.hff").string()));
    CHECK(logged(app, "F has 6 patches but the scene has 2"));
}

TEST_CASE("GUI state: cancel stops a long form-factor computation and keeps the state") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/unit_cube.obj")));
    app.setScene(subdivide(app.scene(), 0.05), "fine cube");  // 2,400 patches
    app.settings.formFactors.as<HemisphereOptions>().samples = 3072;
    app.settings.formFactors.as<HemisphereOptions>().origins = 64;
    app.runPipeline();
    CHECK(app.job().running);
    app.cancel();
    runToEnd(app);
    CHECK_FALSE(app.job().running);
    CHECK(app.formFactors() == nullptr);
    CHECK(logged(app, "cancelled"));
}

TEST_CASE("GUI state: Run computes F again when the method or its options changed, and Recompute F forces it") {
    // Issue 14, defect 1: Run solved with the old F after the panel's method or options changed.
    AppState app;
    solvedCube(app);  // hemisphere, 384 directions x 4 origins
    CHECK(app.formFactors()->parameters.at("samples") == "384");
    app.runPipeline();
    runToEnd(app);
    CHECK(logged(app, "running: solve (form factors are current)"));
    CHECK(app.formFactorsMatchSettings());

    // The thread count makes F faster, not different.
    app.settings.formFactors.common.threads = 1;
    CHECK(app.formFactorsMatchSettings());
    // An option of the same back end.
    app.settings.formFactors.as<HemisphereOptions>().samples = 768;
    CHECK_FALSE(app.formFactorsMatchSettings());
    app.runPipeline();
    runToEnd(app);
    CHECK(logged(app, "the form-factor settings changed since F was made: computing F again"));
    CHECK(app.formFactors()->parameters.at("samples") == "768");
    CHECK(app.formFactorsMatchSettings());
    // The mirror depth.
    app.settings.formFactors.common.maxDepth = 3;
    CHECK_FALSE(app.formFactorsMatchSettings());
    app.runPipeline();
    runToEnd(app);
    CHECK(app.formFactors()->parameters.at("max_depth") == "3");
    // Another back end: the hemicube's F replaces the hemisphere's, and the stats follow.
    app.settings.formFactors = defaultSettings("hemicube");
    setBackendOption(app.settings.formFactors, "--resolution", "16");
    app.runPipeline();
    runToEnd(app);
    REQUIRE(app.formFactors() != nullptr);
    CHECK(app.formFactors()->provenance.method == "hemicube");
    CHECK(app.formFactors()->parameters.at("resolution") == "16");
    REQUIRE(app.formFactorStats().has_value());
    CHECK(app.formFactorStats()->rowSumMean == doctest::Approx(1.0).epsilon(1e-3));

    // Recompute F computes every row again with the same settings.
    const auto computed = [&] {
        return std::count_if(app.log().begin(), app.log().end(),
                             [](const auto& e) { return e.text.rfind("form factors: hemicube", 0) == 0; });
    };
    const auto runs = computed();
    CHECK(runs == 1);
    app.recomputeFormFactors();
    runToEnd(app);
    CHECK(logged(app, "running: form factors (recomputed) and solve"));
    CHECK(computed() == runs + 1);
    REQUIRE(app.formFactors() != nullptr);
    CHECK(app.formFactors()->computedRows() == 6);
    CHECK(app.formFactorsMatchSettings());
}

TEST_CASE("GUI state: after a mirror edit, save, reopen and import of the exported F work end to end") {
    // Issue 14, defect 2: the mirror slider stored 0.9 as a float, the MTL kept 9 digits, and the
    // reopened scene's hash refused the F exported before ("computed for another scene").
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/mirror_pair.obj")));
    PatchId mirror = 0;
    while (!(app.scene().patches[mirror].specular > 0.0)) ++mirror;
    app.select(mirror, false);
    MaterialEdit edit;
    edit.specular = double(0.9f);  // what a 32-bit widget hands over: 0.89999997615814209
    app.editMaterial(edit);
    REQUIRE(app.scene().patches[mirror].specular == double(0.9f));
    app.settings.formFactors.as<HemisphereOptions>().samples = 384;
    app.runPipeline();
    runToEnd(app);
    REQUIRE(app.formFactors() != nullptr);
    const auto dir = tempDir("gui-save-reopen");
    REQUIRE(app.exportFormFactors((dir / "F.hff").string()));
    REQUIRE(app.saveScene((dir / "edited.obj").string()));
    AppState reopened;
    REQUIRE(reopened.loadScene((dir / "edited.obj").string()));
    CHECK(reopened.scene().patches[mirror].specular == double(0.9f));
    CHECK(reopened.scene().geometryHash() == app.scene().geometryHash());
    CHECK(reopened.importFormFactors((dir / "F.hff").string()));
    CHECK_FALSE(logged(reopened, "computed for another scene"));
}

TEST_CASE("GUI state: undo back to the saved values is not an unsaved edit, and redo is") {
    // Issue 14, defect 5: "(edited)" survived an undo back to the original values.
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/unit_cube.obj")));
    app.autoResolve = false;
    CHECK_FALSE(app.dirty());
    app.select(0, false);
    MaterialEdit edit;
    edit.rho = Rgb(0.12, 0.3, 0.4);
    const std::uint64_t revision = app.materialsRevision();
    app.editMaterial(edit);
    CHECK(app.materialsRevision() > revision);  // the editor reloads its fields from the patch
    CHECK(app.dirty());
    app.undo();
    CHECK_FALSE(app.dirty());
    CHECK(app.materialsRevision() > revision + 1);
    app.redo();
    CHECK(app.dirty());
    CHECK((app.scene().patches[0].rho == Rgb(0.12, 0.3, 0.4)).all());  // as typed, not re-quantised
    const auto dir = tempDir("gui-dirty");
    REQUIRE(app.saveScene((dir / "cube.obj").string()));
    CHECK_FALSE(app.dirty());
    app.undo();  // before the save: an unsaved change again
    CHECK(app.dirty());
    app.redo();
    CHECK_FALSE(app.dirty());
    app.undo();
    edit.rho = Rgb(0.2, 0.2, 0.2);  // a new edit drops the redo step that led to the saved state
    app.editMaterial(edit);
    CHECK(app.dirty());
    app.undo();
    CHECK(app.dirty());
}

TEST_CASE("GUI state: an object selection is summed: count, objects, total area, area-weighted means") {
    // Issue 14, defect 6: object and multi-patch selections showed only their first patch.
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    app.setScene(subdivide(app.scene(), 200.0), "cornell");
    app.selectionMode = SelectionMode::Object;
    app.select(0, false);
    const Scene& s = app.scene();
    const SelectionSummary one = app.selectionSummary();
    double area = 0.0;
    Rgb rhoArea = Rgb::Zero();
    for (PatchId i : app.selection()) {
        area += s.patches[i].area;
        rhoArea += s.patches[i].area * s.patches[i].rho;
    }
    CHECK(one.patches == app.selection().size());
    CHECK(one.patches > 1);
    CHECK(one.objects == 1);
    CHECK(one.area == doctest::Approx(area));
    CHECK(one.rho[0] == doctest::Approx(rhoArea[0] / area));
    CHECK((one.radiosity == one.emission).all());  // before any solve B is E
    // A second object added: two objects, areas add up, means weight by area.
    PatchId other = 0;
    while (s.patches[other].object == s.patches[0].object || !(s.patches[other].emission > 0.0).any()) ++other;  // the light
    app.select(other, true);
    const SelectionSummary two = app.selectionSummary();
    double lightArea = 0.0;
    for (const Patch& p : s.patches)
        if (p.object == s.patches[other].object) lightArea += p.area;
    CHECK(two.objects == 2);
    CHECK(two.area == doctest::Approx(area + lightArea));
    CHECK(two.emission[0] == doctest::Approx(s.patches[other].emission[0] * lightArea / (area + lightArea)));
    CHECK(two.power[0] == doctest::Approx(s.patches[other].emission[0] * lightArea));
    app.clearSelection();
    CHECK(app.selectionSummary().patches == 0);
}

TEST_CASE("GUI state: the object table equals the CLI's CSV aggregated per object, and solve --objects writes the same") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    const Scene scene = subdivide(app.scene(), 60.0);
    app.setScene(scene, "cornell");
    app.settings.formFactors.as<HemisphereOptions>().samples = 256;
    app.settings.formFactors.as<HemisphereOptions>().estimator = Estimator::Rays;  // F's accuracy is not the point
    app.runPipeline();
    runToEnd(app);
    REQUIRE(app.formFactors() != nullptr);
    const auto dir = tempDir("gui-objects");
    REQUIRE(app.exportObjectTable((dir / "gui.csv").string()));

    const CommandResult cli = runCommand(std::string(HEMIRAD_BINARY) + " solve " + sourcePath("scenes/cornell_box.obj") +
                                         " --subdivide 60 --estimator rays --samples 256 -o " + (dir / "B.csv").string() + " --objects " +
                                         (dir / "cli.csv").string() + " 2>&1");
    INFO(cli.output);
    REQUIRE(cli.status == 0);
    // The CLI's per-patch CSV, aggregated here by the scene's objects.
    std::istringstream csv(readText(dir / "B.csv"));
    std::string line;
    std::getline(csv, line);
    std::vector<double> area(scene.objects.size(), 0.0), bArea(scene.objects.size(), 0.0), hArea(scene.objects.size(), 0.0),
        hWeight(scene.objects.size(), 0.0), bMax(scene.objects.size(), -1.0);
    PatchId i = 0;
    while (std::getline(csv, line)) {
        std::vector<double> f;
        std::istringstream fields(line);
        for (std::string cell; std::getline(fields, cell, ',');) f.push_back(std::stod(cell));
        REQUIRE(f.size() == 12);
        const std::uint32_t o = scene.patches[i++].object;
        const Rgb E(f[2], f[3], f[4]), rho(f[5], f[6], f[7]), B(f[9], f[10], f[11]);
        area[o] += f[1];
        bArea[o] += f[1] * luminance(B);
        bMax[o] = std::max(bMax[o], luminance(B));
        if ((rho > 0.0).all()) {
            hArea[o] += f[1] * luminance(Rgb((B - E) / rho));
            hWeight[o] += f[1];
        }
    }
    REQUIRE(i == scene.size());
    const std::vector<ObjectSummary> table = app.objectTable();
    std::size_t withPatches = 0;
    for (double a : area) withPatches += a > 0.0;
    REQUIRE(table.size() == withPatches);  // objects without patches are left out
    for (const ObjectSummary& row : table) {
        CAPTURE(row.name);
        const std::size_t o = std::size_t(std::find(scene.objects.begin(), scene.objects.end(), row.name) - scene.objects.begin());
        REQUIRE(o < scene.objects.size());
        CHECK(row.area == doctest::Approx(area[o]).epsilon(1e-7));
        CHECK(row.bMean == doctest::Approx(bArea[o] / area[o]).epsilon(1e-6));
        CHECK(row.bMax == doctest::Approx(bMax[o]).epsilon(1e-6));
        if (hWeight[o] > 0) CHECK(row.hMean == doctest::Approx(hArea[o] / hWeight[o]).epsilon(1e-6));
        else CHECK(std::isnan(row.hMean));
    }
    // The GUI's export and `solve --objects` are the same table.
    CHECK(readText(dir / "gui.csv") == readText(dir / "cli.csv"));
    CHECK(readText(dir / "gui.csv").rfind("object,patches,area (mm^2),B_mean (W/m^2),B_min (W/m^2),B_max (W/m^2),H_patches,"
                                          "H_mean (W/m^2),H_min (W/m^2),H_max (W/m^2)\n", 0) == 0);
}

TEST_CASE("GUI state: before Run the panel knows the rows, the work, the memory bound, and after a first run the time") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/unit_cube.obj")));
    app.settings.formFactors.as<HemisphereOptions>().samples = 384;
    app.settings.formFactors.as<HemisphereOptions>().estimator = Estimator::Rays;
    FormFactorEstimate e = app.formFactorEstimate();
    CHECK(e.rows == 6);
    CHECK_FALSE(e.reusesF);
    CHECK(e.workPerRow == doctest::Approx(384.0));
    CHECK(e.workUnit == "rays");
    CHECK(e.description.find("384 directions") != std::string::npos);
    CHECK(e.memoryBound >= 12.0 * 6 * 6);  // at most every pair, 1.5 x 8 bytes while F is built
    CHECK_FALSE(e.seconds.has_value());     // no rate measured yet
    // What auto picks is in the description.
    app.settings.formFactors.as<HemisphereOptions>().estimator = Estimator::Auto;
    CHECK(app.formFactorEstimate().description.find("analytic") != std::string::npos);

    app.runPipeline();
    runToEnd(app);
    e = app.formFactorEstimate();
    CHECK(e.rows == 0);  // F is current: Run only solves
    CHECK(e.reusesF);
    app.settings.formFactors.as<HemisphereOptions>().samples = 768;
    e = app.formFactorEstimate();
    CHECK(e.rows == 6);  // other settings: every row again
    REQUIRE(e.seconds.has_value());
    CHECK(*e.seconds > 0.0);
}

TEST_CASE("GUI state: Run's time comes from a run of the method on the same mesh, never from another scene or mesh (issue 38 #5)") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    app.settings.formFactors.as<HemisphereOptions>().samples = 384;
    app.settings.formFactors.as<HemisphereOptions>().estimator = Estimator::Rays;
    app.runPipeline();
    runToEnd(app);
    app.settings.formFactors.as<HemisphereOptions>().samples = 768;
    CHECK(app.formFactorEstimate().seconds.has_value());  // the same mesh: its rate
    CHECK(ui::runEstimateText(app.formFactorEstimate()).find("about ") != std::string::npos);
    REQUIRE(app.mesh(200.0, ui::MeshTarget::Scene));
    CHECK_FALSE(app.formFactorEstimate().seconds.has_value());  // a finer mesh: no basis yet
    CHECK(ui::runEstimateText(app.formFactorEstimate()).find("time known after a first run on this mesh") != std::string::npos);
    app.undo();
    REQUIRE(app.loadScene(sourcePath("scenes/unit_cube.obj")));
    CHECK_FALSE(app.formFactorEstimate().seconds.has_value());  // another scene
}

TEST_CASE("GUI state: the analytic estimator's Run line counts shadow rays, not directions (issue 38 #15)") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    app.settings.formFactors.as<HemisphereOptions>().estimator = Estimator::Analytic;
    const FormFactorEstimate e = app.formFactorEstimate();
    CHECK(e.analytic);
    const std::string text = ui::runEstimateText(e);
    CHECK(text.find("Run: 20 rows of analytic factors (20 shadow rays a row, no directions cast)") == 0);
    app.settings.formFactors.as<HemisphereOptions>().estimator = Estimator::Rays;
    CHECK(ui::runEstimateText(app.formFactorEstimate()).find("Run: 20 rows x 3072 rays") == 0);
}

TEST_CASE("GUI state: meshing the selected object previews its patch count, keeps edits, makes F stale, and undoes") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    const Scene source = app.scene();
    app.settings.formFactors.as<HemisphereOptions>().samples = 384;
    app.runPipeline();
    runToEnd(app);
    REQUIRE(app.formFactors() != nullptr);
    REQUIRE(app.formFactors()->size() == source.size());

    // Nothing selected: the selected-object mode says what to do; bad lengths are refused.
    CHECK(app.meshingPreview(50.0, ui::MeshTarget::SelectedObjects).error.find("select the objects") != std::string::npos);
    CHECK_FALSE(app.meshingPreview(-1.0, ui::MeshTarget::Scene).error.empty());
    CHECK(app.meshingPreview(0.01, ui::MeshTarget::Scene).error.find("more than hemirad-gui meshes") != std::string::npos);
    CHECK_FALSE(app.mesh(0.01, ui::MeshTarget::Scene));
    CHECK(app.scene().size() == source.size());

    // An edit on the short block first, then the block meshed: the edit stays on every new patch.
    PatchId block = 0;
    while (source.objects[source.patches[block].object] != "short_block") ++block;
    const std::uint32_t blockObject = source.patches[block].object;
    app.selectionMode = SelectionMode::Object;
    app.select(block, false);
    const std::size_t blockPatches = app.selection().size();
    MaterialEdit edit;
    edit.rho = Rgb(0.2, 0.4, 0.6);
    app.editMaterial(edit);
    runToEnd(app);
    const double oldBlockB = app.radiosity()[block][2];

    const ui::MeshingPreview preview = app.meshingPreview(40.0, ui::MeshTarget::SelectedObjects);
    CHECK(preview.error.empty());
    CHECK(preview.objects == 1);
    REQUIRE(app.mesh(40.0, ui::MeshTarget::SelectedObjects));
    const Scene& meshed = app.scene();
    CHECK(meshed.size() == preview.patches);
    CHECK(meshed.size() > source.size());
    CHECK(meshed.totalArea() == doctest::Approx(source.totalArea()).epsilon(1e-9));
    std::size_t newBlock = 0, others = 0;
    for (const Patch& p : meshed.patches) {
        if (p.object == blockObject) {
            ++newBlock;
            CHECK((p.rho == Rgb(0.2, 0.4, 0.6)).all());
        } else {
            ++others;
        }
    }
    CHECK(others == source.size() - blockPatches);  // the other objects keep their patches
    CHECK(app.meshEdges()[blockObject] == 40.0);
    CHECK(app.selection().size() == newBlock);      // the selection follows the mesh
    CHECK(app.radiosity().size() == meshed.size());
    CHECK(app.radiosity()[app.selection()[0]][2] > 0.0);  // carried over as the warm start
    CHECK(app.formFactorsStale());
    CHECK(app.formFactorRow(0).empty());            // F's ids belong to the old mesh
    CHECK(app.dirty());
    CHECK(logged(app, "meshed 1 object(s) to edges <= 40"));

    // Run computes F for the new mesh: every row, the new size.
    app.runPipeline();
    runToEnd(app);
    REQUIRE(app.formFactors() != nullptr);
    CHECK(app.formFactors()->size() == meshed.size());
    CHECK_FALSE(app.formFactorsStale());
    CHECK(app.formFactorRow(0).size() == meshed.size());
    // The block's mean radiosity stays what the coarse solve gave (a refinement, same physics).
    double area = 0.0, sum = 0.0;
    for (PatchId i = 0; i < meshed.size(); ++i)
        if (meshed.patches[i].object == blockObject && meshed.patches[i].normal.isApprox(source.patches[block].normal, 1e-9)) {
            area += meshed.patches[i].area;
            sum += meshed.patches[i].area * app.radiosity()[i][2];
        }
    CHECK(sum / area == doctest::Approx(oldBlockB).epsilon(0.05));

    // Undo: the old mesh with the edit, and the old F is current again; redo meshes again.
    app.undo();
    runToEnd(app);
    CHECK(app.scene().size() == source.size());
    CHECK(app.scene().geometryHash() == source.geometryHash());
    CHECK((app.scene().patches[block].rho == Rgb(0.2, 0.4, 0.6)).all());
    CHECK(app.meshEdges()[blockObject] == 0.0);
    CHECK(logged(app, "undo meshing"));
    app.redo();
    CHECK(app.scene().size() == preview.patches);
    CHECK_FALSE(app.formFactorsStale());  // the F Run made for this mesh
    app.undo();
    app.undo();  // the material edit
    runToEnd(app);
    CHECK((app.scene().patches[block].rho == source.patches[block].rho).all());
    CHECK_FALSE(app.dirty());

    // The whole scene, then back to the patches as loaded.
    REQUIRE(app.mesh(100.0, ui::MeshTarget::Scene));
    CHECK(app.scene().size() == subdivide(source, 100.0).size());
    CHECK(app.scene().geometryHash() == subdivide(source, 100.0).geometryHash());
    REQUIRE(app.mesh(0.0, ui::MeshTarget::Scene));
    CHECK(app.scene().geometryHash() == source.geometryHash());
    CHECK(logged(app, "back to the patches as loaded"));
}

TEST_CASE("GUI state: coarsening merges patches edited apart, says so, and undo restores them") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    app.autoResolve = false;
    REQUIRE(app.mesh(100.0, ui::MeshTarget::Scene, true));
    CHECK_FALSE(app.dirty());  // part of loading (hemirad-gui --subdivide)
    CHECK_FALSE(app.canUndo());
    const Scene fine = app.scene();
    app.select(0, false);
    MaterialEdit edit;
    edit.emission = Rgb::Constant(5.0);
    app.editMaterial(edit);
    REQUIRE(app.mesh(0.0, ui::MeshTarget::Scene));
    CHECK(logged(app, "edited apart were merged"));
    app.undo();
    CHECK(app.scene().geometryHash() == fine.geometryHash());
    CHECK((app.scene().patches[0].emission == Rgb::Constant(5.0)).all());
    CHECK((app.scene().patches[1].emission == fine.patches[1].emission).all());
}

TEST_CASE("GUI state: the readout of a patch gives B, H = (B - E) / rho, E, rho, s and F_ij from the selected patch") {
    AppState app;
    solvedCube(app);
    const Scene& s = app.scene();
    CHECK_FALSE(app.readout(PatchId(s.size())).has_value());
    const auto r = app.readout(3);
    REQUIRE(r.has_value());
    CHECK(r->patch == 3);
    CHECK(r->object == s.objects[s.patches[3].object]);
    CHECK(r->area == doctest::Approx(1.0));
    CHECK((r->B == app.radiosity()[3]).all());
    for (int c = 0; c < 3; ++c) CHECK(r->H[c] == doctest::Approx((app.radiosity()[3][c] - s.patches[3].emission[c]) / s.patches[3].rho[c]));
    CHECK_FALSE(r->selected.has_value());
    // The floor emits (E = 1) and reflects: H is what it receives from the five walls.
    const auto floor = app.readout(0);
    REQUIRE(floor.has_value());
    double received = 0.0;
    for (PatchId j = 1; j < 6; ++j) received += app.formFactors()->at(0, j) * app.radiosity()[j][0];
    CHECK(floor->H[0] == doctest::Approx(received).epsilon(1e-6));
    // With a patch selected: F_ij from it to the read-out one.
    app.select(0, false);
    const auto toWall = app.readout(3);
    REQUIRE(toWall->selected.has_value());
    CHECK(*toWall->selected == 0);
    REQUIRE(toWall->fromSelected.has_value());
    CHECK(*toWall->fromSelected == app.formFactors()->at(0, 3));
    CHECK(*toWall->fromSelected > 0.15);
    CHECK_FALSE(app.readout(0)->selected.has_value());  // the selected patch itself
}

TEST_CASE("GUI state: the scene's unit comes from the OBJ, is set from the panel, survives meshing and its undo, and is saved") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    CHECK(app.scene().unit == "mm");
    app.setUnit("furlong");  // refused with a message, nothing changes
    CHECK(logged(app, "unknown length unit 'furlong'"));
    CHECK(app.scene().unit == "mm");
    app.setUnit("m");
    CHECK(app.scene().unit == "m");
    CHECK(app.sourceScene().unit == "m");
    REQUIRE(app.mesh(100.0, ui::MeshTarget::Scene));
    CHECK(app.scene().unit == "m");  // meshing starts from the source scene, which has it too
    app.setUnit("cm");
    app.undo();                       // back to the mesh as loaded: the unit is the scene's setting, not the mesh's
    CHECK(app.scene().size() == 20);
    CHECK(app.scene().unit == "cm");
    const auto dir = tempDir("gui-unit");
    REQUIRE(app.saveScene((dir / "cm.obj").string()));
    AppState reopened;
    REQUIRE(reopened.loadScene((dir / "cm.obj").string()));
    CHECK(reopened.scene().unit == "cm");
    reopened.setUnit("");
    REQUIRE(reopened.saveScene((dir / "none.obj").string()));
    CHECK(readText(dir / "none.obj").find("# hemirad unit") == std::string::npos);
}
