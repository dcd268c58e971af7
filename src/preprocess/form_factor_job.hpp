// Running a back end over the rows a solve needs, with progress, cancellation, timing and diagnostics.
#pragma once

#include "engine/emitted_pairs.hpp"
#include "preprocess/backend_registry.hpp"
#include "preprocess/form_factor_backend.hpp"

#include <atomic>
#include <functional>

namespace hemirad {

struct FormFactorRun {
    FormFactors F;
    FormFactorStats stats;
    RayCounts counts;
    double prepareSeconds = 0;   ///< acceleration structures (BVH)
    double computeSeconds = 0;   ///< rows
    double assembleSeconds = 0;  ///< F from the rows: CSR, and each pair from its emitting row
    double statsSeconds = 0;     ///< diagnostics (row sums, reciprocity)
    std::size_t rowsComputed = 0, rowsSkipped = 0;
    std::map<std::string, double> stageSeconds;  ///< back-end stages, thread-seconds (see FormFactorBuilder)
    std::string device;                          ///< FormFactorBackend::device() (rank 0's under MPI)
    EmittedPairsReport emittedPairs;             ///< pairs whose receiver entry came from the emitting row
};

/// (rows done, rows total, seconds so far); called about 10 times a second from the calling thread.
using ProgressCallback = std::function<void(std::size_t, std::size_t, double)>;

/// Rows a solve needs: patches with rho > 0 in some channel (B = E for the others); every row with allRows.
std::vector<PatchId> neededRows(const Scene& scene, bool allRows);

/// An upper bound of the bytes F for `rows` takes while it is built (each nonzero twice, 8 bytes each;
/// at most one nonzero per ray or pixel and chain step, and per patch), with every worker thread's
/// scratch (BackendDescriptor::bytesPerThread times settings.common.threads). No row is computed.
double formFactorMemoryBound(const Scene& scene, const MethodSettings& settings, std::size_t rows);

/// F's size for `rows`: the cheap bound (formFactorMemoryBound) when it is within `budget` bytes,
/// else 64 sample rows spread over the list computed and extrapolated (their nonzeros and time).
MemoryPrediction predictFormFactorMemory(const Scene& scene, const MethodSettings& settings, const std::vector<PatchId>& rows,
                                         double budget);

/// The settings to run `rows` with: the back end's choices left to the scene and the machine made
/// (BackendDescriptor::resolve, e.g. --estimator auto: the exact estimator wherever its F fits in
/// 0.8 x `available` bytes, 0 = the machine's available memory), and a note saying what was chosen
/// and why ("" when nothing was left open).
MethodSettings resolveSettings(const Scene& scene, const MethodSettings& settings, const std::vector<PatchId>& rows,
                               std::string& note, std::size_t available = 0);

/// Refuses (hemirad::Error with the estimate and how to proceed) when F for `rows` may not fit in
/// `available` bytes (0 = the machine's available memory). A cheap upper bound first (rays per
/// row, or N, per row); only if that exceeds the budget, 64 sample rows are computed and their
/// nonzeros extrapolated. Returns the estimate in bytes.
std::size_t checkFormFactorMemory(const Scene& scene, const MethodSettings& settings, const std::vector<PatchId>& rows,
                                  std::size_t available = 0);

/// Computes `rows` of F for `scene` with the named back end; F carries the scene hash and
/// parameters. `cancel` (optional) aborts between rows: then hemirad::Error("cancelled") is thrown.
FormFactorRun computeFormFactors(const Scene& scene, const MethodSettings& settings, const std::vector<PatchId>& rows,
                                 const ProgressCallback& progress = {}, const std::atomic<bool>* cancel = nullptr);

/// F of `scene` that holds no computed row (a scene whose patches are all black needs none: B = E),
/// recorded as computeFormFactors records F, without preparing the back end: N x N, every row marked
/// not computed, the scene hash, the method and its settings. Files of it read back and serve --ff.
FormFactors formFactorsWithoutRows(const Scene& scene, const MethodSettings& settings);

/// Rays (or pixels) one row of `settings` costs on `scene` (the back end's estimate).
double expectedWorkPerRow(const Scene& scene, const MethodSettings& settings);

}  // namespace hemirad
