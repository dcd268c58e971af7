// Formatting of the panels' values and units.
#include "ui/units.hpp"

#include "engine/object_table.hpp"
#include "engine/scene.hpp"

#include <cstdio>

namespace hemirad::ui {

std::string formatNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v);
    return text;
}

std::string formatRgb(const Rgb& c) { return formatNumber(c[0]) + " " + formatNumber(c[1]) + " " + formatNumber(c[2]); }

std::string formatCount(std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string sceneCounts(const Scene& scene) {
    return formatCount(scene.size(), "patch", "patches") + ", " + formatCount(objectsWithPatches(scene), "object", "objects") +
           (scene.hasMirrors() ? ", mirrors" : "");
}

std::string meshedCounts(const Scene& source, const std::vector<double>& edges) {
    std::vector<bool> used(edges.size(), false);  // the loader's "default" object is often empty
    for (const Patch& p : source.patches)
        if (p.object < used.size()) used[p.object] = true;
    std::size_t meshed = 0;
    for (std::size_t k = 0; k < edges.size(); ++k) meshed += used[k] && edges[k] > 0;
    return std::to_string(meshed) + " of " + formatCount(objectsWithPatches(source), "object", "objects") + " meshed";
}

std::string lengthUnitLabel(const std::string& unit) { return unit.empty() ? "scene units" : unit; }

std::string formatArea(double area, const std::string& unit) {
    if (unit.empty()) return formatNumber(area) + " (scene units^2)";
    const double metres = metresPerUnit(unit);
    std::string text = formatNumber(area) + " " + unit + "^2";
    if (unit != "m") text += " (" + formatNumber(area * metres * metres) + " m^2)";
    return text;
}

std::string formatPower(const Rgb& areaTimesB, const std::string& unit) {
    if (unit.empty()) return formatRgb(areaTimesB) + " W/m^2 x scene units^2";
    const double metres = metresPerUnit(unit);
    return formatRgb(areaTimesB * (metres * metres)) + " W";
}

}  // namespace hemirad::ui
