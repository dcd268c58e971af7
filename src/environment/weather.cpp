// EPW reader: the LOCATION line and the hourly rows' date, hour, DNI and DHI.
#include "environment/weather.hpp"

#include "engine/csv.hpp"
#include "engine/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>

namespace hemirad {
namespace {

double number(const std::string& text, const std::string& name, int line, const char* what) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || (*end != '\0' && *end != '\r') || !std::isfinite(v))
        throw Error(name, line, std::string(what) + " '" + text + "' is not a number");
    return v;
}

}  // namespace

Weather readEpw(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, 0, "cannot open the weather file");
    std::ostringstream text;
    text << in.rdbuf();
    return parseEpw(text.str(), path);
}

Weather parseEpw(const std::string& text, const std::string& name) {
    Weather w;
    std::istringstream in(text);
    std::string line;
    int number_ = 0;
    bool located = false;
    while (std::getline(in, line)) {
        ++number_;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) continue;
        const std::vector<std::string> f = splitCsvLine(line);
        if (number_ <= 8) {  // the header records
            if (f[0] == "LOCATION") {
                if (f.size() < 10) throw Error(name, number_, "LOCATION has " + std::to_string(f.size()) + " fields, expected 10");
                w.place = f[1] + ", " + f[2] + ", " + f[3];
                w.latitude = number(f[6], name, number_, "latitude");
                w.longitude = number(f[7], name, number_, "longitude");
                w.timeZone = number(f[8], name, number_, "time zone");
                if (std::abs(w.latitude) > 90 || std::abs(w.longitude) > 180 || std::abs(w.timeZone) > 14)
                    throw Error(name, number_, "LOCATION's latitude, longitude or time zone is out of range");
                located = true;
            } else if (number_ == 1) {
                throw Error(name, number_, "an EPW file starts with LOCATION, found '" + f[0] + "'");
            }
            continue;
        }
        if (!located) throw Error(name, number_, "no LOCATION line before the data");
        if (f.size() < 16)
            throw Error(name, number_, "a data row has " + std::to_string(f.size()) + " fields; direct-normal and diffuse-horizontal "
                                       "irradiance are fields 15 and 16");
        WeatherHour h;
        h.line = number_;
        h.year = int(number(f[0], name, number_, "year"));
        h.month = int(number(f[1], name, number_, "month"));
        h.day = int(number(f[2], name, number_, "day"));
        h.hour = int(number(f[3], name, number_, "hour"));
        if (h.month < 1 || h.month > 12 || h.day < 1 || h.day > 31 || h.hour < 1 || h.hour > 24)
            throw Error(name, number_, "month " + f[1] + ", day " + f[2] + " or hour " + f[3] + " is out of range (hours are 1-24)");
        h.dni = number(f[14], name, number_, "direct-normal irradiance");
        h.dhi = number(f[15], name, number_, "diffuse-horizontal irradiance");
        if (h.dni >= 9999 || h.dhi >= 9999) throw Error(name, number_, "irradiance marked missing (9999)");
        if (h.dni < 0 || h.dhi < 0) throw Error(name, number_, "a negative irradiance");
        w.hours.push_back(h);
    }
    if (!located) throw Error(name, 0, "no LOCATION line: not an EPW file");
    if (w.hours.empty()) throw Error(name, number_, "no hourly data after the 8 header lines");
    return w;
}

std::string middleOfHourUtc(const WeatherHour& h, double timeZone) {
    std::tm t{};
    t.tm_year = (h.year >= 1950 && h.year <= 2050 ? h.year : 2001) - 1900;
    t.tm_mon = h.month - 1;
    t.tm_mday = h.day;
    t.tm_hour = 0;
    const long seconds = long(std::lround((h.hour - 0.5 - timeZone) * 3600.0));
    t.tm_sec = int(seconds);
    const std::time_t utc = timegm(&t);  // normalises the seconds past midnight
    std::tm out{};
    gmtime_r(&utc, &out);
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%04d-%02d-%02dT%02d:%02d:%02dZ", out.tm_year + 1900, out.tm_mon + 1, out.tm_mday,
                  out.tm_hour, out.tm_min, out.tm_sec);
    return buffer;
}

int dayOfYear(const WeatherHour& hour) {
    static constexpr int kBefore[12] = {0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334};
    return std::min(365, kBefore[std::clamp(hour.month, 1, 12) - 1] + hour.day);
}

int dayOfYear(const std::string& time) {
    WeatherHour date;
    int year = 0;
    if (std::sscanf(time.c_str(), "%d-%d-%d", &year, &date.month, &date.day) != 3) return 0;
    return dayOfYear(date);
}

}  // namespace hemirad
