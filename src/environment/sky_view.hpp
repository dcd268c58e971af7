// Sky view factors: per patch, the part of its hemisphere (cosine-weighted) through which the sky is
// seen, directly and by way of mirrors (weighted by their reflectances). Exact by the form-factor
// back end's own means: every surface, front or back, blocks the sky (so not 1 - the row sum of F,
// which leaves out back faces).
#pragma once

#include "engine/scene.hpp"
#include "preprocess/backend_registry.hpp"

#include <string>
#include <vector>

namespace hemirad {

struct SkyView {
    std::vector<double> direct;    ///< per patch: the sky seen straight, 0..1
    std::vector<double> mirrored;  ///< per patch: the sky seen through mirrors, weighted by s (0 without mirrors)
    std::vector<double> total() const;
    /// Mirror chains cut off by --max-depth count as sky; their weight is reported (from the F run).
    double cutoffWeight = 0.0;
    std::string method;            ///< the back end and estimator that measured it, for the report
};

/// The sky view factors of every patch of `scene` with `settings` (the back end's defaults: the
/// analytic estimator where it fits). Computes the direct factors of the scene made two-sided (each
/// patch given a reversed twin 1e-6 x the scene's size behind it, mirrors off), and, with mirrors,
/// the extended factors: the sky through mirrors is sum_m s_m F_im - sum_k (F_ik - D_ik) (what the
/// mirrors send on minus what lands). Throws hemirad::Error as computeFormFactors does.
SkyView skyViewFactors(const Scene& scene, const MethodSettings& settings);

/// The two-sided scene behind the direct factors: patches 0..N-1 as in `scene` (s = 0), then each
/// patch's reversed twin, offset along -normal by `offset`.
Scene twoSidedScene(const Scene& scene, double offset);

/// patch,object,area,sky_view_factor,direct,through_mirrors,x,y,z,nx,ny,nz (CSV, atomic): area in
/// the scene's unit^2, (x, y, z) the patch's centroid, (nx, ny, nz) its normal; every value to the
/// last digit.
void writeSkyViewCsv(const std::string& path, const Scene& scene, const SkyView& sky);

/// The sky view factors of `scene` from a file writeSkyViewCsv wrote (to compute them once for many
/// runs). Each row must be the scene's patch of its number, in order, with its object, its area and
/// its centroid (to 1e-9 of the patch's and the scene's size) and its normal: else hemirad::Error naming the file,
/// the line and the value (the file was computed for other geometry). `method` names the file.
SkyView readSkyViewCsv(const std::string& path, const Scene& scene);

}  // namespace hemirad
