// False-colour images for engineers: a per-patch quantity (radiosity B, irradiance H, emission E,
// the sky view factor) mapped through a perceptually uniform colour map (viridis) on a linear or log scale, with a legend
// (colour bar, values, unit) beside the picture.
#pragma once

#include "engine/scene.hpp"
#include "render/raytracer.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hemirad {

/// SkyViewFactor's values come from skyViewFactors (src/environment), not from B.
enum class FalseColourQuantity { Radiosity, Irradiance, Emission, SkyViewFactor };
enum class FalseColourScale { Linear, Log };

/// "radiosity", "irradiance", "emission", "sky_view_factor"; throws hemirad::Error for another name.
FalseColourQuantity parseFalseColourQuantity(const std::string& name);
/// "linear", "log"; throws hemirad::Error for another name.
FalseColourScale parseFalseColourScale(const std::string& name);
/// "linear" or "log".
const char* falseColourScaleName(FalseColourScale scale);
/// What the legend calls it: "radiosity B", "irradiance H", "emission E", "sky view factor".
std::string falseColourTitle(FalseColourQuantity quantity);
/// Its unit for the legend and reports: "W/m^2, luminance Y", or "unitless, 0..1" for the sky view factor.
std::string falseColourUnit(FalseColourQuantity quantity);
/// The range a side of --range left open takes where the quantity has a natural one: 0 and 1 for
/// the sky view factor (on a log scale the maximum only); none (the values' extremes) otherwise.
std::pair<std::optional<double>, std::optional<double>> falseColourDefaultRange(FalseColourQuantity quantity,
                                                                                  FalseColourScale scale);

/// The quantity per patch as one number: the luminance Y (Rec. 709 weights) of the RGB value, in
/// the scene's emission units (W/m^2). Irradiance H = (B - E) / rho, the flux a patch receives per
/// area (what a meter on the surface reads); NaN where a channel's rho is 0 (B says nothing there).
/// Throws hemirad::Error when no patch emits (then every value would be 0), and for SkyViewFactor
/// (not a function of B).
std::vector<double> falseColourValues(const Scene& scene, const std::vector<Rgb>& B, FalseColourQuantity quantity);

/// An automatic log range spans at most this many decades: its minimum is at least max / 10^4.
/// Below that lie values no meter reads against the rest (the floor under a block, about 0 up to
/// round-off: 1e-5 to 1.8e-19 in the Cornell box), which would otherwise squeeze the map into its top.
constexpr double kFalseColourLogDecades = 4.0;

struct FalseColourRange {
    double min = 0.0, max = 1.0;
    FalseColourScale scale = FalseColourScale::Linear;
    bool automatic = true;
    bool floored = false;  ///< an automatic log minimum raised to max / 10^kFalseColourLogDecades
    /// Position of `value` on the colour bar, 0 (min) .. 1 (max), clamped; NaN for NaN.
    double position(double value) const;
};

/// The range: `min`/`max` where given, else the extremes of the finite values (log: of the positive
/// ones, the minimum no lower than max / 10^kFalseColourLogDecades). Throws hemirad::Error when no
/// value can be shown or min >= max.
FalseColourRange falseColourRange(const std::vector<double>& values, FalseColourScale scale, std::optional<double> min,
                                  std::optional<double> max);
/// How an automatic range was chosen, for reports and legends: "the values' extremes", or "min =
/// max/1e4 (4 decades); lower values show the bottom colour"; empty for a given range.
std::string falseColourRangeNote(const FalseColourRange& range);

/// The colour map at t in [0, 1] (matplotlib's viridis, 256 steps).
std::array<std::uint8_t, 3> viridis(double t);

/// 8-bit RGB image, rows top to bottom.
struct Rgb8Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
};

/// Colours of what is not a value: background, a patch's back, a patch without data (NaN).
constexpr std::array<std::uint8_t, 3> kFalseColourBackground{0, 0, 0};
constexpr std::array<std::uint8_t, 3> kFalseColourBackFace{48, 48, 48};
constexpr std::array<std::uint8_t, 3> kFalseColourNoData{128, 128, 128};
/// The colour of `value` on `range`: the map's, or kFalseColourNoData for NaN.
std::array<std::uint8_t, 3> falseColourOf(double value, const FalseColourRange& range);

/// Width of the legend strip added to the right of the picture.
constexpr int kFalseColourLegendWidth = 170;

/// The picture (one camera ray per pixel centre: each pixel is the colour of the patch it sees,
/// mirrors included as patches) and, to its right, the legend: title, unit, colour bar, five values
/// on it, the scale, and "no data" when some patch has none.
Rgb8Image renderFalseColour(const Scene& scene, const RayScene& rays, const std::vector<double>& values,
                            const FalseColourRange& range, FalseColourQuantity quantity, const RenderOptions& options);

}  // namespace hemirad
