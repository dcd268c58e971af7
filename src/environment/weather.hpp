// Weather for a year of hours: EnergyPlus EPW files (LOCATION header, then hourly rows whose 15th
// and 16th fields are the direct-normal and diffuse-horizontal irradiance, Wh/m^2 over the hour
// ending at the row's hour; EnergyPlus "Auxiliary Programs", the EPW data dictionary).
#pragma once

#include <string>
#include <vector>

namespace hemirad {

struct WeatherHour {
    int year = 0, month = 0, day = 0, hour = 0;  ///< hour 1..24: the interval (hour - 1, hour] local standard time
    double dni = 0.0, dhi = 0.0;                 ///< W/m^2 (the hour's Wh/m^2)
    int line = 0;                                ///< where it was read
};

struct Weather {
    std::string place;                 ///< city, state, country from LOCATION
    double latitude = 0.0, longitude = 0.0, timeZone = 0.0;  ///< degrees north / east; hours from UTC
    std::vector<WeatherHour> hours;
};

/// Reads an EPW file. Throws hemirad::Error naming the file and line for a missing or malformed
/// LOCATION, a data row with too few fields, a field that is not a number, a date or hour out of
/// range, or an irradiance that is negative or marked missing (9999).
Weather readEpw(const std::string& path);
Weather parseEpw(const std::string& text, const std::string& name);

/// The row's time as solarPosition takes it: the middle of the hour, in UTC ("YYYY-MM-DDTHH:MM:SSZ"),
/// with a year outside 1950-2050 (typical-year files mix years) replaced by 2001.
std::string middleOfHourUtc(const WeatherHour& hour, double timeZone);

/// The row's day of the year, 1..365 (a typical year: 29 February counts as 28 February's day + 1).
int dayOfYear(const WeatherHour& hour);
/// The day of the year of a time "YYYY-MM-DD..." (as solarPosition takes it), or 0 when it starts
/// with no date.
int dayOfYear(const std::string& time);

}  // namespace hemirad
