// The sky view factor beside a solve and as a picture (issue 37): solve --sky-view's CSV column and
// PLY face property against `hemirad sky-view`, the outputs without the flag unchanged, and render
// --false-color sky_view_factor's picture, legend and range.
#include "support.hpp"

#include "render/false_colour.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <set>
#include <sstream>

#include <stb/stb_image.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// A street canyon 2 wide, 4 long, 2 high (z up): a floor facing up, a diffuse wall at x = 0 that
/// emits, and a mirror wall (s = 0.9) at x = 2, both facing the street. The floor sees sky straight
/// up and more of it in the mirror: direct and through mirrors both count.
std::string canyon(const std::filesystem::path& dir) {
    writeFile(dir / "canyon.mtl",
              "newmtl ground\nKd 0.3 0.3 0.3\n"
              "newmtl wall\nKd 0.5 0.5 0.5\nKe 1 1 1\n"
              "newmtl mirror\nKd 0 0 0\nKs 0.9 0.9 0.9\nillum 3\n");
    return writeFile(dir / "canyon.obj",
                     "mtllib canyon.mtl\n"
                     "v 0 0 0\nv 2 0 0\nv 2 4 0\nv 0 4 0\n"
                     "v 0 0 2\nv 2 0 2\nv 2 4 2\nv 0 4 2\n"
                     "o floor\nusemtl ground\nf 1 2 3 4\n"
                     "o west\nusemtl wall\nf 1 4 8 5\n"
                     "o east\nusemtl mirror\nf 2 6 7 3\n");
}

/// The shell command that runs hemirad with `arguments`, its standard error with its output.
std::string hemiradCommand(const std::string& arguments) { return std::string(HEMIRAD_BINARY) + " " + arguments + " 2>&1"; }

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) out.push_back(cell);
    return out;
}

/// Column `column` of every data row of a CSV (the header skipped).
std::vector<double> column(const std::string& csv, std::size_t column) {
    std::vector<double> values;
    const std::vector<std::string> rows = lines(csv);
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const std::vector<std::string> c = cells(rows[k]);
        REQUIRE(c.size() > column);
        values.push_back(std::stod(c[column]));
    }
    return values;
}

/// The float property `name` of every face of a binary PLY as writeRadiosityPly writes it (vertex
/// x y z float, red green blue uchar, B_r B_g B_b float; face: uchar count, int indices, then floats).
std::vector<float> facePropertyOfPly(const std::string& ply, const std::string& name) {
    const std::size_t end = ply.find("end_header\n");
    REQUIRE(end != std::string::npos);
    const std::string header = ply.substr(0, end);
    REQUIRE(header.find("property list uchar int vertex_indices\nproperty float " + name + "\n") != std::string::npos);
    std::size_t vertices = 0, faces = 0;
    REQUIRE(std::sscanf(header.c_str() + header.find("element vertex "), "element vertex %zu", &vertices) == 1);
    REQUIRE(std::sscanf(header.c_str() + header.find("element face "), "element face %zu", &faces) == 1);
    std::size_t at = end + std::strlen("end_header\n") + vertices * (3 * 4 + 3 + 3 * 4);
    std::vector<float> values;
    for (std::size_t f = 0; f < faces; ++f) {
        REQUIRE(at < ply.size());
        const auto count = std::uint8_t(ply[at]);
        at += 1 + 4 * std::size_t(count);
        REQUIRE(at + 4 <= ply.size());
        float v = 0;
        std::memcpy(&v, ply.data() + at, 4);
        values.push_back(v);
        at += 4;
    }
    CHECK(at == ply.size());
    return values;
}

/// `ply` with the face property `name` (a float after the indices, facePropertyOfPly) taken out.
std::string withoutFaceProperty(const std::string& ply, const std::string& name) {
    const std::string line = "property float " + name + "\n";
    const std::size_t property = ply.find(line), end = ply.find("end_header\n") + std::strlen("end_header\n");
    REQUIRE(property != std::string::npos);
    std::size_t vertices = 0, faces = 0;
    REQUIRE(std::sscanf(ply.c_str() + ply.find("element vertex "), "element vertex %zu", &vertices) == 1);
    REQUIRE(std::sscanf(ply.c_str() + ply.find("element face "), "element face %zu", &faces) == 1);
    std::string out = ply.substr(0, property) + ply.substr(property + line.size(), end - property - line.size());
    std::size_t at = end + vertices * (3 * 4 + 3 + 3 * 4);
    out += ply.substr(end, at - end);
    for (std::size_t f = 0; f < faces && at < ply.size(); ++f) {
        const std::size_t indices = 1 + 4 * std::size_t(std::uint8_t(ply[at]));
        out += ply.substr(at, indices);
        at += indices + 4;
    }
    return out;
}

}  // namespace

TEST_CASE("solve --sky-view adds sky-view's total per patch as a last CSV column, and without the flag the CSV is unchanged") {
    const auto dir = tempDir("solve-sky-view");
    const std::string scene = canyon(dir) + " --subdivide 1";
    const std::string svf = (dir / "svf.csv").string(), plain = (dir / "B.csv").string(), sky = (dir / "B_sky.csv").string();
    CommandResult r = runCommand(hemiradCommand("sky-view " + scene + " -o " + svf));
    REQUIRE_MESSAGE(r.status == 0, r.output);
    r = runCommand(hemiradCommand("solve " + scene + " -o " + plain));
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(r.output.find("sky view factor") == std::string::npos);  // no second F without the flag
    r = runCommand(hemiradCommand("solve " + scene + " --sky-view -o " + sky));
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("sky view factor (hemisphere") != std::string::npos);
    CHECK(r.output.find("(with each patch's sky_view_factor)") != std::string::npos);

    const std::vector<std::string> without = lines(readText(plain)), with = lines(readText(sky));
    REQUIRE(without.size() == with.size());
    REQUIRE(without.size() > 10);  // subdivided: several patches per wall
    CHECK(without[0] == "patch,area,E_r,E_g,E_b,rho_r,rho_g,rho_b,specular,B_r,B_g,B_b");
    CHECK(with[0] == without[0] + ",sky_view_factor");
    // Every row is the row without the flag plus one cell.
    for (std::size_t k = 0; k < with.size(); ++k) {
        CAPTURE(k);
        CHECK(with[k].substr(0, with[k].rfind(',')) == without[k]);
        CHECK(cells(with[k]).size() == 13);
    }

    // The column is sky-view's sky_view_factor (direct + through mirrors) to the CSV's 9 digits.
    const std::string svfText = readText(svf);
    const std::vector<double> expected = column(svfText, 3), direct = column(svfText, 4), mirrored = column(svfText, 5);
    const std::vector<double> got = column(readText(sky), 12);
    REQUIRE(got.size() == expected.size());
    double largestMirrored = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        CAPTURE(i);
        CHECK(std::abs(got[i] - expected[i]) <= 1e-8 * std::max(1.0, std::abs(expected[i])));
        CHECK(got[i] >= 0.0);
        CHECK(got[i] <= 1.0 + 1e-9);
        largestMirrored = std::max(largestMirrored, mirrored[i]);
        CHECK(std::abs(expected[i] - (direct[i] + mirrored[i])) <= 1e-12);
    }
    // The scene tells the total from the direct part alone: the floor sees sky in the mirror.
    CHECK(largestMirrored > 0.05);
}

TEST_CASE("solve --sky-view -o B.ply gives each face a float sky_view_factor, and without the flag the PLY is unchanged") {
    const auto dir = tempDir("solve-sky-view-ply");
    const std::string scene = canyon(dir) + " --subdivide 1";
    const std::string csv = (dir / "B.csv").string(), plain = (dir / "B.ply").string(), sky = (dir / "B_sky.ply").string();
    CommandResult r = runCommand(hemiradCommand("solve " + scene + " --sky-view -o " + csv));
    REQUIRE_MESSAGE(r.status == 0, r.output);
    r = runCommand(hemiradCommand("solve " + scene + " --exposure 1 -o " + plain));
    REQUIRE_MESSAGE(r.status == 0, r.output);
    r = runCommand(hemiradCommand("solve " + scene + " --exposure 1 --sky-view -o " + sky));
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const std::string without = readText(plain), with = readText(sky);
    CHECK(without.find("sky_view_factor") == std::string::npos);
    const std::vector<float> faces = facePropertyOfPly(with, "sky_view_factor");
    const std::vector<double> expected = column(readText(csv), 12);
    REQUIRE(faces.size() == expected.size());
    for (std::size_t i = 0; i < faces.size(); ++i) {
        CAPTURE(i);
        CHECK(faces[i] == doctest::Approx(expected[i]).epsilon(1e-6));
    }
    // Only the header line and the face values were added: taken out again, the bytes are the PLY without the flag.
    CHECK(withoutFaceProperty(with, "sky_view_factor") == without);
}

TEST_CASE("render --false-color sky_view_factor: no solve, a unitless legend on 0..1, the patches in sky-view's colours") {
    const auto dir = tempDir("render-sky-view");
    // Nothing emits here: B, H and E would have no map, the sky view factor still has one.
    const std::string obj = canyon(dir);
    writeFile(dir / "canyon.mtl", "newmtl ground\nKd 0.3 0.3 0.3\nnewmtl wall\nKd 0.5 0.5 0.5\n"
                                  "newmtl mirror\nKd 0 0 0\nKs 0.9 0.9 0.9\nillum 3\n");
    const std::string scene = obj + " --subdivide 1";
    const std::string svf = (dir / "svf.csv").string(), png = (dir / "svf.png").string();
    CommandResult r = runCommand(hemiradCommand("sky-view " + scene + " -o " + svf));
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const std::vector<double> sky = column(readText(svf), 3);
    const std::string camera = " --camera 1,-6,7,1,2,0,50 --size 160x160";
    r = runCommand(hemiradCommand("render " + scene + camera + " --false-color sky_view_factor -o " + png));
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("solve") == std::string::npos);
    const std::size_t at = r.output.find("false colour: ");
    REQUIRE(at != std::string::npos);
    const std::string report = r.output.substr(at, r.output.find('\n', at) - at);
    CHECK(report.find("false colour: sky view factor (unitless, 0..1), linear scale 0 .. 1") == 0);
    CHECK(report.find("W/m^2") == std::string::npos);

    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load(png.c_str(), &width, &height, &channels, 3);
    REQUIRE(data != nullptr);
    CHECK(width == 160 + kFalseColourLegendWidth);
    // Every coloured pixel is the colour of some patch's sky view factor on 0..1, and there are several.
    FalseColourRange range;
    range.min = 0.0, range.max = 1.0;
    std::set<std::array<std::uint8_t, 3>> allowed;
    for (double v : sky) allowed.insert(falseColourOf(v, range));
    std::set<std::array<std::uint8_t, 3>> seen;
    std::size_t coloured = 0, unmatched = 0;
    for (int y = 0; y < 160; ++y)
        for (int x = 0; x < 160; ++x) {
            const unsigned char* p = data + 3 * (std::size_t(y) * width + x);
            const std::array<std::uint8_t, 3> c{p[0], p[1], p[2]};
            if (c == kFalseColourBackground || c == kFalseColourBackFace) continue;
            ++coloured;
            unmatched += !allowed.count(c);
            seen.insert(c);
        }
    // The legend: the title "sky view factor" on two lines, inside the strip (none of its ink at the
    // image's right edge), and the bar from 1 at its top, one title line lower than for B, H or E.
    auto rgb = [&](int x, int y) {
        const unsigned char* p = data + 3 * (std::size_t(y) * width + x);
        return std::array<std::uint8_t, 3>{p[0], p[1], p[2]};
    };
    const std::array<std::uint8_t, 3> ink{0, 0, 0}, paper{255, 255, 255};
    std::size_t titleInk = 0, edgeInk = 0;
    for (int y = 0; y < 30; ++y) {
        for (int x = 160; x < width; ++x) titleInk += rgb(x, y) == ink;
        edgeInk += rgb(width - 1, y) == ink || rgb(width - 2, y) == ink;
    }
    CHECK(titleInk > 100);
    CHECK(edgeInk == 0);
    const int barX = 160 + 12 + 14;
    CHECK(rgb(barX, 67) == paper);
    CHECK(rgb(barX, 68) == viridis(1.0));
    stbi_image_free(data);
    CHECK(coloured > 1500);  // 1948 of the 160 x 160: the canyon from above and in front
    CHECK(unmatched == 0);
    CHECK(seen.size() >= 3);

    // On a log scale the automatic minimum is the smallest positive value; the maximum stays 1.
    r = runCommand(hemiradCommand("render " + scene + camera + " --false-color sky_view_factor --scale log -o " + png));
    REQUIRE_MESSAGE(r.status == 0, r.output);
    double lo = 0, hi = 0;
    const std::size_t log = r.output.find("log scale ");
    REQUIRE(log != std::string::npos);
    REQUIRE(std::sscanf(r.output.c_str() + log, "log scale %lf .. %lf", &lo, &hi) == 2);
    CHECK(lo > 0.0);
    CHECK(lo < hi);
    CHECK(hi == 1.0);
    double smallest = 1.0;
    for (double v : sky)
        if (v > 0.0) smallest = std::min(smallest, v);
    CHECK(lo == doctest::Approx(std::max(smallest, 1e-4)).epsilon(1e-6));

    // A stored F or the solver's flags mean nothing without a solve: refused, nothing written.
    std::filesystem::remove(png);
    r = runCommand(hemiradCommand("render " + scene + " --false-color sky_view_factor --ff F.hff -o " + png));
    CHECK(r.status == 2);
    CHECK(r.output.find("--ff does not apply with --false-color sky_view_factor") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(png));
}

TEST_CASE("--sky-view is solve's, and needs -o") {
    const auto dir = tempDir("sky-view-usage");
    const std::string scene = canyon(dir);
    CommandResult r = runCommand(hemiradCommand("solve " + scene + " --sky-view --objects " + (dir / "O.csv").string()));
    CHECK(r.status == 2);
    CHECK(r.output.find("--sky-view adds a column to -o B.csv (a face property to B.ply): it needs -o") != std::string::npos);
    r = runCommand(hemiradCommand("render " + scene + " --sky-view -o " + (dir / "x.png").string()));
    CHECK(r.status == 2);
    CHECK(r.output.find("option '--sky-view' does not apply to 'render'") != std::string::npos);
}
