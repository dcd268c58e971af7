// Results per object (the OBJ's `o` groups): what engineers read off a model, as a table and CSV.
#pragma once

#include "engine/scene.hpp"

#include <string>
#include <vector>

namespace hemirad {

/// One object's patches summed: the area, and radiosity B and irradiance H = (B - E)/rho as
/// luminance Y (W/m^2): area-weighted mean, minimum and maximum over its patches. H is over the
/// patches where it is known (every rho > 0); hPatches counts them (0: H has no value, NaN).
struct ObjectSummary {
    std::string name;
    std::size_t patches = 0, hPatches = 0;
    double area = 0.0;
    double bMean = 0.0, bMin = 0.0, bMax = 0.0;
    double hMean = 0.0, hMin = 0.0, hMax = 0.0;
};

/// The objects that hold at least one patch: what a scene's object count means (the loader's
/// "default" object of faces before any `o` line is empty in most OBJs, and is not counted then).
std::size_t objectsWithPatches(const Scene& scene);

/// One entry per object of the scene, in the scene's order (objects without patches left out).
std::vector<ObjectSummary> summarizeObjects(const Scene& scene, const std::vector<Rgb>& B);

/// The table as CSV, written atomically; the header states the units as the GUI's table does,
/// `unit` the scene's length unit ("" not stated: scene units):
///   object,patches,area (mm^2),B_mean (W/m^2),B_min (W/m^2),B_max (W/m^2),H_patches,H_mean (W/m^2),...
/// Object names are quoted when they hold a comma or a quote.
void writeObjectTable(const std::string& path, const std::vector<ObjectSummary>& table, const std::string& unit);

}  // namespace hemirad
