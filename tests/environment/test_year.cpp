// A year of hours against one F: the EPW reader (and its errors by file and line), each hour of
// the batched solve equal to that hour solved alone, and the annual sums.
#include "support.hpp"

#include "engine/error.hpp"
#include "environment/irradiance.hpp"
#include "environment/reflected_sun.hpp"
#include "environment/sensor_mirrors.hpp"
#include "environment/sensor_sky.hpp"
#include "environment/sensors.hpp"
#include "environment/sky_coefficients.hpp"
#include "environment/sky_view.hpp"
#include "environment/solar_position.hpp"
#include "environment/sunlit.hpp"
#include "environment/weather.hpp"
#include "environment/year.hpp"
#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

std::string excerpt() { return sourcePath("tests/data/weather/excerpt.epw"); }

/// A 10 x 10 courtyard-like scene: ground, a box on it, a tall wall.
Scene smallDistrict() {
    SceneBuilder b;
    const std::uint32_t ground = b.material("ground", Rgb::Constant(0.2));
    const std::uint32_t wall = b.material("wall", Rgb::Constant(0.5));
    b.rectangle(2, 0.0, -5, 5, -5, 5, true, ground);
    b.rectangle(2, 3.0, -1, 1, -1, 1, true, wall);
    b.rectangle(0, -1, -1, 1, 0, 3, false, wall);
    b.rectangle(0, 1, -1, 1, 0, 3, true, wall);
    b.rectangle(1, -1, 0, 3, -1, 1, false, wall);
    b.rectangle(1, 1, 0, 3, -1, 1, true, wall);
    b.rectangle(1, -4, 0, 6, -5, 5, true, wall);  // a wall along y = -4 facing +y (north), 6 high
    return b.scene;
}

/// The small district with its tall wall a mirror (s = 0.6, rho 0.3), F with every row.
struct MirroredDistrict {
    Scene s = [] {
        Scene d = smallDistrict();
        d.patches[6].specular = 0.6;
        d.patches[6].rho = Rgb::Constant(0.3);
        return d;
    }();
    FormFactors F = computeFormFactors(s, MethodSettings::of(HemisphereOptions{}), neededRows(s, true)).F;
};

/// The small district's F (every row), its direct sky view factors and the bundled excerpt.
struct Prepared {
    Scene s = smallDistrict();
    FormFactors F = computeFormFactors(s, MethodSettings::of(HemisphereOptions{}), neededRows(s, true)).F;
    std::vector<double> sky = skyViewFactors(s, MethodSettings::of(HemisphereOptions{})).direct;
    Weather w = readEpw(excerpt());
};

/// One weather hour solved alone, as the year solves it: its sun (and the sun the mirrors reflect)
/// and sky on F; `toSun` where the sun is up with a direct beam (`sun`), else straight up.
struct HourAlone {
    IrradianceResult result;
    Vec3 toSun = Vec3(0, 0, 1);
    bool sun = false;  ///< the sun up with a direct beam
};
HourAlone hourAlone(const Scene& s, const FormFactors& F, const std::vector<double>& sky, const Weather& w, const WeatherHour& hour,
                    const YearOptions& options, const SolverOptions& solver) {
    // With a sky model (options.sky), that hour's cells' radiance through the coefficients.
    HourAlone out;
    IrradianceInputs in;
    in.directSun.assign(s.size(), 0.0);
    const SolarPosition p = solarPosition(middleOfHourUtc(hour, w.timeZone), w.latitude, w.longitude);
    if (p.elevation > 0.0 && hour.dni > 0.0) {
        out.toSun = sunDirection(p, options.up, options.north);
        out.sun = true;
        in.directSun = directIrradiance(s, out.toSun, hour.dni, sunlitFractions(s, out.toSun));
        in.reflectedSun = reflectedSun(s, out.toSun, hour.dni).irradiance;
    }
    in.skyView = sky;
    in.dhi = hour.dhi;
    if (options.sky && hour.dhi > 0.0) {
        SkyConditions c;
        c.toSun = skyDirection(p.elevation * kPi / 180, p.azimuth * kPi / 180);
        c.dni = hour.dni;
        c.dhi = hour.dhi;
        c.dayOfYear = dayOfYear(hour);
        SkyHour sky = skyHour(*options.sky, options.skyModel, c);
        in.directSky = std::move(sky.direct);
        in.reflectedSky = std::move(sky.mirrored);
    } else if (options.sky) {
        in.directSky.assign(s.size(), 0.0);
    }
    out.result = solarIrradiance(s, F, in, 1.0, solver);
    return out;
}

/// The year of `w` on the prepared scene by the solver `kind` to a relative residual of 1e-13.
YearResult yearSolvedBy(const std::string& kind, const Prepared& prepared, const Weather& w, const YearOptions& options) {
    SolverOptions solver;
    solver.solver = kind;
    solver.tolerance = 1e-13;
    return solveYear(prepared.s, prepared.F, prepared.sky, w, options, solver);
}

/// The largest difference between an hour of `year` and that hour solved alone by LU, relative to
/// max(1, the hour's total), over every hour and patch.
double worstAgainstHoursAlone(const Scene& s, const FormFactors& F, const std::vector<double>& sky, const Weather& w,
                              const YearResult& year, const YearOptions& options) {
    SolverOptions lu;
    lu.solver = "lu";
    double worst = 0.0;
    for (std::size_t k = 0; k < year.hours.size(); ++k) {
        const IrradianceResult alone = hourAlone(s, F, sky, w, w.hours[year.hours[k]], options, lu).result;
        for (PatchId i = 0; i < s.size(); ++i)
            worst = std::max(worst, std::abs(year.total[k * s.size() + i] - alone.total[i]) / std::max(1.0, alone.total[i]));
    }
    return worst;
}

}  // namespace

TEST_CASE("EPW: the location, the hours' DNI and DHI (fields 15 and 16), and the middle of each hour in UTC") {
    const Weather w = readEpw(excerpt());
    CHECK(w.place == "Munich Test, BY, DEU");
    CHECK(w.latitude == 48.13);
    CHECK(w.longitude == 11.70);
    CHECK(w.timeZone == 1.0);
    REQUIRE(w.hours.size() == 48);
    CHECK(w.hours[12].hour == 13);
    CHECK(w.hours[12].dni > 800);
    CHECK(w.hours[12].line == 21);
    // Hour 13 local standard time (UTC+1) is 12:00-13:00 UTC+1: its middle 11:30 UTC.
    CHECK(middleOfHourUtc(w.hours[12], w.timeZone) == "1995-06-21T11:30:00Z");
    // Hour 1 of the 21st is 00:00-01:00 UTC+1: 23:30 UTC on the 20th.
    CHECK(middleOfHourUtc(w.hours[0], w.timeZone) == "1995-06-20T23:30:00Z");
}

TEST_CASE("EPW errors name the file and the line") {
    const std::string good = readText(excerpt());
    auto fails = [&](const std::string& text, const std::string& message) {
        CHECK_THROWS_WITH_AS(parseEpw(text, "w.epw"), doctest::Contains(message.c_str()), Error);
    };
    fails("DESIGN CONDITIONS,0\n", "w.epw:1: an EPW file starts with LOCATION");
    std::string row = good.substr(0, good.find("1995,6,21,1,"));
    fails(row + "1995,6,21,1,60,x,18\n", "w.epw:9: a data row has 7 fields");
    fails(row + "1995,6,21,25,60,?,18,10,60,95000,1300,1360,350,0,0,0\n", "w.epw:9: month 6, day 21 or hour 25 is out of range");
    fails(row + "1995,6,21,1,60,?,18,10,60,95000,1300,1360,350,0,abc,0\n", "w.epw:9: direct-normal irradiance 'abc' is not a number");
    fails(row + "1995,6,21,1,60,?,18,10,60,95000,1300,1360,350,0,9999,0\n", "w.epw:9: irradiance marked missing (9999)");
    fails(row, "no hourly data");
}

TEST_CASE("A year's hours solved in batches equal each hour solved alone, and the annual sums add them up") {
    const Prepared prepared;
    const Scene& s = prepared.s;
    const FormFactors& F = prepared.F;
    const std::vector<double>& sky = prepared.sky;
    const Weather& w = prepared.w;
    YearOptions options;
    options.batch = 7;  // batches that do not divide the hours
    SolverOptions lu;
    lu.solver = "lu";
    const YearResult year = solveYear(s, F, sky, w, options, lu);
    std::size_t lit = 0;
    for (const WeatherHour& h : w.hours) lit += h.dni > 0 || h.dhi > 0;
    CHECK(year.hours.size() == lit);  // the hours with sun or sky in the excerpt
    CHECK(lit > 20);
    CHECK(year.worstBalance <= 1e-9);
    double worst = 0.0;
    std::vector<double> sum(s.size(), 0.0);
    for (std::size_t k = 0; k < year.hours.size(); ++k) {
        const IrradianceResult alone = hourAlone(s, F, sky, w, w.hours[year.hours[k]], options, lu).result;
        for (PatchId i = 0; i < s.size(); ++i) {
            worst = std::max(worst, std::abs(year.total[k * s.size() + i] - alone.total[i]) / std::max(1.0, alone.total[i]));
            sum[i] += alone.total[i];
        }
    }
    MESSAGE("largest difference between an hour of the year and the hour alone: " << worst);
    CHECK(worst <= 1e-9);
    for (PatchId i = 0; i < s.size(); ++i) CHECK(year.sum[i] == relative(sum[i], 1e-12));
    // The tall wall faces north (+y): at Munich in June it sees the sun only early and late.
    CHECK(year.directSun[6] < 0.2 * year.directSun[0]);
}

TEST_CASE("Overcast hours (sky, no sun) in a year: the sky solved once and scaled equals each hour solved alone") {
    // The isotropic sky's inter-reflection is solved once per unit DHI; an hour without sun solves
    // nothing, one with sun solves for its sun alone.
    Prepared prepared;
    Weather& w = prepared.w;
    std::size_t overcast = 0;
    for (std::size_t h = 0; h < w.hours.size(); h += 2)
        if (w.hours[h].dni > 0.0) {
            w.hours[h].dhi += 0.5 * w.hours[h].dni;
            w.hours[h].dni = 0.0;
            ++overcast;
        }
    REQUIRE(overcast > 10);
    for (const std::string kind : {"lu", "gauss-seidel", "sor"}) {
        CAPTURE(kind);
        YearOptions options;
        options.batch = 5;
        const YearResult year = yearSolvedBy(kind, prepared, w, options);
        CHECK(year.worstBalance <= 1e-9);
        const double worst = worstAgainstHoursAlone(prepared.s, prepared.F, prepared.sky, w, year, options);
        MESSAGE(kind << ", " << overcast << " overcast hours: largest difference from the hours alone " << worst);
        CHECK(worst <= 1e-9);
    }
}

TEST_CASE("A year's batches solved by the iterative solvers (many hours in one pass over F) equal each hour solved alone") {
    // The solvers above 2,000 patches: SOR (auto on up to 2 threads), Gauss-Seidel or Jacobi over a
    // batch of hours at once. SOR's factor is shared by the batch: an hour's sweeps depend on its
    // companions, its answer (to the tolerance) does not.
    const Prepared prepared;
    for (const std::string kind : {"sor", "gauss-seidel", "jacobi"}) {
        CAPTURE(kind);
        YearOptions options;
        options.batch = 24;
        const YearResult year = yearSolvedBy(kind, prepared, prepared.w, options);
        REQUIRE(year.hours.size() > 20);
        const double worst = worstAgainstHoursAlone(prepared.s, prepared.F, prepared.sky, prepared.w, year, options);
        MESSAGE(kind << ": largest difference from the hours alone (LU) " << worst);
        CHECK(worst <= 1e-9);
    }
}

TEST_CASE("A year with a mirror: each hour with the sun it reflects equals the hour alone, and every hour balances") {
    Scene s = smallDistrict();
    s.patches[6].specular = 0.6;  // the tall wall along y = -4, facing north: the morning and evening sun
    s.patches[6].rho = Rgb::Constant(0.3);
    const MethodSettings method = MethodSettings::of(HemisphereOptions{});
    const FormFactors F = computeFormFactors(s, method, neededRows(s, true)).F;
    const std::vector<double> sky = skyViewFactors(s, method).direct;
    const Weather w = readEpw(excerpt());
    YearOptions options;
    SolverOptions lu;
    lu.solver = "lu";
    const YearResult year = solveYear(s, F, sky, w, options, lu);
    CHECK(year.worstBalance <= 1e-9);
    double worst = 0.0, landed = 0.0;
    for (std::size_t k = 0; k < year.hours.size(); ++k) {
        const IrradianceResult alone = hourAlone(s, F, sky, w, w.hours[year.hours[k]], options, lu).result;
        CHECK(alone.balance <= 1e-9);
        for (PatchId i = 0; i < s.size(); ++i) {
            worst = std::max(worst, std::abs(year.total[k * s.size() + i] - alone.total[i]) / std::max(1.0, alone.total[i]));
            landed += alone.reflectedSun[i] * s.patches[i].area;
        }
    }
    MESSAGE("with a mirror: largest difference from the hours alone " << worst << ", reflected sun landed " << landed << " Wh");
    CHECK(worst <= 1e-9);
    CHECK(landed > 0.0);
    double annual = 0.0;
    for (PatchId i = 0; i < s.size(); ++i) annual += year.reflectedSun[i] * s.patches[i].area;
    CHECK(annual == relative(landed, 1e-12));
}

TEST_CASE("A year with a pure mirror and a dark roof: what they receive summed over their rows of F, one by one or in one pass, equals the hours alone") {
    // Patches that reflect read what they receive from their row of the solved system; a pure
    // mirror (rho 0) and a roof at rho 0.01 sum their rows of F instead: in one pass over F where
    // they are more than a tenth of the patches (7 patches), row by row where they are fewer (23).
    for (const int extra : {0, 16}) {
        CAPTURE(extra);
        Scene s = smallDistrict();
        if (extra > 0) {
            SceneBuilder b;
            b.scene = s;
            const std::uint32_t paving = b.material("paving", Rgb::Constant(0.25));
            for (int k = 0; k < extra; ++k)  // small tiles east of the ground
                b.rectangle(2, 0.0, 5.0 + 0.5 * (k % 4), 5.5 + 0.5 * (k % 4), -5.0 + 0.5 * (k / 4), -4.5 + 0.5 * (k / 4), true, paving);
            s = b.scene;
        }
        s.patches[6].specular = 0.6;  // the tall wall: a pure mirror
        s.patches[6].rho = Rgb::Zero();
        s.patches[1].rho = Rgb::Constant(0.01);  // the box's roof, nearly black
        const MethodSettings method = MethodSettings::of(HemisphereOptions{});
        const FormFactors F = computeFormFactors(s, method, neededRows(s, true)).F;
        const std::vector<double> sky = skyViewFactors(s, method).direct;
        const Weather w = readEpw(excerpt());
        YearOptions options;
        options.batch = 9;
        SolverOptions lu;
        lu.solver = "lu";
        const YearResult year = solveYear(s, F, sky, w, options, lu);
        CHECK(year.worstBalance <= 1e-9);
        double worst = 0.0, mirrorReceived = 0.0;
        for (std::size_t k = 0; k < year.hours.size(); ++k) {
            const IrradianceResult alone = hourAlone(s, F, sky, w, w.hours[year.hours[k]], options, lu).result;
            for (PatchId i = 0; i < s.size(); ++i)
                worst = std::max(worst, std::abs(year.total[k * s.size() + i] - alone.total[i]) / std::max(1.0, alone.total[i]));
            mirrorReceived += alone.reflected[6];
        }
        MESSAGE(s.size() << " patches: largest difference from the hours alone " << worst);
        CHECK(worst <= 1e-9);
        CHECK(mirrorReceived > 0.0);  // the mirror's own row carries light from the others
        CHECK(year.reflected[6] == relative(mirrorReceived, 1e-12));
    }
}

TEST_CASE("A year under Perez's sky with a mirror: each hour equals the hour alone, the sky through the mirror lands, all balance") {
    const MirroredDistrict district;
    const Scene& s = district.s;
    const FormFactors& F = district.F;
    YearOptions options;
    const SkyCoefficients sky = skyCoefficients(s, 1, 1, options.up, options.north);
    options.sky = &sky;
    options.skyModel = parseSkyModel("perez");
    SolverOptions lu;
    lu.solver = "lu";
    const Weather excerptOnly = readEpw(excerpt());
    // The excerpt's 32 hours with sky are fewer than Tregenza's 145 cells: each hour solves its own
    // sky. Six times over (192 hours) the cells' radiosity is solved once and summed by the hour.
    for (const int repeat : {1, 6}) {
        CAPTURE(repeat);
        Weather w = excerptOnly;
        for (int r = 1; r < repeat; ++r) w.hours.insert(w.hours.end(), excerptOnly.hours.begin(), excerptOnly.hours.end());
        const YearResult year = solveYear(s, F, {}, w, options, lu);
        CHECK(year.worstBalance <= 1e-9);
        // By Gauss-Seidel (the cells solved once each to its share of the tolerance, or each hour
        // its own sky), the hours equal LU's.
        SolverOptions sweeps;
        sweeps.solver = "gauss-seidel";
        sweeps.tolerance = 1e-12;
        const YearResult swept = solveYear(s, F, {}, w, options, sweeps);
        double apart = 0.0;
        for (std::size_t k = 0; k < year.total.size(); ++k)
            apart = std::max(apart, std::abs(swept.total[k] - year.total[k]) / std::max(1.0, year.total[k]));
        MESSAGE("Perez sky by Gauss-Seidel: largest difference from LU's year " << apart);
        CHECK(apart <= 1e-9);
        double worst = 0.0, landed = 0.0, skyPower = 0.0;
        for (std::size_t k = 0; k < year.hours.size(); ++k) {
            const WeatherHour& hour = w.hours[year.hours[k]];
            const IrradianceResult alone = hourAlone(s, F, {}, w, hour, options, lu).result;
            CHECK(alone.balance <= 1e-9);
            double hourLanded = 0.0;
            for (PatchId i = 0; i < s.size(); ++i) {
                worst = std::max(worst, std::abs(year.total[k * s.size() + i] - alone.total[i]) / std::max(1.0, alone.total[i]));
                hourLanded += alone.reflectedSky[i] * s.patches[i].area;
                skyPower += alone.directSky[i] * s.patches[i].area;
            }
            // What lands through the mirror is part of its specular reflection of the sky on it.
            CHECK(hourLanded <= 0.6 * alone.directSky[6] * s.patches[6].area * (1 + 1e-12));
            landed += hourLanded;
        }
        MESSAGE("Perez sky: largest difference from the hours alone " << worst << ", sky through the mirror " << landed << " Wh of "
                                                                       << skyPower << " Wh of direct sky");
        CHECK(worst <= 1e-9);
        CHECK(landed > 0.0);
        double annual = 0.0;
        for (PatchId i = 0; i < s.size(); ++i) annual += year.reflectedSky[i] * s.patches[i].area;
        CHECK(annual == relative(landed, 1e-12));
    }
    // The coefficients are of one scene, and sensors keep the isotropic sky.
    Scene other = smallDistrict();
    other.patches.pop_back();
    CHECK_THROWS_WITH_AS(solveYear(other, computeFormFactors(other, MethodSettings::of(HemisphereOptions{}), neededRows(other, true)).F, {}, excerptOnly,
                                   options, lu),
                         doctest::Contains("not this scene's"), Error);
}

TEST_CASE("Sensors through a year: each hour at each sensor equals that hour's irradiance there from the hour solved alone") {
    const Prepared prepared;
    const Scene& s = prepared.s;
    const FormFactors& F = prepared.F;
    const std::vector<double>& sky = prepared.sky;
    const Weather& w = prepared.w;
    // In the open, north of the tall wall facing it, under nothing and beside the box facing west.
    Sensors sensors;
    sensors.position = {Vec3(3, 3, 1), Vec3(0, -3, 1), Vec3(-1.5, 0, 1)};
    sensors.normal = {Vec3(0, 0, 1), Vec3(0, -1, 0), Vec3(-1, 0, 0)};
    sensors.name = {"open", "facing the wall", "beside the box"};
    const SensorFactors factors = sensorFactors(s, sensors);
    YearOptions options;
    options.batch = 5;
    options.sensors = &sensors;
    options.sensorFactors = &factors;
    SolverOptions lu;
    lu.solver = "lu";
    const YearResult year = solveYear(s, F, sky, w, options, lu);
    REQUIRE(year.sensorTotal.size() == year.hours.size() * 3);
    double worst = 0.0;
    std::vector<double> sum(3, 0.0), reflected(3, 0.0);
    for (std::size_t k = 0; k < year.hours.size(); ++k) {
        const WeatherHour& hour = w.hours[year.hours[k]];
        const HourAlone alone = hourAlone(s, F, sky, w, hour, options, lu);
        const std::vector<double> lit = alone.sun ? sensorSunlit(s, sensors, alone.toSun) : std::vector<double>(3, 0.0);
        const SensorIrradiance at = sensorIrradiance(sensors, factors, lit, alone.toSun, hour.dni, hour.dhi, alone.result.radiosity);
        for (std::size_t q = 0; q < 3; ++q) {
            worst = std::max(worst, std::abs(year.sensorTotal[k * 3 + q] - at.total[q]) / std::max(1.0, at.total[q]));
            sum[q] += at.total[q];
            reflected[q] += at.reflected[q];
        }
    }
    MESSAGE("largest difference between a sensor's hour in the year and the hour alone: " << worst);
    CHECK(worst <= 1e-9);
    for (std::size_t q = 0; q < 3; ++q) {
        CHECK(year.sensorSum[q] == relative(sum[q], 1e-12));
        CHECK(year.sensorReflected[q] == relative(reflected[q], 1e-9));
    }
    CHECK(year.sensorReflected[1] > year.sensorReflected[0]);  // the wall it faces reflects to it
    CHECK(year.sensorDirectSun[0] > year.sensorDirectSun[1]);   // the wall shades the one facing it from the southern sun
}

TEST_CASE("Sensors through a year under Perez's sky with a mirror: each hour at each sensor equals that hour there alone") {
    const MirroredDistrict district;  // the tall wall a mirror
    const Scene& s = district.s;
    const FormFactors& F = district.F;
    YearOptions options;
    const SkyCoefficients sky = skyCoefficients(s, 1, 2, options.up, options.north);
    options.sky = &sky;
    options.skyModel = parseSkyModel("perez");
    Sensors sensors;
    sensors.position = {Vec3(3, 3, 1), Vec3(0, -3, 1), Vec3(-1.5, 0, 1)};
    sensors.normal = {Vec3(0, 0, 1), Vec3(0, -1, 0), Vec3(-1, 0, 0)};
    sensors.name = {"open", "facing the mirror", "beside the box"};
    const SensorFactors factors = sensorFactors(s, sensors);
    const SensorSkyCoefficients sensorSky = sensorSkyCoefficients(s, sensors, sky.grid, sky.samples, options.up, options.north);
    REQUIRE(sensorSky.mirrored.rows() == (rayCastingNotBuilt().empty() ? 3 : 0));
    options.sensors = &sensors;
    options.sensorFactors = &factors;
    SolverOptions lu;
    lu.solver = "lu";
    const Weather w = readEpw(excerpt());
    // Without the sensors' coefficients a sky model's year refuses them.
    CHECK_THROWS_WITH_AS(solveYear(s, F, {}, w, options, lu), doctest::Contains("sensorSkyCoefficients"), Error);
    options.sensorSky = &sensorSky;
    const YearResult year = solveYear(s, F, {}, w, options, lu);
    REQUIRE(year.sensorTotal.size() == year.hours.size() * 3);
    const SensorReflections mirrors(s);
    double worst = 0.0, skyInMirror = 0.0;
    for (std::size_t k = 0; k < year.hours.size(); ++k) {
        const WeatherHour& hour = w.hours[year.hours[k]];
        const HourAlone alone = hourAlone(s, F, {}, w, hour, options, lu);
        std::vector<double> lit(3, 0.0), glare;
        if (alone.sun) {
            lit = sensorSunlit(s, sensors, alone.toSun);
            glare = mirrors.sun(BeamShadows(s), sensors, alone.toSun, hour.dni);
        }
        // That hour's sky at the sensors: the cells' radiance through their coefficients.
        SensorSky modelSky{std::vector<double>(3, 0.0), {}};
        if (hour.dhi > 0.0) {
            const SolarPosition p = solarPosition(middleOfHourUtc(hour, w.timeZone), w.latitude, w.longitude);
            SkyConditions c;
            c.toSun = skyDirection(p.elevation * kPi / 180, p.azimuth * kPi / 180);
            c.dni = hour.dni;
            c.dhi = hour.dhi;
            c.dayOfYear = dayOfYear(hour);
            modelSky = sensorSkyHour(sensorSky, skyRadiance(sky.grid, sky.samples, options.skyModel, c));
        }
        const SensorIrradiance at =
            sensorIrradiance(sensors, factors, lit, alone.toSun, hour.dni, hour.dhi, alone.result.radiosity, glare, &modelSky);
        for (std::size_t q = 0; q < 3; ++q) {
            worst = std::max(worst, std::abs(year.sensorTotal[k * 3 + q] - at.total[q]) / std::max(1.0, at.total[q]));
            skyInMirror += at.reflectedSky[q];
        }
    }
    MESSAGE("Perez's sky at the sensors: largest difference between an hour in the year and the hour alone " << worst
                                                                                                              << "; sky in the mirror " << skyInMirror << " Wh/m^2");
    CHECK(worst <= 1e-9);
    if (rayCastingNotBuilt().empty()) {
        CHECK(skyInMirror > 0.0);  // the sensor facing the mirror sees sky in it
        CHECK(year.sensorReflectedSky[0] + year.sensorReflectedSky[1] + year.sensorReflectedSky[2] == relative(skyInMirror, 1e-9));
    }
}

TEST_CASE("The .npy writer writes a header NumPy reads: magic, version 1.0, a 64-byte aligned header, the shape") {
    const auto dir = tempDir("npy");
    writeNpy((dir / "a.npy").string(), {1, 2, 3, 4, 5, 6}, 2, 3);
    const std::string bytes = readText(dir / "a.npy");
    CHECK(bytes.substr(0, 8) == std::string("\x93NUMPY\x01\x00", 8));
    const std::size_t headerLength = std::uint8_t(bytes[8]) + 256u * std::uint8_t(bytes[9]);
    CHECK((10 + headerLength) % 64 == 0);
    CHECK(bytes.find("'shape': (2, 3)") != std::string::npos);
    CHECK(bytes.size() == 10 + headerLength + 6 * sizeof(double));
    CHECK_THROWS_AS(writeNpy((dir / "b.npy").string(), {1, 2, 3}, 2, 3), Error);
    // Row by row: a row too many is refused, and so is a commit before the last row (nothing written).
    {
        NpyWriter rows((dir / "c.npy").string(), 2, 3);
        const double row[3] = {1, 2, 3};
        rows.append(row);
        CHECK_THROWS_AS(rows.commit(), Error);
        rows.append(row);
        CHECK_THROWS_AS(rows.append(row), Error);
        rows.commit();
    }
    CHECK(readText(dir / "c.npy").size() == 10 + headerLength + 6 * sizeof(double));
    {
        NpyWriter lost((dir / "d.npy").string(), 2, 3);
    }
    CHECK(!std::filesystem::exists(dir / "d.npy"));  // never committed: no file
    std::filesystem::remove_all(dir);
}

TEST_CASE("A year's hours handed over one by one as they are solved equal the totals a year keeps") {
    // hemirad year writes each hour to its .npy file as it comes, holding none of them.
    const Prepared prepared;
    YearOptions keep;
    keep.batch = 7;
    const YearResult kept = solveYear(prepared.s, prepared.F, prepared.sky, prepared.w, keep, SolverOptions{});
    YearOptions streamed = keep;
    std::vector<double> rows;
    streamed.hourly = [&](const double* patches, const double* sensors) {
        CHECK(sensors == nullptr);
        rows.insert(rows.end(), patches, patches + prepared.s.size());
    };
    const YearResult year = solveYear(prepared.s, prepared.F, prepared.sky, prepared.w, streamed, SolverOptions{});
    CHECK(year.total.empty());
    CHECK(rows == kept.total);
    CHECK(year.sum == kept.sum);
    CHECK(solvedHours(prepared.w) == kept.hours);
}
