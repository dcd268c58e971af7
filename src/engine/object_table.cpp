// Per-object summaries of a solved scene.
#include "engine/object_table.hpp"
#include "engine/csv.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"
#include "engine/irradiance.hpp"
#include "engine/tone_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace hemirad {

std::size_t objectsWithPatches(const Scene& scene) {
    std::vector<bool> used(scene.objects.size() + 1, false);  // the last: patches of no object
    for (const Patch& p : scene.patches) used[std::min<std::size_t>(p.object, scene.objects.size())] = true;
    return std::size_t(std::count(used.begin(), used.end(), true));
}

std::vector<ObjectSummary> summarizeObjects(const Scene& scene, const std::vector<Rgb>& B) {
    if (B.size() != scene.size()) throw Error("object table: radiosity does not match the scene");
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<ObjectSummary> all(scene.objects.size() + 1);  // the last: patches of no object
    for (std::size_t k = 0; k < all.size(); ++k) {
        all[k].name = k < scene.objects.size() ? scene.objects[k] : std::string("(no object)");
        all[k].bMin = all[k].hMin = inf;
        all[k].bMax = all[k].hMax = -inf;
    }
    std::vector<double> hArea(all.size(), 0.0);
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        const std::size_t k = std::min<std::size_t>(p.object, scene.objects.size());
        ObjectSummary& o = all[k];
        const double b = luminance(B[i]);
        ++o.patches;
        o.area += p.area;
        o.bMean += p.area * b;
        o.bMin = std::min(o.bMin, b);
        o.bMax = std::max(o.bMax, b);
        if (const double h = irradianceLuminance(p, B[i]); !std::isnan(h)) {
            ++o.hPatches;
            hArea[k] += p.area;
            o.hMean += p.area * h;
            o.hMin = std::min(o.hMin, h);
            o.hMax = std::max(o.hMax, h);
        }
    }
    std::vector<ObjectSummary> table;
    for (std::size_t k = 0; k < all.size(); ++k) {
        ObjectSummary& o = all[k];
        if (o.patches == 0) continue;
        o.bMean /= o.area;
        if (o.hPatches > 0) o.hMean /= hArea[k];
        else o.hMean = o.hMin = o.hMax = std::numeric_limits<double>::quiet_NaN();
        table.push_back(o);
    }
    return table;
}

void writeObjectTable(const std::string& path, const std::vector<ObjectSummary>& table, const std::string& unit) {
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    const std::string wm2 = " (W/m^2)";  // B and H: luminance Y
    out << "object,patches,area (" << (unit.empty() ? "scene units" : unit) << "^2)";
    for (const char* column : {"B_mean", "B_min", "B_max"}) out << ',' << column << wm2;
    out << ",H_patches";
    for (const char* column : {"H_mean", "H_min", "H_max"}) out << ',' << column << wm2;
    out << '\n';
    for (const ObjectSummary& o : table) {
        const std::string name = csvField(o.name);
        char line[512];
        std::snprintf(line, sizeof line, ",%zu,%.9g,%.9g,%.9g,%.9g,%zu,%.9g,%.9g,%.9g\n", o.patches, o.area, o.bMean, o.bMin,
                      o.bMax, o.hPatches, o.hMean, o.hMin, o.hMax);
        out << name << line;
    }
    file.commit();
}

}  // namespace hemirad
