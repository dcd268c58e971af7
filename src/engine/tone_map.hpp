// Display mapping: exposure (manual or automatic) and the sRGB transfer function.
#pragma once

#include "engine/math.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace hemirad {

/// Scale that maps the given percentile (0..1) of `luminances` to `target` (0..1); 1 when all are 0.
double autoExposure(std::vector<double> luminances, double percentile = 0.95, double target = 0.8);

/// Rec. 709 luminance of a linear RGB value.
inline double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

/// Linear value -> 8-bit sRGB after multiplying by `scale` (clamped to [0, 1]).
std::array<std::uint8_t, 3> toSrgb8(const Rgb& linear, double scale);

}  // namespace hemirad
