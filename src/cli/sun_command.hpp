// The sun as the command line gives it, shared by `sun` and `irradiance`.
#pragma once

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "environment/irradiance.hpp"

namespace hemirad {

/// The unit direction toward the sun: --sun-direction, or the solar position at --sun-time,
/// --latitude, --longitude in the frame --up and --north set; reports it. Throws hemirad::Error.
Vec3 sunDirectionFromOptions(const Options& options, const Reporter& reporter);

/// Metres per scene unit: the scene's stated unit, else --unit, else 1 with a warning.
double metresFromOptions(const Scene& scene, const Options& options, Warnings& warnings);

/// One hour of sun (--dni along `toSun`) and isotropic sky (--dhi) on the patches, as `irradiance`
/// solves it: sunlit fractions, direct sky view factors, the sun reflected by mirrors, F with every
/// row (obtained as the options say), the inter-reflection. Throws hemirad::Error.
IrradianceResult patchHour(const Scene& scene, const Options& options, const Vec3& toSun, double metres, Timings& timings,
                           const Reporter& reporter, Warnings& warnings);

}  // namespace hemirad
