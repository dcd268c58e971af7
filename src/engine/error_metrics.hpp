// Accuracy metrics against a reference: per-row form-factor errors and radiosity errors.
#pragma once

#include "engine/form_factors.hpp"
#include "engine/scene.hpp"

#include <vector>

namespace hemirad {

/// Per-row errors of F against F_ref over the rows both computed, as the reference system defined
/// them: for row i, the mean, max and RMS over j of |F_ij - F_ref,ij| (N entries, zeros included);
/// then their averages over rows and the worst row of each. Also the mean row L1 distance.
struct FormFactorError {
    std::size_t rows = 0;
    double mean = 0, worstMean = 0;  ///< average over rows of the row mean; the largest row mean
    double max = 0, worstMax = 0;    ///< average of row maxima; the largest entry error
    double rms = 0, worstRms = 0;
    double rowL1 = 0, worstRowL1 = 0;  ///< sum_j |dF_ij|, averaged over rows / worst
    std::size_t worstRow = 0;          ///< row with the largest L1 distance
};
FormFactorError compareFormFactors(const FormFactors& F, const FormFactors& reference);

/// Radiosity errors |B - B_ref| pooled over patches and channels: mean, max, RMS, and the same
/// relative to the mean of |B_ref| (so scenes of any brightness compare).
struct RadiosityError {
    double mean = 0, max = 0, rms = 0;
    double relativeMean = 0, relativeMax = 0, relativeRms = 0;
};
RadiosityError compareRadiosity(const std::vector<Rgb>& B, const std::vector<Rgb>& reference);

}  // namespace hemirad
