// False-colour images: per-patch values, the viridis map, and a legend drawn with stb_easy_font.
#include "render/false_colour.hpp"

#include "engine/error.hpp"
#include "engine/irradiance.hpp"
#include "engine/tone_map.hpp"
#include "rays/ray_scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <stb/stb_easy_font.h>

namespace hemirad {
namespace {

const std::uint8_t kViridis[256][3] = {
    {68, 1, 84}, {68, 2, 86}, {69, 4, 87}, {69, 5, 89}, {70, 7, 90}, {70, 8, 92}, {70, 10, 93}, {70, 11, 94},
    {71, 13, 96}, {71, 14, 97}, {71, 16, 99}, {71, 17, 100}, {71, 19, 101}, {72, 20, 103}, {72, 22, 104}, {72, 23, 105},
    {72, 24, 106}, {72, 26, 108}, {72, 27, 109}, {72, 28, 110}, {72, 29, 111}, {72, 31, 112}, {72, 32, 113}, {72, 33, 115},
    {72, 35, 116}, {72, 36, 117}, {72, 37, 118}, {72, 38, 119}, {72, 40, 120}, {72, 41, 121}, {71, 42, 122}, {71, 44, 122},
    {71, 45, 123}, {71, 46, 124}, {71, 47, 125}, {70, 48, 126}, {70, 50, 126}, {70, 51, 127}, {70, 52, 128}, {69, 53, 129},
    {69, 55, 129}, {69, 56, 130}, {68, 57, 131}, {68, 58, 131}, {68, 59, 132}, {67, 61, 132}, {67, 62, 133}, {66, 63, 133},
    {66, 64, 134}, {66, 65, 134}, {65, 66, 135}, {65, 68, 135}, {64, 69, 136}, {64, 70, 136}, {63, 71, 136}, {63, 72, 137},
    {62, 73, 137}, {62, 74, 137}, {62, 76, 138}, {61, 77, 138}, {61, 78, 138}, {60, 79, 138}, {60, 80, 139}, {59, 81, 139},
    {59, 82, 139}, {58, 83, 139}, {58, 84, 140}, {57, 85, 140}, {57, 86, 140}, {56, 88, 140}, {56, 89, 140}, {55, 90, 140},
    {55, 91, 141}, {54, 92, 141}, {54, 93, 141}, {53, 94, 141}, {53, 95, 141}, {52, 96, 141}, {52, 97, 141}, {51, 98, 141},
    {51, 99, 141}, {50, 100, 142}, {50, 101, 142}, {49, 102, 142}, {49, 103, 142}, {49, 104, 142}, {48, 105, 142}, {48, 106, 142},
    {47, 107, 142}, {47, 108, 142}, {46, 109, 142}, {46, 110, 142}, {46, 111, 142}, {45, 112, 142}, {45, 113, 142}, {44, 113, 142},
    {44, 114, 142}, {44, 115, 142}, {43, 116, 142}, {43, 117, 142}, {42, 118, 142}, {42, 119, 142}, {42, 120, 142}, {41, 121, 142},
    {41, 122, 142}, {41, 123, 142}, {40, 124, 142}, {40, 125, 142}, {39, 126, 142}, {39, 127, 142}, {39, 128, 142}, {38, 129, 142},
    {38, 130, 142}, {38, 130, 142}, {37, 131, 142}, {37, 132, 142}, {37, 133, 142}, {36, 134, 142}, {36, 135, 142}, {35, 136, 142},
    {35, 137, 142}, {35, 138, 141}, {34, 139, 141}, {34, 140, 141}, {34, 141, 141}, {33, 142, 141}, {33, 143, 141}, {33, 144, 141},
    {33, 145, 140}, {32, 146, 140}, {32, 146, 140}, {32, 147, 140}, {31, 148, 140}, {31, 149, 139}, {31, 150, 139}, {31, 151, 139},
    {31, 152, 139}, {31, 153, 138}, {31, 154, 138}, {30, 155, 138}, {30, 156, 137}, {30, 157, 137}, {31, 158, 137}, {31, 159, 136},
    {31, 160, 136}, {31, 161, 136}, {31, 161, 135}, {31, 162, 135}, {32, 163, 134}, {32, 164, 134}, {33, 165, 133}, {33, 166, 133},
    {34, 167, 133}, {34, 168, 132}, {35, 169, 131}, {36, 170, 131}, {37, 171, 130}, {37, 172, 130}, {38, 173, 129}, {39, 173, 129},
    {40, 174, 128}, {41, 175, 127}, {42, 176, 127}, {44, 177, 126}, {45, 178, 125}, {46, 179, 124}, {47, 180, 124}, {49, 181, 123},
    {50, 182, 122}, {52, 182, 121}, {53, 183, 121}, {55, 184, 120}, {56, 185, 119}, {58, 186, 118}, {59, 187, 117}, {61, 188, 116},
    {63, 188, 115}, {64, 189, 114}, {66, 190, 113}, {68, 191, 112}, {70, 192, 111}, {72, 193, 110}, {74, 193, 109}, {76, 194, 108},
    {78, 195, 107}, {80, 196, 106}, {82, 197, 105}, {84, 197, 104}, {86, 198, 103}, {88, 199, 101}, {90, 200, 100}, {92, 200, 99},
    {94, 201, 98}, {96, 202, 96}, {99, 203, 95}, {101, 203, 94}, {103, 204, 92}, {105, 205, 91}, {108, 205, 90}, {110, 206, 88},
    {112, 207, 87}, {115, 208, 86}, {117, 208, 84}, {119, 209, 83}, {122, 209, 81}, {124, 210, 80}, {127, 211, 78}, {129, 211, 77},
    {132, 212, 75}, {134, 213, 73}, {137, 213, 72}, {139, 214, 70}, {142, 214, 69}, {144, 215, 67}, {147, 215, 65}, {149, 216, 64},
    {152, 216, 62}, {155, 217, 60}, {157, 217, 59}, {160, 218, 57}, {162, 218, 55}, {165, 219, 54}, {168, 219, 52}, {170, 220, 50},
    {173, 220, 48}, {176, 221, 47}, {178, 221, 45}, {181, 222, 43}, {184, 222, 41}, {186, 222, 40}, {189, 223, 38}, {192, 223, 37},
    {194, 223, 35}, {197, 224, 33}, {200, 224, 32}, {202, 225, 31}, {205, 225, 29}, {208, 225, 28}, {210, 226, 27}, {213, 226, 26},
    {216, 226, 25}, {218, 227, 25}, {221, 227, 24}, {223, 227, 24}, {226, 228, 24}, {229, 228, 25}, {231, 228, 25}, {234, 229, 26},
    {236, 229, 27}, {239, 229, 28}, {241, 229, 29}, {244, 230, 30}, {246, 230, 32}, {248, 230, 33}, {251, 231, 35}, {253, 231, 37},
};

/// A value for the legend: 4 significant digits, no exponent between 1e-3 and 1e5.
std::string label(double v) {
    char text[32];
    const double a = std::abs(v);
    std::snprintf(text, sizeof text, (a != 0.0 && (a < 1e-3 || a >= 1e5)) ? "%.3e" : "%.4g", v);
    return text;
}

/// `text` in lines no wider than `width` pixels in stb_easy_font at scale 1, broken at spaces (a word
/// wider than that keeps a line of its own).
std::vector<std::string> wrapText(const std::string& text, int width) {
    auto pixels = [](std::string s) { return stb_easy_font_width(s.data()); };
    std::vector<std::string> lines;
    std::string line, word;
    std::istringstream words(text);
    while (words >> word) {
        if (!line.empty() && pixels(line + ' ' + word) > width) lines.push_back(line), line.clear();
        line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty() || lines.empty()) lines.push_back(line);
    return lines;
}

class Canvas {
public:
    explicit Canvas(Rgb8Image& image) : m_image(image) {}
    void fill(int x0, int y0, int x1, int y1, std::array<std::uint8_t, 3> c) {
        x0 = std::max(x0, 0), y0 = std::max(y0, 0);
        x1 = std::min(x1, m_image.width), y1 = std::min(y1, m_image.height);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) std::copy(c.begin(), c.end(), m_image.rgb.begin() + 3 * (std::size_t(y) * m_image.width + x));
    }
    /// Text with stb_easy_font's segments, each scaled by `scale` (the font is 7 pixels tall at 1).
    void text(int x, int y, const std::string& s, int scale, std::array<std::uint8_t, 3> c) {
        std::vector<char> copy(s.begin(), s.end());
        copy.push_back('\0');
        static thread_local std::vector<char> quads(64 * 1024);
        const int n = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, quads.data(), int(quads.size()));
        for (int q = 0; q < n; ++q) {
            const float* v = reinterpret_cast<const float*>(quads.data() + 64 * q);  // 4 vertices of x, y, z, rgba
            const float qx0 = v[0], qy0 = v[1], qx1 = v[8], qy1 = v[9];
            fill(x + int(std::lround(qx0 * scale)), y + int(std::lround(qy0 * scale)), x + int(std::lround(qx1 * scale)),
                 y + int(std::lround(qy1 * scale)), c);
        }
    }

private:
    Rgb8Image& m_image;
};

}  // namespace

FalseColourQuantity parseFalseColourQuantity(const std::string& name) {
    if (name == "radiosity") return FalseColourQuantity::Radiosity;
    if (name == "irradiance") return FalseColourQuantity::Irradiance;
    if (name == "emission") return FalseColourQuantity::Emission;
    if (name == "sky_view_factor") return FalseColourQuantity::SkyViewFactor;
    throw Error("--false-color expects radiosity, irradiance, emission or sky_view_factor, got '" + name + "'");
}

FalseColourScale parseFalseColourScale(const std::string& name) {
    if (name == "linear") return FalseColourScale::Linear;
    if (name == "log") return FalseColourScale::Log;
    throw Error("--scale expects linear or log, got '" + name + "'");
}

const char* falseColourScaleName(FalseColourScale scale) { return scale == FalseColourScale::Log ? "log" : "linear"; }

std::string falseColourTitle(FalseColourQuantity quantity) {
    switch (quantity) {
        case FalseColourQuantity::Radiosity: return "radiosity B";
        case FalseColourQuantity::Irradiance: return "irradiance H";
        case FalseColourQuantity::Emission: return "emission E";
        case FalseColourQuantity::SkyViewFactor: return "sky view factor";
    }
    return "?";
}

std::string falseColourUnit(FalseColourQuantity quantity) {
    return quantity == FalseColourQuantity::SkyViewFactor ? "unitless, 0..1" : "W/m^2, luminance Y";
}

std::pair<std::optional<double>, std::optional<double>> falseColourDefaultRange(FalseColourQuantity quantity,
                                                                                  FalseColourScale scale) {
    // A fraction of the hemisphere: maps of different scenes compare on 0..1 (a lone ground plane, all
    // 1, would otherwise get the uniform quantity's 0.5..1.5).
    if (quantity != FalseColourQuantity::SkyViewFactor) return {};
    return {scale == FalseColourScale::Linear ? std::optional<double>(0.0) : std::nullopt, 1.0};
}

std::vector<double> falseColourValues(const Scene& scene, const std::vector<Rgb>& B, FalseColourQuantity quantity) {
    if (quantity == FalseColourQuantity::SkyViewFactor)
        throw Error("internal: false colour: the sky view factor comes from skyViewFactors, not from B");
    if (B.size() != scene.size()) throw Error("false colour: radiosity does not match the scene");
    // Without an emitter B, H and E are 0 everywhere: a map of zeros (once a -1..1 range in one colour)
    // would read as a measurement.
    if (std::none_of(scene.patches.begin(), scene.patches.end(), [](const Patch& p) { return (p.emission > 0.0).any(); }))
        throw Error("false colour: nothing emits (no patch has emission E > 0), so B, H and E are 0 everywhere: no data");
    std::vector<double> values(scene.size());
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        switch (quantity) {
            case FalseColourQuantity::Radiosity: values[i] = luminance(B[i]); break;
            case FalseColourQuantity::Emission: values[i] = luminance(p.emission); break;
            case FalseColourQuantity::Irradiance: values[i] = irradianceLuminance(p, B[i]); break;
            case FalseColourQuantity::SkyViewFactor: break;
        }
    }
    return values;
}

double FalseColourRange::position(double value) const {
    if (std::isnan(value)) return value;
    double t;
    if (scale == FalseColourScale::Log)
        t = value > 0.0 ? (std::log(value) - std::log(min)) / (std::log(max) - std::log(min)) : 0.0;
    else
        t = (value - min) / (max - min);
    return std::clamp(t, 0.0, 1.0);
}

FalseColourRange falseColourRange(const std::vector<double>& values, FalseColourScale scale, std::optional<double> min,
                                  std::optional<double> max) {
    FalseColourRange r;
    r.scale = scale;
    r.automatic = !min || !max;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double v : values)
        if (std::isfinite(v) && (scale == FalseColourScale::Linear || v > 0.0)) lo = std::min(lo, v), hi = std::max(hi, v);
    r.min = min ? *min : lo;
    r.max = max ? *max : hi;
    const double floor = r.max * std::pow(10.0, -kFalseColourLogDecades);
    if (scale == FalseColourScale::Log && !min && std::isfinite(r.max) && r.min < floor) r.min = floor, r.floored = true;
    if (!std::isfinite(r.min) || !std::isfinite(r.max))
        throw Error(scale == FalseColourScale::Log ? "false colour: no positive value to show on a log scale"
                                                   : "false colour: no patch has a value to show");
    if (r.min == r.max && r.automatic) {  // a uniform quantity: a range around it
        const double pad = r.min != 0.0 ? 0.5 * std::abs(r.min) : 1.0;
        if (!min) r.min = scale == FalseColourScale::Log ? r.min / 2.0 : r.min - pad;
        if (!max) r.max = scale == FalseColourScale::Log ? r.max * 2.0 : r.max + pad;
    }
    if (!(r.min < r.max))
        throw Error("false colour: the range " + label(r.min) + " .. " + label(r.max) + " is empty (min must be below max)");
    if (scale == FalseColourScale::Log && !(r.min > 0.0))
        throw Error("false colour: a log scale needs a positive minimum, got " + label(r.min));
    return r;
}

std::string falseColourRangeNote(const FalseColourRange& range) {
    if (!range.automatic) return {};
    if (!range.floored) return "the values' extremes";
    char text[96];
    std::snprintf(text, sizeof text, "min = max/1e%g (%g decades); lower values show the bottom colour", kFalseColourLogDecades,
                  kFalseColourLogDecades);
    return text;
}

std::array<std::uint8_t, 3> viridis(double t) {
    const int k = std::isnan(t) ? 0 : int(std::lround(std::clamp(t, 0.0, 1.0) * 255.0));
    return {kViridis[k][0], kViridis[k][1], kViridis[k][2]};
}

std::array<std::uint8_t, 3> falseColourOf(double value, const FalseColourRange& range) {
    return std::isnan(value) ? kFalseColourNoData : viridis(range.position(value));
}

Rgb8Image renderFalseColour(const Scene& scene, const RayScene& rays, const std::vector<double>& values,
                            const FalseColourRange& range, FalseColourQuantity quantity, const RenderOptions& options) {
    if (values.size() != scene.size()) throw Error("false colour: values do not match the scene");
    const std::vector<PatchId> ids = renderPatchIds(scene, rays, options);
    Rgb8Image image;
    image.width = options.width + kFalseColourLegendWidth;
    image.height = std::max(options.height, 240);
    image.rgb.assign(std::size_t(image.width) * image.height * 3, 255);
    Canvas canvas(image);
    canvas.fill(0, 0, options.width, image.height, kFalseColourBackground);
    bool noData = false;
    for (int y = 0; y < options.height; ++y)
        for (int x = 0; x < options.width; ++x) {
            const PatchId id = ids[std::size_t(y) * options.width + x];
            std::array<std::uint8_t, 3> c = kFalseColourBackground;
            if (id == kBackFace) c = kFalseColourBackFace;
            else if (id != RayScene::kNoHit) {
                noData |= std::isnan(values[id]);
                c = falseColourOf(values[id], range);
            }
            canvas.fill(x, y, x + 1, y + 1, c);
        }

    // The legend: title and unit, the bar (max at the top), five values beside it, the scale.
    const std::array<std::uint8_t, 3> ink{0, 0, 0};
    // A title wider than the legend at twice the font's size ("sky view factor") takes two lines,
    // and the unit and the bar move down by one.
    const int left = options.width + 12;
    const std::vector<std::string> title = wrapText(falseColourTitle(quantity), (kFalseColourLegendWidth - 16) / 2);
    const int titleShift = 16 * (int(title.size()) - 1);
    const int barTop = 52 + titleShift, barBottom = image.height - (noData ? 64 : 36);
    const int barLeft = left, barRight = left + 28;
    for (std::size_t k = 0; k < title.size(); ++k) canvas.text(left, 8 + 16 * int(k), title[k], 2, ink);
    canvas.text(left, 30 + titleShift, falseColourUnit(quantity), 1, ink);
    for (int y = barTop; y < barBottom; ++y)
        canvas.fill(barLeft, y, barRight, y + 1, viridis(double(barBottom - 1 - y) / double(barBottom - 1 - barTop)));
    for (int k = 0; k <= 4; ++k) {
        const double t = k / 4.0;
        const double v = range.scale == FalseColourScale::Log ? range.min * std::pow(range.max / range.min, t)
                                                              : range.min + t * (range.max - range.min);
        const int y = barBottom - 1 - int(std::lround(t * (barBottom - 1 - barTop)));
        canvas.fill(barRight, y, barRight + 5, y + 1, ink);
        canvas.text(barRight + 8, y - 6, label(v), 2, ink);
    }
    char scaleText[48];
    if (range.floored) std::snprintf(scaleText, sizeof scaleText, "log scale, floor max/1e%g", kFalseColourLogDecades);
    else std::snprintf(scaleText, sizeof scaleText, "%s scale", falseColourScaleName(range.scale));
    canvas.text(left, barBottom + 10, scaleText, 1, ink);
    if (noData) {
        canvas.fill(left, barBottom + 30, left + 14, barBottom + 44, kFalseColourNoData);
        canvas.text(left + 20, barBottom + 33, "no data (rho = 0)", 1, ink);
    }
    return image;
}

}  // namespace hemirad
