// The values a colour bar is labelled with: round numbers (1, 2 or 5 times a power of ten) inside
// the range, placed where they fall on the bar, not five odd fractions of the range ("0.8751").
#pragma once

#include "render/false_colour.hpp"

#include <string>
#include <vector>

namespace hemirad::ui {

struct LegendTick {
    double value = 0.0;
    double position = 0.0;  ///< on the bar, 0 (min, bottom) .. 1 (max, top)
    std::string label;
};

/// Ticks for `range`: linear, 2 to 7 multiples of a 1-2-5 step; log, the powers of ten inside it (with
/// their 2 and 5 multiples when it spans less than two decades, every other one past 6). The range's
/// ends are stated apart (the legend's note).
std::vector<LegendTick> legendTicks(const FalseColourRange& range);

}  // namespace hemirad::ui
