// Anisotropic skies: the sky hemisphere cut into Tregenza's 145 cells (or Reinhart's finer
// subdivision), and the radiance of each cell under a sky model (uniform, the CIE overcast sky, the
// 15 CIE standard general skies, or Perez's all-weather sky from direct-normal and diffuse-horizontal
// irradiance), scaled so that the sky's irradiance on an unobstructed horizontal plane is the DHI.
#pragma once

#include "engine/math.hpp"

#include <string>
#include <vector>

namespace hemirad {

/// The sky hemisphere in cells: rows of equal altitude height, each cut in equal azimuth ranges, and
/// a cap at the zenith. Subdivision 1 is Tregenza's (1987) 145 cells: seven 12-degree rows of 30, 30,
/// 24, 24, 18, 12 and 6 cells and a 6-degree cap; subdivision m is Reinhart's (7m rows of m times as
/// many cells, 144 m^2 + 1 cells), as Radiance's gendaymtx lays them out. Angles in radians; azimuth
/// clockwise from north (east = pi/2).
struct SkyGrid {
    struct Cell {
        double altitudeLow = 0.0, altitudeHigh = 0.0, azimuthLow = 0.0, azimuthHigh = 0.0;
        /// Solid angle, sr: (sin altitudeHigh - sin altitudeLow) x (azimuthHigh - azimuthLow).
        double solidAngle() const;
    };
    int subdivision = 1;
    std::vector<Cell> cells;
    std::size_t size() const { return cells.size(); }
};

/// Subdivision 1..8 (1: Tregenza's 145 cells). Throws hemirad::Error outside that range.
SkyGrid skyGrid(int subdivision);

/// A direction in the sky's frame: x east, y north, z up (altitude and azimuth in radians).
Vec3 skyDirection(double altitude, double azimuth);

/// The directions that sample a cell: `samples` x `samples` parts equal in solid angle (equal steps in
/// sin(altitude) and azimuth), each at its centre in those coordinates, in the sky's frame. Each part
/// weighs solidAngle() / samples^2.
std::vector<Vec3> cellSamples(const SkyGrid::Cell& cell, int samples);

/// A direction from the sky's frame into a scene's: east = north x up (north made perpendicular to up).
Vec3 skyToScene(const Vec3& skyFrame, const Vec3& up, const Vec3& north);

/// The inverse: a scene direction in the sky's frame.
Vec3 sceneToSky(const Vec3& sceneFrame, const Vec3& up, const Vec3& north);

struct SkyModel {
    enum class Kind { Uniform, CieOvercast, CieStandard, Perez };
    Kind kind = Kind::Uniform;
    int cieType = 0;  ///< 1..15 for CieStandard (ISO 15469:2004 / CIE S 011/E:2003)
    std::string name() const;
};

/// "uniform", "cie-overcast", "cie:N" (N = 1..15) or "perez". Throws hemirad::Error naming the value.
SkyModel parseSkyModel(const std::string& text);

/// What a sky model needs of the hour: the direction toward the sun in the sky's frame (z up; below
/// the horizon is allowed: the models then take the sun at the horizon), the direct-normal and
/// diffuse-horizontal irradiance (W/m^2), and the day of the year (1..366) for the extraterrestrial
/// irradiance in Perez's sky brightness (0: the mean Sun-Earth distance).
struct SkyConditions {
    Vec3 toSun = Vec3(0, 0, 1);
    double dni = 0.0, dhi = 0.0;
    int dayOfYear = 0;
};

/// Perez's (1990) sky clearness epsilon and brightness Delta, the bin (0..7) of epsilon, and the
/// all-weather model's coefficients a..e (Perez, Seals & Michalsky 1993, Table 1 and eqns 6-8, with
/// the first bin's c and d by eqns 7-8). Sun zenith clamped to 90 degrees; air mass Kasten (1966);
/// epsilon kept at 12.01 or less and Delta within 0.01..0.6, the ranges the model was fitted over
/// (as Radiance's gendaylit does: twilight hours with diffuse light would otherwise get a sky of
/// negative luminance everywhere), and Delta at 0.2 or more for 1.065 < epsilon < 2.8 (as
/// Radiance's gendaymtx: a low sun's thin diffuse light there gives a gradation below 0 everywhere).
struct PerezParameters {
    double epsilon = 1.0, delta = 0.0;
    bool clamped = false;  ///< epsilon or Delta was outside those ranges
    int bin = 0;
    double a = 0.0, b = 0.0, c = 0.0, d = 0.0, e = 0.0;
};
PerezParameters perezParameters(const SkyConditions& conditions);

/// The model's radiance toward `direction` (sky frame, unit, z > 0) relative to an arbitrary scale
/// (the CIE and Perez gradation x indicatrix, the CIE overcast 1 + 2 sin(altitude)), never negative.
double relativeRadiance(const SkyModel& model, const PerezParameters& perez, const Vec3& toSun, const Vec3& direction);

/// Each cell's radiance, W/(m^2 sr): the model's mean over the cell's `samples` x `samples` parts,
/// scaled so that sum_k L_k H_k = DHI, H_k = sum over the cell's parts of (solid angle x sin(altitude)),
/// the cell's irradiance on an unobstructed horizontal plane per unit radiance. All zeros when the
/// DHI is 0. Where Perez's sky is dark everywhere (it can be at the edges of its fitted range, after
/// the clamps of perezParameters) the DHI comes from a uniform sky and `uniformFallback` (when given)
/// is set. Throws hemirad::Error for a DHI or DNI that is negative or not finite, or a sun direction
/// that is zero or not finite.
std::vector<double> skyRadiance(const SkyGrid& grid, int samples, const SkyModel& model, const SkyConditions& conditions,
                                bool* uniformFallback = nullptr);

/// H_k of skyRadiance: per cell, sr.
std::vector<double> horizontalWeights(const SkyGrid& grid, int samples);

}  // namespace hemirad
