// False-colour images: per-patch values (B, H, E), ranges and scales, the colour map, and
// `hemirad render --false-color` end to end against the CSV of `hemirad solve`.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/tone_map.hpp"
#include "render/false_colour.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <set>
#include <sstream>

#include <stb/stb_image.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// One number per line of `hemirad solve`'s CSV (patch,area,E_r,E_g,E_b,rho_r,rho_g,rho_b,specular,B_r,B_g,B_b):
/// the irradiance H = Y((B - E) / rho), NaN where a rho is 0.
std::vector<double> irradianceFromCsv(const std::string& csv) {
    std::istringstream in(csv);
    std::string line;
    std::getline(in, line);  // header
    std::vector<double> H;
    while (std::getline(in, line)) {
        std::vector<double> f;
        std::istringstream fields(line);
        for (std::string cell; std::getline(fields, cell, ',');) f.push_back(std::stod(cell));
        REQUIRE(f.size() == 12);
        const Rgb E(f[2], f[3], f[4]), rho(f[5], f[6], f[7]), B(f[9], f[10], f[11]);
        H.push_back((rho > 0.0).all() ? luminance(Rgb((B - E) / rho)) : std::nan(""));
    }
    return H;
}

std::array<std::uint8_t, 3> pixel(const unsigned char* rgb, int width, int x, int y) {
    const unsigned char* p = rgb + 3 * (std::size_t(y) * width + x);
    return {p[0], p[1], p[2]};
}

/// The colours of the patches in the picture's top-left `size` x `size` pixels: background, back
/// faces and no data left out.
std::vector<std::array<std::uint8_t, 3>> patchColours(const unsigned char* rgb, int width, int size) {
    std::vector<std::array<std::uint8_t, 3>> colours;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const auto c = pixel(rgb, width, x, y);
            if (c != kFalseColourBackground && c != kFalseColourBackFace && c != kFalseColourNoData) colours.push_back(c);
        }
    return colours;
}

}  // namespace

TEST_CASE("False colour: values per quantity, automatic and given ranges, linear and log positions") {
    SceneBuilder b;
    b.rectangle(2, 0, 0, 1, 0, 1, true);
    b.rectangle(2, 1, 0, 1, 0, 1, false);
    b.rectangle(1, 0, 0, 1, 0, 1, true);
    b.scene.patches[0].emission = Rgb(10, 10, 10);
    b.scene.patches[1].rho = Rgb(0.5, 0.25, 0.5);
    b.scene.patches[2].rho = Rgb(0.5, 0.0, 0.5);  // no green reflectance: H unknown
    const std::vector<Rgb> B = {Rgb(10.5, 10.5, 10.5), Rgb(1, 1, 1), Rgb(2, 2, 2)};
    const std::vector<double> H = falseColourValues(b.scene, B, FalseColourQuantity::Irradiance);
    CHECK(H[0] == doctest::Approx(luminance(Rgb((B[0] - Rgb::Constant(10)) / b.scene.patches[0].rho))));
    CHECK(H[1] == doctest::Approx(0.2126 * 2 + 0.7152 * 4 + 0.0722 * 2));
    CHECK(std::isnan(H[2]));
    CHECK(falseColourValues(b.scene, B, FalseColourQuantity::Radiosity)[1] == doctest::Approx(1.0));
    CHECK(falseColourValues(b.scene, B, FalseColourQuantity::Emission)[0] == doctest::Approx(10.0));

    const FalseColourRange automatic = falseColourRange(H, FalseColourScale::Linear, {}, {});
    CHECK(automatic.min == doctest::Approx(std::min(H[0], H[1])));
    CHECK(automatic.max == doctest::Approx(std::max(H[0], H[1])));
    CHECK(automatic.automatic);
    CHECK(automatic.position(automatic.max) == 1.0);
    CHECK(automatic.position(automatic.min) == 0.0);
    CHECK(std::isnan(automatic.position(H[2])));
    const FalseColourRange log = falseColourRange({0.01, 1.0, 0.0, -3.0}, FalseColourScale::Log, {}, {});
    CHECK(log.min == doctest::Approx(0.01));  // non-positive values cannot sit on a log scale
    CHECK(log.position(0.1) == doctest::Approx(0.5));
    CHECK(log.position(0.0) == 0.0);
    const FalseColourRange given = falseColourRange(H, FalseColourScale::Linear, 0.0, 8.0);
    CHECK(given.position(2.0) == doctest::Approx(0.25));
    CHECK(given.position(100.0) == 1.0);
    CHECK_FALSE(given.automatic);
    CHECK_THROWS_WITH_AS(falseColourRange({-1.0, 0.0}, FalseColourScale::Log, {}, {}),
                         doctest::Contains("no positive value to show on a log scale"), Error);
    CHECK_THROWS_WITH_AS(falseColourRange(H, FalseColourScale::Linear, 5.0, 5.0), doctest::Contains("is empty"), Error);
    CHECK_FALSE(log.floored);
    CHECK(falseColourRangeNote(log) == "the values' extremes");
    CHECK(falseColourRangeNote(given).empty());
        // A uniform quantity still gets a range (and a colour) around its value.
    const FalseColourRange flat = falseColourRange({2.0, 2.0}, FalseColourScale::Linear, {}, {});
    CHECK(flat.min < 2.0);
    CHECK(flat.max > 2.0);
    // The map: viridis' ends and middle.
    CHECK(viridis(0.0) == std::array<std::uint8_t, 3>{68, 1, 84});
    CHECK(viridis(1.0) == std::array<std::uint8_t, 3>{253, 231, 37});
    CHECK(viridis(0.5) == std::array<std::uint8_t, 3>{33, 145, 140});
}

TEST_CASE("hemirad render --false-color irradiance: colours, range and legend come from the solved values") {
    const auto dir = tempDir("false-colour");
    const std::string scene = sourcePath("scenes/cornell_box.obj"), F = (dir / "F.hff").string();
    const std::string csvPath = (dir / "B.csv").string(), png = (dir / "H.png").string();
    const std::string hemirad = std::string(HEMIRAD_BINARY) + " ";
    CommandResult r = runCommand(hemirad + "solve " + scene + " --subdivide 150 --samples 512 --ff " + F + " -o " + csvPath + " 2>&1");
    REQUIRE(r.status == 0);
    // The settings F was made with (--samples): --ff refuses an F made with others.
    r = runCommand(hemirad + "render " + scene + " --subdivide 150 --samples 512 --ff " + F +
                   " --false-color irradiance --size 200x200 -o " + png + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const std::vector<double> H = irradianceFromCsv(readText(csvPath));
    double lo = 1e300, hi = -1e300;
    bool noData = false;
    for (double h : H) {
        if (std::isnan(h)) noData = true;
        else lo = std::min(lo, h), hi = std::max(hi, h);
    }
    // The report's range is the CSV's extremes.
    double reportedMin = 0, reportedMax = 0;
    const std::size_t at = r.output.find("linear scale ");
    REQUIRE(at != std::string::npos);
    REQUIRE(std::sscanf(r.output.c_str() + at, "linear scale %lf .. %lf", &reportedMin, &reportedMax) == 2);
    CHECK(reportedMin == doctest::Approx(lo).epsilon(1e-6));
    CHECK(reportedMax == doctest::Approx(hi).epsilon(1e-6));

    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load(png.c_str(), &width, &height, &channels, 3);
    REQUIRE(data != nullptr);
    CHECK(width == 200 + kFalseColourLegendWidth);
    CHECK(height == 240);  // the legend needs 240 rows
    // Every coloured pixel of the picture is the colour of some patch's value (the map's 256 steps).
    FalseColourRange range;
    range.min = lo, range.max = hi;
    std::set<int> steps;
    for (double h : H)
        if (!std::isnan(h)) steps.insert(int(std::lround(range.position(h) * 255.0)));
    const auto coloured = patchColours(data, width, 200);
    std::size_t unmatched = 0;
    for (const auto& c : coloured) {
        bool found = false;
        for (int k : steps) found |= viridis(k / 255.0) == c;
        unmatched += !found;
    }
    CHECK(coloured.size() > 30000);
    CHECK(unmatched == 0);
    // The legend's bar runs from the map's top colour (max) down to its bottom one (min).
    const int barX = 200 + 12 + 14;
    CHECK(pixel(data, width, barX, 52) == viridis(1.0));
    int bottom = 52;
    while (bottom + 1 < height && pixel(data, width, barX, bottom + 1) != std::array<std::uint8_t, 3>{255, 255, 255}) ++bottom;
    CHECK(pixel(data, width, barX, bottom) == viridis(0.0));
    CHECK(bottom == height - (noData ? 64 : 36) - 1);
    // Its five values are drawn in ink right of the bar.
    std::size_t ink = 0;
    for (int y = 40; y < bottom + 8; ++y)
        for (int x = barX + 20; x < width; ++x) ink += pixel(data, width, x, y) == std::array<std::uint8_t, 3>{0, 0, 0};
    CHECK(ink > 200);
    stbi_image_free(data);

    // Flags that only make sense together, or not with a false-colour map, are usage errors.
    r = runCommand(hemirad + "render " + scene + " --scale log -o " + png + " 2>&1");
    CHECK(r.status == 2);
    CHECK(r.output.find("--scale needs --false-color QUANTITY") != std::string::npos);
    r = runCommand(hemirad + "render " + scene + " --false-color irradiance --exposure 2 -o " + png + " 2>&1");
    CHECK(r.status == 2);
    CHECK(r.output.find("--exposure does not apply with --false-color") != std::string::npos);
    r = runCommand(hemirad + "render " + scene + " --false-color lux -o " + png + " 2>&1");
    CHECK(r.status == 2);
    CHECK(r.output.find("--false-color expects radiosity, irradiance, emission or sky_view_factor, got 'lux'") != std::string::npos);
}

TEST_CASE("False colour: the sky view factor is unitless on 0..1 by default, and not made from B") {
    CHECK(parseFalseColourQuantity("sky_view_factor") == FalseColourQuantity::SkyViewFactor);
    CHECK(falseColourTitle(FalseColourQuantity::SkyViewFactor) == "sky view factor");
    CHECK(falseColourUnit(FalseColourQuantity::SkyViewFactor) == "unitless, 0..1");
    CHECK(falseColourUnit(FalseColourQuantity::Irradiance) == "W/m^2, luminance Y");
    const auto linear = falseColourDefaultRange(FalseColourQuantity::SkyViewFactor, FalseColourScale::Linear);
    CHECK(linear.first == 0.0);
    CHECK(linear.second == 1.0);
    const auto log = falseColourDefaultRange(FalseColourQuantity::SkyViewFactor, FalseColourScale::Log);
    CHECK_FALSE(log.first.has_value());  // log: the values' smallest, 0 has no place on it
    CHECK(log.second == 1.0);
    const auto radiosity = falseColourDefaultRange(FalseColourQuantity::Radiosity, FalseColourScale::Linear);
    CHECK_FALSE(radiosity.first.has_value());
    CHECK_FALSE(radiosity.second.has_value());
    SceneBuilder b;
    b.rectangle(2, 0, 0, 1, 0, 1, true);
    b.scene.patches[0].emission = Rgb(1, 1, 1);
    CHECK_THROWS_WITH_AS(falseColourValues(b.scene, {Rgb(1, 1, 1)}, FalseColourQuantity::SkyViewFactor),
                         doctest::Contains("comes from skyViewFactors"), Error);
}

TEST_CASE("False colour: an automatic log range spans at most 4 decades, a given minimum is kept") {
    // The Cornell box's irradiance: 1.07 under the light, round-off (1.76e-19) on the floor under a block.
    const std::vector<double> H = {1.76e-19, 2e-3, 0.3, 1.07, 0.0};
    const FalseColourRange log = falseColourRange(H, FalseColourScale::Log, {}, {});
    CHECK(log.max == doctest::Approx(1.07));
    CHECK(log.min == doctest::Approx(1.07e-4));
    CHECK(log.floored);
    CHECK(falseColourRangeNote(log).find("max/1e4") != std::string::npos);
    CHECK(log.position(2e-3) == doctest::Approx(std::log10(2e-3 / 1.07e-4) / 4.0));
    CHECK(log.position(1.76e-19) == 0.0);  // below the floor: the bottom colour
    const FalseColourRange given = falseColourRange(H, FalseColourScale::Log, 1e-20, {});
    CHECK(given.min == 1e-20);
    CHECK_FALSE(given.floored);
    CHECK_FALSE(falseColourRange(H, FalseColourScale::Linear, {}, {}).floored);  // linear: the extremes
}

TEST_CASE("False colour refuses a scene where nothing emits: every value would be 0") {
    SceneBuilder b;
    b.rectangle(2, 0, 0, 1, 0, 1, true);
    b.rectangle(2, 1, 0, 1, 0, 1, false);
    const std::vector<Rgb> B(2, Rgb::Zero());
    CHECK_THROWS_WITH_AS(falseColourValues(b.scene, B, FalseColourQuantity::Irradiance), doctest::Contains("nothing emits"), Error);
    CHECK_THROWS_WITH_AS(falseColourValues(b.scene, B, FalseColourQuantity::Emission), doctest::Contains("no data"), Error);
}

TEST_CASE("hemirad render --false-color irradiance --scale log: the floor under the blocks does not squeeze the map") {
    const auto dir = tempDir("false-colour-log");
    const std::string png = (dir / "H.png").string();
    const CommandResult r = runCommand(std::string(HEMIRAD_BINARY) + " render " + sourcePath("scenes/cornell_box.obj") +
                                       " --subdivide 30 --false-color irradiance --scale log --size 100x100 -o " + png +
                                       " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    double lo = 0, hi = 0;
    const std::size_t at = r.output.find("log scale ");
    REQUIRE(at != std::string::npos);
    REQUIRE(std::sscanf(r.output.c_str() + at, "log scale %lf .. %lf", &lo, &hi) == 2);
    CHECK(lo == doctest::Approx(hi * 1e-4).epsilon(1e-6));  // without the floor: 1.0e-5, a patch under a block
    CHECK(r.output.find("min = max/1e4 (4 decades)") != std::string::npos);
    // The picture spreads over the map: a tenth of its coloured pixels or more in the lower three
    // quarters of the map (H < 0.1 here: the blocks, the shaded floor).
    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load(png.c_str(), &width, &height, &channels, 3);
    REQUIRE(data != nullptr);
    const auto coloured = patchColours(data, width, 100);
    stbi_image_free(data);
    std::size_t low = 0;
    for (const auto& c : coloured)
        for (int k = 0; k < 192; ++k)
            if (viridis(k / 255.0) == c) {
                ++low;
                break;
            }
    CHECK(coloured.size() > 5000);
    CHECK(double(low) > 0.1 * double(coloured.size()));
}
