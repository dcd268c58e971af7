// The radiosity pipeline shared by every front end (hemirad, hemirad-gui, and later Python and the
// MPI driver): load -> subdivide -> needed rows -> F (reuse, merge, memory check, reciprocity and
// normalisation policy) -> solve -> vertex values. Front ends choose how to show its events.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/scene.hpp"
#include "engine/scene_loader.hpp"
#include "solve/solver.hpp"
#include "engine/warnings.hpp"
#include "preprocess/backend_registry.hpp"
#include "preprocess/form_factor_job.hpp"

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hemirad {

/// How F is made and post-processed.
struct FormFactorPolicy {
    MethodSettings backend = defaultSettings(defaultBackend().name);  ///< the back end and its options
    bool allRows = false;             ///< also rows of black patches (skipped by default: B = E there)
    bool enforceReciprocity = false;  ///< A_i F_ij = A_j F_ji by the pair's area-weighted mean
    bool normalizeRows = false;       ///< every row to sum 1 (closed scenes without mirrors)
    double dropBelow = 0.0;           ///< pairs with both entries below this dropped, rows rebalanced (0: none)
    bool memoryCheck = true;          ///< refuse an F that would not fit the available memory
    /// Keep FormFactorUpdate::stats current after merging and post-processing (a pass over F and its
    /// transpose: the GUI shows them; the CLI reports only what it computed).
    bool statistics = false;
};

/// What a front end hears from the pipeline; every member may be empty. Called on the thread that
/// runs the pipeline (progress about 10 times a second).
struct PipelineEvents {
    std::function<void(const std::string&)> message;                 ///< one line for the console or log
    std::function<void(const std::string& stage, double seconds)> timing;
    /// Progress of a form-factor computation: (label, work per row, its unit) -> callback.
    std::function<ProgressCallback(const std::string&, double, const std::string&)> progress;
    /// After rows were computed (before merging), with the run's counts and statistics.
    std::function<void(const FormFactorRun&, const Scene&, const MethodSettings&)> formFactorsComputed;
    /// After a post-process changed F (reciprocity): the new statistics.
    std::function<void(const FormFactorStats&, std::size_t memoryBytes)> formFactorsChanged;
    const std::atomic<bool>* cancel = nullptr;  ///< set to stop between rows ("form factors: cancelled")
};

/// The result of bringing F up to date.
struct FormFactorUpdate {
    FormFactors F;
    std::size_t rowsComputed = 0;  ///< rows the back end computed (0: F was current)
    bool changed = false;          ///< rows added or post-processing applied (a stored F is out of date)
    /// Of the returned F: always after a fresh computation, else with FormFactorPolicy::statistics.
    std::optional<FormFactorStats> stats;
};

/// Takes the rows `added` computed into `current` (a reused F): the merged F allows the larger row sum
/// of the two computations (e.g. a deeper mirror chain) and records "rows_added" (`rows` rows, the
/// back end's run description).
void mergeAddedRows(FormFactors& current, const FormFactors& added, std::size_t rows, const Scene& scene,
                    const MethodSettings& method);

/// What a front end says when a scene needs no row of F (formFactorsWithoutRows).
inline constexpr const char* kNoRowsNeeded =
    "form factors: no row needed: every patch is black (rho = 0, so B = E); F holds none (--all-rows computes them)";

/// The post-processing of F a run applies (FormFactorPolicy's steps).
struct PostProcessing {
    double dropBelow = 0.0;           ///< drop pairs below this and close (0: not)
    bool enforceReciprocity = false;  ///< close without dropping (when dropBelow is 0)
    bool normalizeRows = false;       ///< then rows to sum 1
    bool any() const { return dropBelow > 0.0 || enforceReciprocity || normalizeRows; }
};

/// The post-processing `policy` asks of F less what F's parameters record as done (issue 35 #2: a
/// stored F was dropped again on every reuse): no drop when "sparsified" names the same EPS (a drop
/// ends with the closure), no closure when "reciprocity" is recorded, no normalisation when "rows"
/// says normalised and nothing before it changes F.
PostProcessing pendingPostProcessing(const FormFactorPolicy& policy, const FormFactors& F);

/// F's record of its post-processing for people ("pairs below 0.01 dropped ...; reciprocity
/// enforced, ...; rows normalised to sum 1"), "" when it has none.
std::string recordedPostProcessing(const FormFactors& F);

/// The rule for an F kept in a file between runs (--ff), one for the pipeline and the MPI driver:
///   - a new F (no file yet, or --recompute-ff) is stored once post-processed; its parameters
///     record each step (pendingPostProcessing);
///   - a reused F gets only the steps it does not record, and its file stays as it is, except when
///     rows it lacked were computed: then it is stored with them, before any step;
///   - a reused F that records post-processing and lacks rows is computed again whole: its entries
///     were changed by the steps, and new rows cannot join them.
class StoredFormFactorRule {
public:
    /// F computed whole: stored after post-processing when there is a file (`path` not empty).
    static StoredFormFactorRule computed(const std::string& path);
    /// The F read from `path` (already checked against the scene, checkStoredFormFactors), holding
    /// `rows` computed rows and lacking `missing` rows the run needs.
    static StoredFormFactorRule reused(const FormFactors& F, std::size_t rows, std::size_t missing, const std::string& path);

    /// Whether the file's F is used (else F is computed whole and stored).
    bool reuse() const { return m_reuse; }
    /// What the front end tells about the file (reused, rows to compute, its post-processing, or why
    /// it is computed again).
    const std::vector<std::string>& lines() const { return m_lines; }
    /// Store F once its missing rows are added, before post-processing.
    bool storeBeforePostProcessing(bool rowsAdded) const { return m_reuse && rowsAdded; }
    /// Store F after post-processing.
    bool storeAfterPostProcessing() const { return m_store && !m_reuse; }

private:
    bool m_reuse = false, m_store = false;
    std::vector<std::string> m_lines;
};

/// Checks an F read from `path` for `scene` and `settings`, in one process and on MPI ranks: the
/// scene hash and size (checkFormFactorsMatch; a file without a hash is counted in `warnings` as
/// unverified), then the form-factor settings it records against `settings` by the GUI's rule
/// (sameFormFactorSettings; issue 35 #22: an F of --max-depth 0 --samples 512 was reused for
/// --max-depth 8 --samples 4096 without a word). Other settings throw hemirad::Error naming the
/// difference and the ways on (--recompute-ff, --reuse-ff-anyway); with `otherSettings`
/// (--reuse-ff-anyway) they are a warning. A file that records no settings (older files, foreign
/// .mtx) is counted in `warnings`.
void checkStoredFormFactors(const FormFactors& F, const Scene& scene, const MethodSettings& settings, bool otherSettings,
                            const std::string& path, Warnings& warnings);

/// Where F is kept between runs (--ff).
struct StoredFormFactors {
    std::string path;        ///< "" = none
    bool recompute = false;  ///< recompute F and overwrite the file
    bool otherSettings = false;  ///< reuse the file although it records other settings (a warning)
    /// Store it as a shard manifest with its shard (form_factor_shards.hpp); a manifest already at
    /// `path` stays one.
    bool sharded = false;
};

class RadiosityPipeline {
public:
    RadiosityPipeline(FormFactorPolicy policy, PipelineEvents events);

    const FormFactorPolicy& policy() const { return m_policy; }

    /// Loads a scene (loadScene: OBJ + MTL or STL, materials by object name from `loading`) and
    /// subdivides it to edges <= `subdivide` (0 = not at all). Throws hemirad::Error.
    Scene load(const std::string& path, double subdivide, Warnings& warnings, const SceneLoadOptions& loading = {}) const;

    /// Rows the solve of `scene` needs (all with allRows) that `current` lacks (all without it).
    std::vector<PatchId> missingRows(const Scene& scene, const FormFactors* current) const;

    /// Checks what can be checked before any row is computed: the policy against the scene (row
    /// normalisation with mirrors), the back end's options. Throws hemirad::Error.
    void checkBeforeComputing(const Scene& scene) const;

    /// Brings F up to date for `scene`: computes the missing rows (memory check first), merges them
    /// into `current` (taken over; empty = none), then applies the post-processing F does not record
    /// (pendingPostProcessing). A `current` that records post-processing and lacks rows is computed
    /// again whole (see StoredFormFactorRule).
    /// `current` must belong to `scene` (checkFormFactorsMatch). Throws hemirad::Error.
    FormFactorUpdate updateFormFactors(const Scene& scene, FormFactors current = {}) const;

    /// updateFormFactors with a stored F: reuses `file.path` when it exists and belongs to the scene
    /// and the policy's settings (unless `file.recompute`; checkStoredFormFactors), and stores F there as
    /// StoredFormFactorRule says. Files without a Hemirad scene hash (foreign .mtx) are checked by
    /// size only and counted in `warnings`.
    FormFactorUpdate formFactorsWithFile(const Scene& scene, const StoredFormFactors& file, Warnings& warnings) const;

    /// Solves (I - R F) B = E per channel; `initial` warm-starts iterative solvers. "auto" picks the
    /// solver for the scene (chooseSolver). Throws hemirad::Error unless solver.allowUnconverged.
    Radiosity solve(const Scene& scene, const FormFactors& F, SolverOptions solver,
                    const std::vector<Rgb>* initial = nullptr) const;

private:
    /// The missing rows merged into `current` (no post-processing).
    FormFactorUpdate computeMissingRows(const Scene& scene, FormFactors current) const;
    /// Reciprocity (or the drop) and normalisation as the policy asks, less what F records.
    void postProcess(const Scene& scene, FormFactorUpdate& update) const;
    /// Recomputes update.stats (timed as "F diagnostics") when the policy keeps statistics or `needed`.
    void refreshStats(const Scene& scene, FormFactorUpdate& update, bool needed = false) const;
    void message(const std::string& text) const;
    void timing(const std::string& stage, double seconds) const;

    FormFactorPolicy m_policy;
    PipelineEvents m_events;
};

}  // namespace hemirad
