// The sun as the command line gives it, shared by `sun` and `irradiance`.
#pragma once

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "environment/irradiance.hpp"
#include "environment/sky_coefficients.hpp"

namespace hemirad {

/// The unit direction toward the sun: --sun-direction, or the solar position at --sun-time,
/// --latitude, --longitude in the frame --up and --north set; reports it. Throws hemirad::Error.
Vec3 sunDirectionFromOptions(const Options& options, const Reporter& reporter);

/// Whether --sun-time puts the sun at or below the horizon at --latitude, --longitude (then no direct
/// sun reaches the scene). A --sun-direction is taken as given: false.
bool sunBelowHorizon(const Options& options);

/// The scene's up and north as --up and --north give them (north: +y for z up, -z for y up).
Vec3 upFromOptions(const Options& options);
Vec3 northFromOptions(const Options& options);

/// --sky MODEL's daylight coefficients for `scene` (cells and directions as --sky-subdivision and
/// --sky-samples say), timed and reported. Throws hemirad::Error.
SkyCoefficients skyCoefficientsFromOptions(const Scene& scene, const Options& options, Timings& timings, const Reporter& reporter);

/// The sky's conditions for one hour as the command line gives them: the sun `toSun` (scene frame)
/// in the sky's frame, --dni, --dhi and --sun-time's day of the year (0 with --sun-direction).
SkyConditions skyConditionsFromOptions(const Options& options, const Vec3& toSun);

/// One hour of a sky model on the patches: the direct sky and the sky through mirrors (W/m^2) from
/// the coefficients, for the sun `toSun` (scene frame), --dni and --dhi, on --sun-time's day of the
/// year (the mean Sun-Earth distance with --sun-direction); reports Perez's clearness and brightness.
void modelSkyHour(const SkyCoefficients& sky, const Options& options, const Vec3& toSun, IrradianceInputs& in,
                  const Reporter& reporter);

/// The isotropic sky's direct sky view factors per patch: read from --svf FILE where it exists
/// (checked against the scene), else computed (and, with --svf, stored there); timed and
/// reported. Throws hemirad::Error.
std::vector<double> directSkyViewFromOptions(const Scene& scene, const Options& options, Timings& timings, const Reporter& reporter);

/// Metres per scene unit: the scene's stated unit, else --unit, else 1 with a warning.
double metresFromOptions(const Scene& scene, const Options& options, Warnings& warnings);

/// One hour of sun (--dni along `toSun`) and sky (--dhi: isotropic, or --sky MODEL) on the patches,
/// as `irradiance` solves it: sunlit fractions, direct sky view factors (or the model's daylight
/// coefficients), the sun (and the model's sky) reflected by mirrors, F with every row (obtained as
/// the options say), the inter-reflection. Throws hemirad::Error.
IrradianceResult patchHour(const Scene& scene, const Options& options, const Vec3& toSun, double metres, Timings& timings,
                           const Reporter& reporter, Warnings& warnings);

}  // namespace hemirad
