// The form-factor back-end interface, the options every back end takes, and the thread-safe row builder.
#pragma once

#include "engine/error.hpp"
#include "engine/form_factors.hpp"
#include "engine/scene.hpp"

#include <any>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace hemirad {

/// Options every back end takes: mirror chains and worker threads.
struct CommonOptions {
    std::uint32_t maxDepth = 8;    ///< mirror bounces followed per ray or pixel
    double minWeight = 1e-4;       ///< a mirror chain stops below this weight
    int threads = 0;               ///< worker threads (GL contexts); 0 = all cores
};

/// A form-factor method: the back end's name, the options every back end takes, and the back end's
/// own typed options struct (e.g. HemisphereOptions), held without this header naming it. Each
/// options struct names its back end in `kMethod`; backend_registry.hpp reads and edits them by flag.
struct MethodSettings {
    std::string method;
    CommonOptions common;
    std::any own;

    template <class T>
    static MethodSettings of(const T& own, const CommonOptions& common = {}) {
        return {std::string(T::kMethod), common, own};
    }
    /// The back end's options as its type; throws hemirad::Error when they belong to another back end.
    template <class T>
    const T& as() const {
        if (const T* p = std::any_cast<T>(&own)) return *p;
        throw Error("internal: the options of --method " + method + " are not those of " + std::string(T::kMethod));
    }
    template <class T>
    T& as() {
        return const_cast<T&>(static_cast<const MethodSettings&>(*this).as<T>());
    }
};

/// Ray bookkeeping of a computation, summed over rows. Weights are in units of one row's power.
struct RayCounts {
    std::uint64_t rays = 0;          ///< rays cast from patches (not counting bounces)
    std::uint64_t bounces = 0;       ///< mirror reflections traced
    std::uint64_t misses = 0;        ///< rays (or bounces) that left the scene
    std::uint64_t backfaces = 0;     ///< rays that hit the back of a patch (lost)
    double lostWeight = 0;           ///< sum over rows of the row fraction lost to misses and backfaces
    double lostArea = 0;             ///< sum over rows of A_i x row i's lost fraction (scene units^2)
    double rowArea = 0;              ///< sum of A_i over the computed rows: lostArea / rowArea is the area-weighted loss
    double cutoffWeight = 0;         ///< sum over rows of the fraction still travelling at the depth/weight limit
    std::uint64_t rescaledRows = 0;  ///< analytic estimator: rows whose direct factors summed above 1.001, scaled to 1
    std::uint64_t shadowTerms = 0;   ///< analytic estimator: point-to-patch terms whose visibility came from shadow polygons
    std::uint64_t shadowProbes = 0;  ///< analytic estimator: shadow-polygon probes of a pair's corners and edges' midpoints (not terms)
    std::uint64_t cutPairs = 0;      ///< analytic estimator: far pairs whose receiver's plane cuts the emitter (PairRules::cutValue)
    std::uint64_t cutWholePairs = 0; ///< of those, pairs a shadow's edge crosses, computed whole
    double largestDirectSum = 0;     ///< analytic estimator: the largest direct row sum before that scaling
    std::uint64_t contactPairs = 0;  ///< analytic estimator: pairs computed whole (close, straddling, penumbral, cut: contact_pairs.hpp)
    std::uint64_t contactShafts = 0; ///< of those, pairs with a blocker in their shaft
    std::uint64_t contactEvaluations = 0;  ///< visible-part evaluations of their hidden parts
    std::uint64_t straddlingPairs = 0;     ///< of the close-pair computations, ruled pairs across a shadow's edge
    std::uint64_t penumbralPairs = 0;      ///< of the close-pair computations, pairs in a penumbra (computed whole too)
    std::uint64_t coveredRows = 0;         ///< analytic estimator: rows whose patch a solid covers in part
    std::uint64_t convexSolids = 0;        ///< analytic estimator: convex solids among the blockers (the scene's, not summed: the largest)
    std::uint64_t solidFaces = 0;          ///< the patches that are their faces (likewise)
    RayCounts& operator+=(const RayCounts& o);
    /// The fraction of the power leaving the computed rows' patches that reached no patch, each row
    /// weighted by its patch's area (what a uniformly bright scene loses; the same on any mesh of the
    /// same geometry, unlike the mean over rows). 0 without rows.
    double lostFraction() const { return rowArea > 0.0 ? lostArea / rowArea : 0.0; }
};

/// The reports' words for lostFraction(), one for the CLI and the GUI: "lost 11.45% of the power
/// (area-weighted; 120 misses, 3 back faces)", or where no ray tells misses from hidden patches
/// (`lossFromRays` false) "11.45% of the power reached no patch (area-weighted; escaped, ...)".
std::string lostPowerText(const RayCounts& counts, bool lossFromRays);

/// Collects rows from worker threads (each row written once) into a CSR FormFactors.
class FormFactorBuilder {
public:
    /// Rows of `scene`'s F; the scene must outlive the builder.
    explicit FormFactorBuilder(const Scene& scene);
    /// Thread-safe for distinct rows. Entries sorted by column, unique; `lost` is the fraction of the
    /// row's power that reached no patch (misses, back faces), weighted by the patch's area in counts().
    void setRow(PatchId row, std::vector<FormFactors::Entry>&& entries, double lost);
    void addCounts(const RayCounts& counts);
    /// The back ends' counts, with lostArea and rowArea summed over the rows set so far (also after finish()).
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
    std::vector<double> m_lost;  ///< per row: the fraction of its power that reached no patch (-1: not set)
    const Scene& m_scene;
    std::atomic<std::size_t> m_done{0};
    std::atomic<bool> m_cancelled{false};
    mutable std::mutex m_mutex;
    RayCounts m_counts;
    std::map<std::string, double> m_stageSeconds;
};

/// Hands rows to a back end's workers, one at a time, from any thread. A back end pulls rows until
/// next() says none is left, so one run (one BVH, one GL context per worker) serves rows that arrive
/// while it works: a fixed list here, blocks handed out by an MPI work queue (src/mpi).
class RowSource {
public:
    virtual ~RowSource() = default;
    /// The next row to compute; false when no row is left (it may block until one arrives).
    virtual bool next(PatchId& row) = 0;
    /// Rows this source will hand out at most (sizes per-worker scratch; may over-estimate).
    virtual std::size_t sizeHint() const = 0;
    /// Whether next() may still hand out `row` (or has handed it out): a back end keeps work done
    /// for later rows only for these. False where the source cannot tell. Thread-safe.
    virtual bool mayHandOut(PatchId) const { return false; }
};

/// A fixed list of rows, handed out in order.
class RowList final : public RowSource {
public:
    explicit RowList(const std::vector<PatchId>& rows) : m_rows(rows) {
        for (const PatchId row : rows) {
            if (row >= m_listed.size()) m_listed.resize(std::size_t(row) + 1, 0);
            m_listed[row] = 1;
        }
    }
    bool next(PatchId& row) override {
        const std::size_t k = m_next.fetch_add(1, std::memory_order_relaxed);
        if (k >= m_rows.size()) return false;
        row = m_rows[k];
        return true;
    }
    std::size_t sizeHint() const override { return m_rows.size(); }
    bool mayHandOut(PatchId row) const override { return row < m_listed.size() && m_listed[row]; }

private:
    const std::vector<PatchId>& m_rows;
    std::vector<std::uint8_t> m_listed;  ///< per patch: in the list
    std::atomic<std::size_t> m_next{0};
};

/// Computes rows of F: F(i,j) = fraction of power leaving patch i that arrives at patch j.
class FormFactorBackend {
public:
    virtual ~FormFactorBackend() = default;
    virtual std::string_view name() const = 0;
    /// Builds acceleration structures for `scene`, which must outlive the back end's use of it.
    virtual void prepare(const Scene& scene) = 0;
    /// Fills every row `rows` hands out (parallel inside), until it has none left or the builder is
    /// cancelled. Throws hemirad::Error.
    virtual void computeRows(RowSource& rows, FormFactorBuilder& builder) = 0;
    /// Fills the listed rows, in orderRows()'s order.
    void computeRows(const std::vector<PatchId>& rows, FormFactorBuilder& builder) {
        std::vector<PatchId> ordered(rows);
        orderRows(ordered);
        RowList list(ordered);
        computeRows(list, builder);
    }
    /// Puts `rows` in the order this back end computes them fastest; the default keeps it. Valid
    /// after prepare(); the same on every MPI rank.
    virtual void orderRows(std::vector<PatchId>&) const {}
    /// Relative cost of row i against the back end's average row (1): what a scheduler that spreads
    /// rows over processes weighs them by. Valid after prepare().
    virtual double rowCost(PatchId) const { return 1.0; }
    /// How F was computed, typed (method, estimator, row-sum bound); valid after prepare().
    virtual FormFactorProvenance provenance() const = 0;
    /// The back end's parameters recorded with F for people ("samples", "resolution", ...).
    virtual std::map<std::string, std::string> parameters() const = 0;
    /// What computed the rows, for the run's report (e.g. the GL renderer and its contexts); not
    /// recorded with F, which must not depend on how many processes or threads made it.
    virtual std::string device() const { return {}; }
    /// Whether each pair's value is the one its emitting row computes (emitsFor, engine/emitted_pairs.hpp):
    /// then the other row's entry is taken from it once the rows are done (takePairsFromEmitters).
    virtual bool pairsFromEmitters() const { return false; }
};

/// The largest row sum of an extended F (Sillion & Puech): a ray or pixel deposits its weight on
/// every patch of its mirror chain, so a row reaches at most 1 + s + ... + s^maxDepth (s = the
/// largest mirror reflectance, terms below minWeight dropped).
double extendedRowSumBound(const Scene& scene, std::uint32_t maxDepth, double minWeight);

}  // namespace hemirad
