// The hemisphere back end's own options, and the estimator rule that depends on them.
#pragma once

#include <cstddef>
#include <cstdint>

namespace hemirad {

/// Direct factors from ray counts, Lambert's exact point-to-polygon factor for every patch a shadow
/// ray finds visible, or automatic (analytic wherever its F fits in memory: resolveSettings).
enum class Estimator { Auto, Rays, Analytic };

/// The analytic estimator's terms through mirrors: exact by virtual images (planar convex mirrors),
/// or Monte Carlo along the Beckers directions. The ray estimator always follows its own rays.
enum class MirrorEstimator { Images, Rays };

/// The analytic estimator's pairs: by the emitter's rules (close pairs whole), or every pair whole
/// (the double contour integral less the adaptive hidden part): a converged reference, O(n^2)
/// contour integrals.
enum class PairMethod { Rules, Whole };

struct HemisphereOptions {
    static constexpr const char* kMethod = "hemisphere";
    std::uint32_t samples = 3072;  ///< directions per origin (Beckers cells), >= 1
    std::uint32_t origins = 1;     ///< ray origins per patch, stratified over its area, >= 1
    std::uint64_t seed = 1;        ///< origin jitter and pattern rotation
    bool fixedDirections = false;  ///< one pattern orientation for every origin (the reference system's way)
    bool jitter = false;           ///< a random direction inside each Beckers cell (unbiased; for references)
    Estimator estimator = Estimator::Auto;
    MirrorEstimator mirrorEstimator = MirrorEstimator::Images;
    /// The analytic estimator's emitter rule aims at a relative error of 10^-pairDigits per pair.
    std::uint32_t pairDigits = 2;
    PairMethod pairs = PairMethod::Rules;
};

/// Whether the hemisphere back end uses the analytic estimator (auto counts as analytic until
/// resolveSettings has decided, from the memory F would take).
bool usesAnalyticEstimator(const HemisphereOptions& options, std::size_t patches);

}  // namespace hemirad
