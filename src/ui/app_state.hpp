// hemirad-gui's application state and the actions that change it. No window, no GL: the event loop
// turns input into these calls, ImGui panels only read the state and call actions, and the tests
// drive it headless. Long work (form factors, solves) runs on a worker thread.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/object_table.hpp"
#include "engine/scene.hpp"
#include "engine/scene_loader.hpp"
#include "render/false_colour.hpp"
#include "solve/solver.hpp"
#include "preprocess/backend_registry.hpp"
#include "ui/up_axis.hpp"
#include "ui/sun_sky_setup.hpp"
#include "ui/thermal_setup.hpp"

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace hemirad::ui {

enum class Layer { Radiosity, PatchId, Emission, Reflectance, Specular, FormFactorRow, FalseColour };

/// The false-colour view's settings (as `hemirad render --false-color`).
struct FalseColourSettings {
    FalseColourQuantity quantity = FalseColourQuantity::Irradiance;
    FalseColourScale scale = FalseColourScale::Linear;
    bool automatic = true;     ///< the values' extremes, else [min, max]
    double min = 0.0, max = 1.0;
    /// A thermal quantity instead of `quantity`: the last thermal run's T (K) or q (W/m^2, net leaving).
    enum class Thermal { None, Temperature, HeatFlux };
    Thermal thermal = Thermal::None;
    /// A quantity of the last Sky and sun run instead (it takes precedence over `thermal`).
    enum class Sun { None, SunlitFraction, SkyView, DirectSun, DirectSky, Reflected, Total, Absorbed };
    Sun sun = Sun::None;
};

/// The Sky and sun quantities' names as hemirad-gui --false-color takes them ("sunlit_fraction",
/// "sky_view_factor", "direct_sun", "direct_sky", "reflected_solar", "total_solar", "absorbed_solar"),
/// and back (none for another name).
const char* sunQuantityName(FalseColourSettings::Sun quantity);
std::optional<FalseColourSettings::Sun> parseSunQuantity(const std::string& name);

/// The false-colour map of the current radiosity: its range and each patch's colour.
struct FalseColourView {
    FalseColourRange range;
    std::vector<std::uint32_t> colours;  ///< per patch 0xRRGGBB (falseColourOf: the no-data grey where none)
    bool noData = false;                 ///< some patch has no value (all of them where `error` is set)
    std::string error;                   ///< why no map can be shown (then every patch is no-data grey)
};
enum class SelectionMode { Patch, Object };

struct PipelineSettings {
    /// The form-factor back end and its options (the registry's default back end first).
    MethodSettings formFactors = defaultSettings(defaultBackend().name);
    SolverOptions solver;
};

/// A material change for the selected patches; unset fields stay as they are.
struct MaterialEdit {
    std::optional<Rgb> emission;  ///< E, W/m^2
    std::optional<Rgb> rho;       ///< diffuse reflectance 0..1
    std::optional<double> specular;
};

/// What Run would compute, shown before it is pressed.
struct FormFactorEstimate {
    std::size_t rows = 0;           ///< rows Run computes (0: it reuses F and only solves)
    bool reusesF = false;
    double workPerRow = 0.0;        ///< rays or pixels (workUnit) per row
    std::string workUnit;
    bool analytic = false;          ///< analytic factors: the rays are shadow rays, no directions cast
    std::string description;        ///< the back end's run description (what "auto" picks, e.g.)
    double memoryBound = 0.0;       ///< bytes F takes at most while it is built
    /// From the rate of the last run of this method on this mesh; none before one (a rate measured on
    /// another scene or mesh says little here: fixed costs dominate small scenes).
    std::optional<double> seconds;
};

/// What the Selection panel shows for a selection of one or many patches.
struct SelectionSummary {
    std::size_t patches = 0, objects = 0;
    double area = 0.0;                   ///< total, scene units squared
    Rgb emission = Rgb::Zero();          ///< area-weighted means
    Rgb rho = Rgb::Zero();
    double specular = 0.0;
    Rgb radiosity = Rgb::Zero();
    Rgb power = Rgb::Zero();             ///< sum of A B: the power leaving the selection
};

/// What the meshing panel would make (subdivide per object), shown before Apply.
enum class MeshTarget { Scene, SelectedObjects };
struct MeshingPreview {
    std::size_t patches = 0;       ///< the scene's patch count after meshing
    std::size_t objects = 0;       ///< objects given the new edge length
    std::string error;             ///< why it cannot be applied (then the counts are 0)
};
/// hemirad-gui meshes interactively up to this many patches; larger meshes belong to the CLI.
inline constexpr std::size_t kMaxGuiPatches = 2'000'000;

/// The status bar's readout of one patch (the one under the cursor, else the selected one).
struct PatchReadout {
    PatchId patch = 0;
    std::string object;
    int sourceLine = 0;
    double area = 0.0;                    ///< scene units squared
    Rgb B = Rgb::Zero();                  ///< radiosity, W/m^2
    Rgb H = Rgb::Zero();                  ///< irradiance (B - E) / rho, W/m^2; NaN in a channel with rho 0
    Rgb emission = Rgb::Zero(), rho = Rgb::Zero();
    double specular = 0.0;
    /// F_ij from the (first) selected patch i to this one, when F holds row i and i is not this patch.
    std::optional<PatchId> selected;
    std::optional<double> fromSelected;
};

struct LogEntry {
    double seconds;  ///< since the application started
    std::string text;
    bool error;
};

/// What the worker thread is doing, for the progress bar.
struct JobStatus {
    bool running = false;
    std::string stage;      ///< "form factors", "solve"
    double progress = 0.0;  ///< 0..1 within the stage
    double elapsed = 0.0;
    bool cancelling = false;  ///< Cancel was pressed; the job is stopping
    int workers = 0;          ///< worker threads it computes with
};

/// Worker threads for a job: `requested` when > 0; for 0 (all cores) one fewer than the cores, at
/// least 1, so that the window keeps a core to draw and to take Cancel (issue 38 #4).
int jobWorkers(int requested);
class ThermalJob;
class SunSkyJob;
class WorkerJob;

class AppState {
public:
    AppState();
    ~AppState();
    AppState(const AppState&) = delete;
    AppState& operator=(const AppState&) = delete;

    // --- State (read by panels and the viewer) -------------------------------------------------
    bool hasScene() const { return m_scene != nullptr; }
    const Scene& scene() const { return *m_scene; }
    const std::string& scenePath() const { return m_scenePath; }
    /// Changes with every scene loaded or set (not with edits or meshing).
    std::uint64_t sceneId() const { return m_sceneId; }
    /// The scene as loaded, before meshing: what the meshing panel subdivides.
    const Scene& sourceScene() const { return *m_source; }
    /// The maximum edge length each object was meshed to (scene units; 0 = as loaded).
    const std::vector<double>& meshEdges() const { return m_meshEdges; }
    /// Bumped whenever geometry, materials or results change: the viewer re-uploads.
    std::uint64_t revision() const { return m_revision; }

    /// The current F (null before the first run); shared with the worker, never modified in place.
    const FormFactors* formFactors() const { return m_F.get(); }
    const std::optional<FormFactorStats>& formFactorStats() const { return m_stats; }
    /// F was computed for another geometry or mirror setup: recompute before solving.
    bool formFactorsStale() const { return m_fStale; }
    /// Radiosity does not reflect the current materials (re-solve pending).
    bool radiosityStale() const { return m_bStale; }
    const std::vector<Rgb>& radiosity() const { return m_B; }
    const std::vector<SolveReport>& solveReports() const { return m_reports; }
    /// (stage, seconds) of the last pipeline run.
    const std::vector<std::pair<std::string, double>>& timings() const { return m_timings; }

    const std::vector<PatchId>& selection() const { return m_selection; }
    SelectionMode selectionMode = SelectionMode::Patch;
    bool isSelected(PatchId id) const;
    /// What the status bar shows for patch j; none when there is no such patch.
    std::optional<PatchReadout> readout(PatchId j) const;
    /// Count, objects, total area and area-weighted means of the selection (empty: all zero).
    SelectionSummary selectionSummary() const;

    /// Unsaved material edits: the undo history is not where it was at the last load or save (an
    /// undo back to the saved values is clean again). Thermal edits are not saved with the scene and
    /// do not count.
    bool dirty() const;
    /// Bumped by every material edit, undo and redo (the material editor reloads its values).
    std::uint64_t materialsRevision() const { return m_materialsRevision; }
    bool canUndo() const { return !m_undo.empty(); }
    bool canRedo() const { return !m_redo.empty(); }

    PipelineSettings settings;
    /// hemirad-gui --materials: an MTL library assigned by object name to every scene loaded ("" none).
    SceneLoadOptions loading;
    /// Re-solve by itself after material edits (warm start, F kept).
    bool autoResolve = true;

    // View settings (used by the viewer; kept here so tests and panels share them).
    Layer layer = Layer::Radiosity;
    bool gouraud = true;
    bool autoExposure = true;
    double exposure = 1.0;
    bool showReflections = true;
    double creaseDegrees = 45.0;
    FalseColourSettings falseColour;
    /// The false-colour map of the current radiosity with `falseColour` (as hemirad render's), or of
    /// the last thermal run's T or q.
    FalseColourView falseColourView() const;
    /// The legend's title and unit for `falseColour` ("temperature T", "K").
    std::pair<std::string, std::string> falseColourLegend() const;

    const std::vector<LogEntry>& log() const { return m_log; }
    void info(const std::string& text) { addLog(text, false); }
    void error(const std::string& text) { addLog(text, true); }

    JobStatus job() const;

    // --- Actions -----------------------------------------------------------------------------
    /// Loads an OBJ (+MTL) or an STL with `loading`; on error the current scene stays and the error
    /// is logged. Returns success.
    bool loadScene(const std::string& path);
    /// Replaces the scene (tests, generators); F and radiosity are dropped. It becomes the source
    /// the meshing panel subdivides.
    void setScene(Scene scene, const std::string& path);
    bool saveScene(const std::string& path);
    /// The scene's length unit ("" not stated, or one of lengthUnits()): how lengths and areas are
    /// labelled, and power (sum A B) in W where it is known; written by the next save. Not an edit
    /// of the results (nothing is recomputed) and not undone.
    void setUnit(const std::string& unit);
    /// The scene's up axis (1 y, 2 z; upAxisOf) and where it came from.
    int upAxis() const { return hasScene() ? upAxisOf(*m_scene) : 1; }
    UpAxisSource upAxisSource() const { return m_upSource; }
    /// The Scene panel's choice of up axis (1 y, 2 z): stated in the scene (written by the next save)
    /// and remembered for its file in `upAxes`. Not an edit of the results and not undone.
    void setUpAxis(int axis);
    /// The up axes chosen per scene file; a scene loaded takes the one chosen for its file.
    UpAxisMemory upAxes;

    void select(PatchId id, bool additive);
    void clearSelection();
    /// Applies an edit to the selection (undoable). Specular changes invalidate F; emission and
    /// diffuse changes only need a re-solve, started at once when autoResolve is on. An edit out of
    /// range, or one that would make rho + s > 1, is refused and logged as an error: returns false.
    bool editMaterial(const MaterialEdit& edit);
    void undo();
    void redo();

    /// The patch count meshing would give: the objects of `target` subdivided from the scene as
    /// loaded until no edge exceeds maxEdge (scene units; 0 = back to the patches as loaded).
    MeshingPreview meshingPreview(double maxEdge, MeshTarget target) const;
    /// Meshes as meshingPreview says. Material edits are kept (each new patch takes the values of the
    /// patch that covered its centroid), so are the selection and, as a warm start, radiosity; F
    /// becomes stale. Undoable unless `asLoaded` (hemirad-gui --subdivide: part of loading, the
    /// scene stays unedited). Returns success; errors are logged.
    bool mesh(double maxEdge, MeshTarget target, bool asLoaded = false);

    /// Computes F if it is missing, stale, made with other settings than `settings.formFactors`
    /// (method, its options, mirror depth) or lacks rows the materials now need, then solves.
    void runPipeline();
    /// Computes the whole F again with the current settings, even when it is current, then solves.
    void recomputeFormFactors();
    /// True when F was made with the current form-factor settings (an imported F: with those the
    /// panel had when it was imported).
    bool formFactorsMatchSettings() const;
    /// Rows, work, the memory bound and (after a first run of the method) the time Run would take.
    FormFactorEstimate formFactorEstimate() const;
    /// Solves with the current F (warm start from the last radiosity), first computing the rows the
    /// materials need that it lacks (runPipeline).
    void resolve();
    /// Asks the running job to stop (it does between rows, and between solver sweeps); nothing
    /// without one. Never starts work.
    void cancel();
    /// Called once a frame: applies a finished job's results. Returns true if something changed.
    bool poll();
    /// Blocks until the worker is idle (tests, --exit).
    void wait();

    /// Imports F (checked against the scene) and, with autoResolve, solves with it at once.
    bool importFormFactors(const std::string& path);
    bool exportFormFactors(const std::string& path);
    bool exportPly(const std::string& path);
    /// Per object: patches, area, B and H (as `hemirad solve --objects`); exported as CSV.
    std::vector<ObjectSummary> objectTable() const;
    bool exportObjectTable(const std::string& path);

    // --- Thermal (docs/thermal.md; app_state_thermal.cpp) ----------------------------------------
    /// The thermal files as loaded and the per-object edits over them (reset with every scene).
    const ThermalSetup& thermalSetup() const { return m_thermal; }
    /// Bumped by every thermal file loaded, edit and refused edit: the panel reloads its fields.
    std::uint64_t thermalRevision() const { return m_thermalRevision; }
    /// The last thermal file's error as the library threw it (file:line), "" after a good load.
    const std::string& thermalLoadError() const { return m_thermalLoadError; }
    /// Reads a properties (boundary-condition) TOML and checks it against the scene; on error nothing
    /// changes and the error is logged. A properties file's specular reflectances become the scene's
    /// s (an undoable edit; F must be recomputed). Loading drops the edits of what the file gives.
    bool loadThermalProperties(const std::string& path);
    bool loadThermalConditions(const std::string& path);
    /// Per-object edits over the files; a value the library refuses (eps + s > 1, T < 0 K, ...) is
    /// logged and changes nothing: returns false.
    bool setObjectEmissivity(std::uint32_t object, double emissivity);
    bool setObjectCondition(std::uint32_t object, const ObjectCondition& condition);
    /// The environment's temperature (K), or none: a closed scene.
    bool setThermalEnvironment(std::optional<double> kelvin);
    /// The Scene panel's rows and the environment in effect; `error` says why there are none.
    std::vector<ObjectThermalRow> thermalObjects(std::optional<double>& environment, std::string& error) const;
    /// Solves the thermal model on the current F (computing every row it lacks, or F whole when it is
    /// stale or made with other settings) on the worker thread; cancel() stops it.
    void runThermal();
    /// The last thermal run's result for the current mesh (null before one, or after meshing).
    const ThermalResult* thermalResult() const;
    /// The result was made with other materials, geometry or thermal inputs than the current ones.
    bool thermalStale() const;
    /// The object exchange table (W) as CSV, units in the header (as hemirad thermal --exchange).
    bool exportThermalExchange(const std::string& path);
    /// The last thermal run's radiative conductors per object (and to the environment), GR in m^2, in
    /// the format of the path's extension as hemirad thermal --conductors writes them: .csv, .mtx,
    /// .esatan or .cnd (an ESATAN-TMS $CONDUCTORS block), .sinda or .inp (SINDA/FLUINT). Another
    /// extension, or no result, is logged and writes nothing.
    bool exportThermalConductors(const std::string& path);

    // --- Sky and sun (app_state_sun_sky.cpp; src/environment) ---------------------------------------
    /// The section's inputs (time and place or a direction, DNI, DHI, the sky); read when Run starts.
    SunSkySetup sunSky;
    /// One hour of sun and sky on the current F (computing every row it lacks, or F whole when it is
    /// stale or made with other settings), the sky view factors or the sky model's coefficients, on the
    /// worker thread; cancel() stops it. A bad input (a time that does not parse) is logged.
    void runSunSky();
    /// The last run's result for the current mesh (null before one, or after meshing).
    const SunSkyResult* sunSkyResult() const;
    /// The result was made with other geometry or materials than the current ones.
    bool sunSkyStale() const;
    /// Per patch, a quantity of the last result (the false-colour map's values); throws hemirad::Error
    /// saying what to run when there is none (or, for the sky view factor, when a sky model ran).
    std::vector<double> sunSkyValues(FalseColourSettings::Sun quantity) const;
    /// The legend's title and unit of a Sky and sun quantity.
    static std::pair<std::string, std::string> sunSkyLegend(FalseColourSettings::Sun quantity);

    /// Per-patch value of row `i` of F (the inspector's layer); empty when F or the row is missing.
    std::vector<float> formFactorRow(PatchId i) const;
    /// Per-corner radiosity for Gouraud shading (cached per revision).
    const std::vector<Rgb>& cornerRadiosity();

private:
    struct Job;
    struct Snapshot {
        std::vector<Rgb> emission, rho;
        std::vector<double> specular;
    };
    void addLog(const std::string& text, bool isError);
    void startJob(bool computeF, std::shared_ptr<const FormFactors> F);
    Snapshot snapshot(const std::vector<PatchId>& ids) const;
    void restore(const std::vector<PatchId>& ids, const Snapshot& s);
    void materialsChanged(bool specularChanged);
    /// Re-solves with the current F (resolve), or once the running job has finished.
    void refreshRadiosity();
    void bump() { ++m_revision; }

    std::unique_ptr<Scene> m_scene;
    std::unique_ptr<const Scene> m_source;  ///< the scene as loaded (meshing subdivides it)
    std::vector<double> m_meshEdges;        ///< per object, 0 = as loaded
    std::uint64_t m_sceneId = 0;
    std::string m_scenePath;
    UpAxisSource m_upSource = UpAxisSource::Guessed;
    std::uint64_t m_revision = 1;
    std::shared_ptr<const FormFactors> m_F;
    std::optional<MethodSettings> m_fSettings;  ///< the settings m_F was made with
    /// Measured rays (pixels) per second, by method and mesh (m_meshRevision).
    std::map<std::pair<std::string, std::uint64_t>, double> m_workPerSecond;
    std::uint64_t m_meshRevision = 0;  ///< bumped by every scene set and every meshing
    std::optional<FormFactorStats> m_stats;
    std::uint64_t m_fGeometryHash = 0;
    std::uint64_t m_materialsRevision = 0;  ///< bumped by every material edit
    bool m_pendingResolve = false;          ///< an edit arrived while a job ran
    bool m_fStale = false, m_bStale = false;
    std::optional<std::size_t> m_cleanDepth = 0;  ///< undo depth of the saved state; none once unreachable
    std::vector<Rgb> m_B;
    std::vector<SolveReport> m_reports;
    std::vector<std::pair<std::string, double>> m_timings;
    std::vector<PatchId> m_selection;
    /// A mesh and the edge lengths it was made with (whole scenes: meshing renumbers patches).
    struct Mesh {
        Scene scene;
        std::vector<double> edges;
    };
    /// A material edit of `ids`, a meshing step (meshBefore, meshAfter set), and/or a thermal edit
    /// (thermalBefore, thermalAfter set: the thermal files and per-object edits before and after).
    struct UndoStep {
        std::vector<PatchId> ids;
        Snapshot before, after;
        std::shared_ptr<const Mesh> meshBefore, meshAfter;
        std::shared_ptr<const ThermalSetup> thermalBefore, thermalAfter;
        /// Whether it changes what File > Save writes (materials or the mesh), not only thermal inputs.
        bool changesScene() const { return !ids.empty() || meshBefore || meshAfter; }
    };
    /// Records a new step (the redo history goes).
    void pushUndo(UndoStep step);
    /// Records the thermal setup's change from `before` to m_thermal as an undoable step.
    void pushThermalUndo(const ThermalSetup& before);
    /// Moves the newest step of `from` to `to`, applying its before (undo) or after (redo) side.
    void replay(std::vector<UndoStep>& from, std::vector<UndoStep>& to, bool undoing);
    /// Makes `next` the current mesh, carrying radiosity and the selection over.
    void applyMesh(const Mesh& next);
    /// The edge lengths per object meshing with (maxEdge, target) asks for.
    std::vector<double> meshEdgesFor(double maxEdge, MeshTarget target) const;
    std::vector<UndoStep> m_undo, m_redo;
    std::vector<LogEntry> m_log;
    std::chrono::steady_clock::time_point m_start;
    std::vector<Rgb> m_corner;
    std::uint64_t m_cornerRevision = 0;
    std::unique_ptr<Job> m_job;
    std::optional<int> m_framesSinceCancel;  ///< poll() calls since cancel(), while the job stops
    void pollThermal();
    /// A finished thermal or sky-and-sun job: joins it, logs its messages, and adopts its F (every
    /// row) when made for the current geometry. False (logged) when it failed or was cancelled.
    bool finishWorkerJob(WorkerJob& job, const std::string& what);
    /// A job (radiosity or thermal) is running.
    bool busy() const;
    ThermalSetup m_thermal;
    std::uint64_t m_thermalRevision = 0;
    std::uint64_t m_thermalSetupRevision = 0;  ///< bumped by accepted thermal inputs only (staleness)
    std::pair<std::uint64_t, std::uint64_t> m_thermalJobRevisions;  ///< materials, setup of the running job
    std::string m_thermalLoadError;
    std::optional<ThermalResult> m_thermalResult;
    std::unique_ptr<ThermalJob> m_thermalJob;
    void pollSunSky();
    std::unique_ptr<SunSkyJob> m_sunSkyJob;
    std::uint64_t m_sunSkyJobMaterials = 0;
    std::optional<SunSkyResult> m_sunSkyResult;
};

}  // namespace hemirad::ui
