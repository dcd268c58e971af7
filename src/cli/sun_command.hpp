// The sun as the command line gives it, shared by `sun` and `irradiance`.
#pragma once

#include "cli/options.hpp"
#include "cli/report.hpp"

namespace hemirad {

/// The unit direction toward the sun: --sun-direction, or the solar position at --sun-time,
/// --latitude, --longitude in the frame --up and --north set; reports it. Throws hemirad::Error.
Vec3 sunDirectionFromOptions(const Options& options, const Reporter& reporter);

}  // namespace hemirad
