// Exposure and sRGB encoding.
#include "engine/tone_map.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

double autoExposure(std::vector<double> luminances, double percentile, double target) {
    luminances.erase(std::remove_if(luminances.begin(), luminances.end(),
                                    [](double v) { return !(v > 0.0) || !std::isfinite(v); }),
                     luminances.end());
    if (luminances.empty()) return 1.0;
    const auto k = static_cast<std::size_t>(std::clamp(percentile, 0.0, 1.0) * double(luminances.size() - 1));
    std::nth_element(luminances.begin(), luminances.begin() + static_cast<std::ptrdiff_t>(k), luminances.end());
    return target / luminances[k];
}

std::array<std::uint8_t, 3> toSrgb8(const Rgb& linear, double scale) {
    std::array<std::uint8_t, 3> out{};
    for (int c = 0; c < 3; ++c) {
        const double v = std::clamp(linear[c] * scale, 0.0, 1.0);
        const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
        out[c] = static_cast<std::uint8_t>(std::lround(s * 255.0));
    }
    return out;
}

}  // namespace hemirad
