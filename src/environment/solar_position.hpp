// Where the sun is: the Astronomical Almanac's low-precision algorithm as published by Michalsky
// (1988, "The Astronomical Almanac's algorithm for approximate solar position (1950-2050)", Solar
// Energy 40(3)), within 0.01 degrees for 1950-2050, with its refraction correction; and the
// direction to the sun in a scene's frame.
#pragma once

#include "engine/math.hpp"

#include <string>

namespace hemirad {

struct SolarPosition {
    double elevation = 0.0;  ///< degrees above the horizon, refraction included
    double azimuth = 0.0;    ///< degrees clockwise from north (east = 90)
};

/// The sun's position at `utc` (a time string "YYYY-MM-DDTHH:MM[:SS]" with an optional offset
/// "Z", "+HH:MM" or "-HH:MM"; without one it is UTC), latitude and longitude in degrees (north and
/// east positive). Throws hemirad::Error naming the value for a malformed time, a date outside
/// 1950-2050 or coordinates out of range.
SolarPosition solarPosition(const std::string& time, double latitude, double longitude);

/// The unit vector toward the sun in a scene whose up and north directions are given (any length;
/// north is made perpendicular to up): east = north x up.
Vec3 sunDirection(const SolarPosition& position, const Vec3& up, const Vec3& north);

}  // namespace hemirad
