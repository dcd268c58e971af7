// The form-factor back-end interface (hemisphere rays, later the hemicube), its options and row builder.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/scene.hpp"

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace hemirad {

struct BackendOptions {
    std::uint32_t samples = 3072;  ///< directions per origin (Beckers cells), >= 1
    std::uint32_t origins = 1;     ///< ray origins per patch, stratified over its area, >= 1
    std::uint32_t maxDepth = 8;    ///< mirror bounces followed per ray
    double minWeight = 1e-4;       ///< a mirror chain stops below this weight
    int threads = 0;               ///< worker threads; 0 = all cores
    std::uint64_t seed = 1;        ///< origin jitter and pattern rotation
    bool fixedDirections = false;  ///< one pattern orientation for every origin (the reference system's way)
    bool jitter = false;           ///< a random direction inside each Beckers cell (unbiased; for references)
    /// Hemisphere direct factors: "rays" (each ray deposits 1/N on the patch it hits), "analytic"
    /// (Lambert's exact point-to-polygon factor for every patch a shadow ray finds visible) or
    /// "auto": analytic when the scene has at most kAnalyticRaysFactor x samples patches.
    std::string estimator = "auto";
    // Hemicube back end.
    std::uint32_t resolution = 128;  ///< top face R x R pixels, sides R x R/2 (R even)
    std::string reduce = "cpu";      ///< where pixels are summed into rows: "cpu" or "gpu"
    std::string gl = "auto";         ///< context API: "auto" (EGL, then OSMesa), "egl", "osmesa"
    bool parentPolygons = true;      ///< draw subdivided parents whole, patch ids from their grids
    std::string mirrors = "portals"; ///< hemicube mirrors: "portals" (stencil, reflected views) or "rays" (Embree)
};

/// "auto" picks the analytic estimator while the patch count is at most this many times the
/// samples. Per origin it casts about one shadow ray per patch where the rays cast `samples`, so its
/// cost stays within ~5x the rays' (3.9x measured on cornell13k: 12,922 patches, 3072 samples),
/// and there the rays give fewer than one ray to an average patch, so the analytic per-entry error
/// is 1-2 orders of magnitude lower at equal time. Larger scenes (street64k) keep the rays.
constexpr double kAnalyticRaysFactor = 5.0;

/// Whether the hemisphere back end uses the analytic estimator for a scene of `patches` patches.
bool usesAnalyticEstimator(const BackendOptions& options, std::size_t patches);

/// Origins per patch the analytic estimator really uses: 1 (the centroid) or the m x m points of
/// its Gauss-Legendre rule, m = ceil(sqrt(origins)), per quad (per fan triangle otherwise).
std::uint32_t analyticOriginPoints(std::uint32_t origins);

/// Rays (or hemicube pixels) one row costs: samples x origins, one shadow ray per patch and origin
/// point for the analytic estimator (plus the directions when mirrors need them), 3 R^2 pixels.
double expectedRaysPerRow(const Scene& scene, std::string_view method, const BackendOptions& options);

/// Ray bookkeeping of a computation, summed over rows. Weights are in units of one row's power.
struct RayCounts {
    std::uint64_t rays = 0;          ///< rays cast from patches (not counting bounces)
    std::uint64_t bounces = 0;       ///< mirror reflections traced
    std::uint64_t misses = 0;        ///< rays (or bounces) that left the scene
    std::uint64_t backfaces = 0;     ///< rays that hit the back of a patch (lost)
    double lostWeight = 0;           ///< sum over rows of the row fraction lost to misses and backfaces
    double cutoffWeight = 0;         ///< sum over rows of the fraction still travelling at the depth/weight limit
    std::uint64_t rescaledRows = 0;  ///< analytic estimator: rows whose direct factors summed above 1, scaled to 1
    double largestDirectSum = 0;     ///< analytic estimator: the largest direct row sum before that scaling
    RayCounts& operator+=(const RayCounts& o);
};

/// Collects rows from worker threads (each row written once) into a CSR FormFactors.
class FormFactorBuilder {
public:
    explicit FormFactorBuilder(std::size_t patches);
    /// Thread-safe for distinct rows. Entries sorted by column, unique.
    void setRow(PatchId row, std::vector<FormFactors::Entry>&& entries);
    void addCounts(const RayCounts& counts);
    RayCounts counts() const;
    /// Thread-seconds spent in a named stage (e.g. "hemicube render"), summed over workers.
    void addStageSeconds(const std::string& stage, double seconds);
    std::map<std::string, double> stageSeconds() const;
    std::size_t rowsDone() const { return m_done.load(std::memory_order_relaxed); }
    /// A back end stops between rows once this is set (GUI Cancel, Ctrl-C).
    void cancel() { m_cancelled.store(true); }
    bool cancelled() const { return m_cancelled.load(std::memory_order_relaxed); }
    FormFactors finish();

private:
    std::vector<std::vector<FormFactors::Entry>> m_rows;
    std::vector<std::uint8_t> m_computed;
    std::atomic<std::size_t> m_done{0};
    std::atomic<bool> m_cancelled{false};
    mutable std::mutex m_mutex;
    RayCounts m_counts;
    std::map<std::string, double> m_stageSeconds;
};

/// Computes rows of F: F(i,j) = fraction of power leaving patch i that arrives at patch j.
class FormFactorBackend {
public:
    virtual ~FormFactorBackend() = default;
    virtual std::string_view name() const = 0;
    /// Builds acceleration structures for `scene`, which must outlive the back end's use of it.
    virtual void prepare(const Scene& scene) = 0;
    /// Fills the listed rows (parallel inside). Throws hemirad::Error.
    virtual void computeRows(const std::vector<PatchId>& rows, FormFactorBuilder& builder) = 0;
    /// Method and parameters recorded with F ("method", "samples", ...).
    virtual std::map<std::string, std::string> parameters() const = 0;
};

/// The largest row sum of an extended F (Sillion & Puech): a ray or pixel deposits its weight on
/// every patch of its mirror chain, so a row reaches at most 1 + s + ... + s^maxDepth (s = the
/// largest mirror reflectance, terms below minWeight dropped). "%.9g" text for F's parameters.
std::string rowSumBoundText(const Scene& scene, std::uint32_t maxDepth, double minWeight);

/// "hemisphere" (Embree rays) or "hemicube" (OpenGL). Throws hemirad::Error for an unknown name or invalid options.
std::unique_ptr<FormFactorBackend> makeBackend(std::string_view name, const BackendOptions& options);

}  // namespace hemirad
