// Round tick values for the legends' colour bars.
#include "ui/legend_ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hemirad::ui {
namespace {

/// `v` written with no more digits than `step` needs ("0.2", "150", "3e-05").
std::string tickLabel(double v, double step) {
    char text[32];
    const double a = std::abs(v);
    if (a != 0.0 && (a < 1e-3 || a >= 1e5)) {
        std::snprintf(text, sizeof text, "%.2g", v);
    } else {
        const int decimals = std::max(0, -int(std::floor(std::log10(step) + 1e-9)));
        std::snprintf(text, sizeof text, "%.*f", decimals, v);
    }
    return text;
}

}  // namespace

std::vector<LegendTick> legendTicks(const FalseColourRange& range) {
    std::vector<LegendTick> ticks;
    if (!(range.max > range.min) || !std::isfinite(range.min) || !std::isfinite(range.max)) return ticks;
    const auto add = [&](double v, double step) {
        ticks.push_back({v, range.position(v), tickLabel(v, step)});
    };
    if (range.scale == FalseColourScale::Log && range.min > 0.0) {
        const int first = int(std::ceil(std::log10(range.min) - 1e-9)), last = int(std::floor(std::log10(range.max) + 1e-9));
        if (last - first < 1) {
            // Less than two decades: 1, 2 and 5 times each power of ten inside.
            for (int k = first - 1; k <= last; ++k)
                for (double m : {1.0, 2.0, 5.0}) {
                    const double v = m * std::pow(10.0, k);
                    if (v >= range.min * (1 - 1e-9) && v <= range.max * (1 + 1e-9)) add(v, v);
                }
        } else {
            const int every = (last - first) / 6 + 1;
            for (int k = last; k >= first; k -= every) add(std::pow(10.0, k), std::pow(10.0, k));
            std::reverse(ticks.begin(), ticks.end());
        }
        return ticks;
    }
    // The smallest 1-2-5 step of at least a sixth of the range: 2 to 7 ticks.
    const double raw = (range.max - range.min) / 6.0;
    const double decade = std::pow(10.0, std::floor(std::log10(raw)));
    const double step = raw <= decade ? decade : raw <= 2 * decade ? 2 * decade : raw <= 5 * decade ? 5 * decade : 10 * decade;
    for (double k = std::ceil(range.min / step - 1e-9); k * step <= range.max + 1e-9 * step; ++k)
        add(std::abs(k) < 0.5 ? 0.0 : k * step, step);
    return ticks;
}

}  // namespace hemirad::ui
