// Michalsky (1988): mean longitude and anomaly from the Julian date, the ecliptic longitude,
// right ascension and declination, Greenwich and local mean sidereal time, the hour angle, then
// elevation and azimuth, and the refraction correction.
#include "environment/solar_position.hpp"

#include "engine/error.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace hemirad {
namespace {

constexpr double kDegree = kPi / 180.0;

double wrap(double x, double period) {
    x = std::fmod(x, period);
    return x < 0.0 ? x + period : x;
}

/// Days from 2000-01-01 12:00 UT (J2000.0) for a proleptic Gregorian civil date and UT hour.
double daysFromJ2000(int year, int month, int day, double hour) {
    // Julian day number (Fliegel & Van Flandern 1968), then the fraction from noon.
    const int a = (14 - month) / 12, y = year + 4800 - a, m = month + 12 * a - 3;
    const long jdn = day + (153 * m + 2) / 5 + 365L * y + y / 4 - y / 100 + y / 400 - 32045;
    return double(jdn - 2451545L) + (hour - 12.0) / 24.0;
}

}  // namespace

SolarPosition solarPosition(const std::string& time, double latitude, double longitude) {
    int year = 0, month = 0, day = 0, hh = 0, mm = 0, consumed = 0;
    double ss = 0.0;
    if (std::sscanf(time.c_str(), "%4d-%2d-%2dT%2d:%2d%n", &year, &month, &day, &hh, &mm, &consumed) != 5)
        throw Error("sun: time '" + time + "' is not YYYY-MM-DDTHH:MM[:SS][Z|+HH:MM|-HH:MM]");
    std::string rest = time.substr(std::size_t(consumed));
    if (!rest.empty() && rest[0] == ':') {
        int more = 0;
        if (std::sscanf(rest.c_str(), ":%lf%n", &ss, &more) != 1 || !(ss >= 0.0 && ss < 61.0))
            throw Error("sun: time '" + time + "' has malformed seconds");
        rest = rest.substr(std::size_t(more));
    }
    double offset = 0.0;
    if (rest == "Z" || rest.empty()) {
    } else {
        int oh = 0, om = 0;
        char sign = 0;
        if (std::sscanf(rest.c_str(), "%c%2d:%2d", &sign, &oh, &om) != 3 || (sign != '+' && sign != '-') || oh > 14 || om > 59)
            throw Error("sun: time '" + time + "' has a malformed offset '" + rest + "' (Z, +HH:MM or -HH:MM)");
        offset = (sign == '-' ? -1.0 : 1.0) * (oh + om / 60.0);
    }
    if (year < 1950 || year > 2050 || month < 1 || month > 12 || day < 1 || day > 31 || hh > 23 || mm > 59)
        throw Error("sun: time '" + time + "' is outside 1950-2050 (the algorithm's range) or not a date and time");
    if (!(std::abs(latitude) <= 90.0) || !(std::abs(longitude) <= 180.0)) {
        std::ostringstream msg;
        msg << "sun: latitude " << latitude << " and longitude " << longitude << " must be within [-90, 90] and [-180, 180]";
        throw Error(msg.str());
    }
    const double hourUT = hh + mm / 60.0 + ss / 3600.0 - offset;
    const double n = daysFromJ2000(year, month, day, hourUT);
    const double L = wrap(280.460 + 0.9856474 * n, 360.0);
    const double g = wrap(357.528 + 0.9856003 * n, 360.0) * kDegree;
    const double lambda = (L + 1.915 * std::sin(g) + 0.020 * std::sin(2.0 * g)) * kDegree;
    const double epsilon = (23.439 - 0.0000004 * n) * kDegree;
    const double ra = std::atan2(std::cos(epsilon) * std::sin(lambda), std::cos(lambda));
    const double dec = std::asin(std::sin(epsilon) * std::sin(lambda));
    // Greenwich mean sidereal time in hours (n counts days from noon, so the UT hour is taken from
    // midnight: n + 0.5 - hour/24 whole days).
    const double midnight = std::floor(n + 0.5) - 0.5;
    const double gmst = wrap(6.697375 + 0.0657098242 * midnight + 1.00273790935 * (hourUT - 24.0 * std::floor(hourUT / 24.0)), 24.0);
    const double lmst = wrap(gmst + longitude / 15.0, 24.0);
    double ha = lmst * 15.0 * kDegree - ra;
    ha = std::remainder(ha, 2.0 * kPi);
    const double lat = latitude * kDegree;
    const double sinEl = std::sin(dec) * std::sin(lat) + std::cos(dec) * std::cos(lat) * std::cos(ha);
    double el = std::asin(std::max(-1.0, std::min(1.0, sinEl))) / kDegree;
    const double az = std::atan2(-std::cos(dec) * std::sin(ha), std::sin(dec) * std::cos(lat) - std::cos(dec) * std::sin(lat) * std::cos(ha));
    if (el > -0.56)
        el += 3.51561 * (0.1594 + 0.0196 * el + 0.00002 * el * el) / (1.0 + 0.505 * el + 0.0845 * el * el);
    return {std::min(el, 90.0), wrap(az / kDegree, 360.0)};
}

Vec3 sunDirection(const SolarPosition& position, const Vec3& upGiven, const Vec3& northGiven) {
    const Vec3 up = upGiven.normalized();
    const Vec3 north = (northGiven - northGiven.dot(up) * up).normalized();
    if (!up.allFinite() || !north.allFinite()) throw Error("sun: up and north must be non-zero and not parallel");
    const Vec3 east = north.cross(up);
    const double el = position.elevation * kDegree, az = position.azimuth * kDegree;
    return std::cos(el) * (std::sin(az) * east + std::cos(az) * north) + std::sin(el) * up;
}

}  // namespace hemirad
