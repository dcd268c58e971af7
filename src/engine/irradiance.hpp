// Irradiance H = (B - E) / rho: the flux a patch receives per area, what a meter on it reads.
#pragma once

#include "engine/scene.hpp"
#include "engine/tone_map.hpp"

#include <limits>

namespace hemirad {

/// H of patch `p` with radiosity `B` as luminance Y (W/m^2); NaN where a channel's rho is 0 (B then
/// says nothing about what that channel receives).
inline double irradianceLuminance(const Patch& p, const Rgb& B) {
    return (p.rho > 0.0).all() ? luminance(Rgb((B - p.emission) / p.rho)) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace hemirad
