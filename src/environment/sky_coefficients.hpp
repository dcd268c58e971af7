// Daylight coefficients: per patch and sky cell, the cell's radiance-to-irradiance factor with the
// scene's shadows (and the cell seen through mirrors), so that any sky of the same cells gives each
// patch's direct sky irradiance as one matrix-vector product; a year of skies is one matrix product.
#pragma once

#include "engine/scene.hpp"
#include "environment/sky_model.hpp"

#include <Eigen/Core>

#include <vector>

namespace hemirad {

struct SkyCoefficients {
    SkyGrid grid;
    int samples = 1;              ///< directions per cell side
    /// patches x cells, sr: sum over the cell's directions d of (its solid angle) x cos(theta_i(d)) x
    /// the sunlit fraction of patch i in a parallel beam from d (exact shadow polygons).
    Eigen::MatrixXd direct;
    /// patches x cells, sr: the same for the cell seen by way of one mirror (the reflected beam's
    /// exact footprints, weighted by s; environment/reflected_sun.hpp). 0 x 0 without mirrors.
    Eigen::MatrixXd mirrored;
    std::vector<double> horizontal;  ///< per cell, sr: horizontalWeights(grid, samples)
};

/// The coefficients of every patch of `scene` for the cells of skyGrid(subdivision), `samples` x
/// `samples` directions per cell; `up` and `north` orient the sky in the scene. Below the horizon
/// nothing comes (model the ground in the scene). Cost: one sunlit-fraction pass (and one reflected-
/// sun pass with mirrors) per direction. Throws hemirad::Error for a subdivision or sample count out
/// of range (samples 1..16).
SkyCoefficients skyCoefficients(const Scene& scene, int subdivision, int samples, const Vec3& up, const Vec3& north);

/// Per patch, W/m^2: the coefficients (direct or mirrored) times the cells' radiance (skyRadiance).
std::vector<double> skyIrradiance(const Eigen::MatrixXd& coefficients, const std::vector<double>& radiance);

/// One hour of a sky model on the patches: the direct sky and the sky through mirrors (empty without
/// mirrors), W/m^2, from the cells' radiance under `conditions`; `uniformFallback` as skyRadiance's.
struct SkyHour {
    std::vector<double> direct, mirrored;
    bool uniformFallback = false;
};
SkyHour skyHour(const SkyCoefficients& coefficients, const SkyModel& model, const SkyConditions& conditions);

}  // namespace hemirad
