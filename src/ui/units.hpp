// Values with their units for the GUI's panels: lengths and areas in the scene's unit (converted
// to m^2 alongside), power in W where the unit is known.
#pragma once

#include "engine/math.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace hemirad {
class Scene;
}

namespace hemirad::ui {

/// A value with 4 significant digits ("0.1331", "1.534e+05"): scientific only past 1e-4 .. 1e5.
std::string formatNumber(double v);
/// The three channels, as formatNumber writes each.
std::string formatRgb(const Rgb& c);
/// "1 patch", "20 patches": the count with the noun in the number it takes.
std::string formatCount(std::size_t n, const char* one, const char* many);
/// The Scene panel's counts: "20 patches, 8 objects, mirrors" (objects that hold patches).
std::string sceneCounts(const Scene& scene);
/// The Pipeline panel's meshing line: "3 of 8 objects meshed", of the objects of `source` (the scene
/// as loaded) that hold patches, `edges` per object as AppState::meshEdges (0 = as loaded).
std::string meshedCounts(const Scene& source, const std::vector<double>& edges);
/// "mm", or "scene units" when the scene states none.
std::string lengthUnitLabel(const std::string& unit);
/// "3090 mm^2 (0.00309 m^2)", "2 m^2", "3090 (scene units^2)".
std::string formatArea(double area, const std::string& unit);
/// The power sum A B of a selection: "0.041 0.023 0.0075 W" where the unit is known, else
/// "... W/m^2 x scene units^2".
std::string formatPower(const Rgb& areaTimesB, const std::string& unit);

}  // namespace hemirad::ui
