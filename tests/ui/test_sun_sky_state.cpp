// hemirad-gui's Sky and sun, driven without a window: the run on the worker thread against `hemirad
// irradiance`'s CSV for the same scene, sun and sky (isotropic and Perez's), the false-colour
// quantities and their legend, bad inputs refused with a message, the result going out of date.
#include "support.hpp"

#include "ui/app_state.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

using namespace hemirad;
using namespace hemirad::test;
using hemirad::ui::AppState;
using hemirad::ui::FalseColourSettings;

namespace {

bool logged(const AppState& app, const std::string& text) {
    for (const auto& e : app.log())
        if (e.text.find(text) != std::string::npos) return true;
    return false;
}

void runToEnd(AppState& app) {
    app.wait();
    app.poll();
}

/// A column of a CSV with a header line, as numbers.
std::vector<double> column(const std::string& path, std::size_t index) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    std::vector<double> values;
    while (std::getline(in, line)) {
        std::stringstream cells(line);
        std::string cell;
        for (std::size_t k = 0; k <= index; ++k) std::getline(cells, cell, ',');
        values.push_back(std::stod(cell));
    }
    return values;
}

}  // namespace

TEST_CASE("hemirad-gui's Sky and sun gives hemirad irradiance's hour, isotropic and Perez's, and maps it in false colour") {
    const auto dir = tempDir("gui-sun-sky");
    const std::string scene = sourcePath("scenes/cornell_mirror.obj");
    for (const std::string sky : {"isotropic", "perez"}) {
        CAPTURE(sky);
        const std::string csv = (dir / (sky + ".csv")).string();
        const CommandResult cli = runCommand(std::string(HEMIRAD_BINARY) + " irradiance " + scene +
                                             " --up y --sun-time 2026-06-21T10:00Z --latitude 48.1 --longitude 11.6 --dni 700 --dhi 100"
                                             " --sky " + sky + " -o " + csv + " 2>&1");
        INFO(cli.output);
        REQUIRE(cli.status == 0);
        AppState app;
        REQUIRE(app.loadScene(scene));
        app.setUpAxis(1);
        app.sunSky.time = "2026-06-21T10:00Z";
        app.sunSky.latitude = 48.1;
        app.sunSky.longitude = 11.6;
        app.sunSky.dni = 700;
        app.sunSky.dhi = 100;
        app.sunSky.sky = sky;
        app.falseColour.sun = FalseColourSettings::Sun::Total;
        CHECK_FALSE(app.falseColourView().error.empty());  // no result yet
        app.runSunSky();
        CHECK(app.job().running);
        runToEnd(app);
        const ui::SunSkyResult* r = app.sunSkyResult();
        REQUIRE(r != nullptr);
        CHECK(r->irradiance.balance <= 1e-9);
        CHECK(logged(app, "irradiance: "));
        CHECK(app.formFactors() != nullptr);  // F with every row serves the radiosity too
        CHECK(app.formFactors()->computedRows() == app.scene().size());
        const std::vector<double> directSky = column(csv, 3), total = column(csv, 5), reflectedSun = column(csv, 7);
        REQUIRE(total.size() == app.scene().size());
        for (PatchId i = 0; i < app.scene().size(); ++i) {
            CHECK(r->irradiance.directSky[i] == doctest::Approx(directSky[i]).epsilon(1e-9).scale(1e-9));
            CHECK(r->irradiance.total[i] == doctest::Approx(total[i]).epsilon(1e-9).scale(1e-9));
            CHECK(r->irradiance.reflectedSun[i] == doctest::Approx(reflectedSun[i]).epsilon(1e-9).scale(1e-9));
        }
        ui::FalseColourView view = app.falseColourView();
        CHECK(view.error.empty());
        CHECK(view.range.max == doctest::Approx(*std::max_element(total.begin(), total.end())).epsilon(1e-9));
        CHECK(app.falseColourLegend().first == "total irradiance (sun and sky)");
        CHECK(app.falseColourLegend().second == "W/m^2");
        app.falseColour.sun = FalseColourSettings::Sun::SunlitFraction;
        CHECK(app.falseColourView().error.empty());
        app.falseColour.sun = FalseColourSettings::Sun::SkyView;
        if (sky == "isotropic") {
            CHECK(app.falseColourView().error.empty());
        } else {
            CHECK(app.falseColourView().error.find("comes with the isotropic sky") != std::string::npos);
        }
        // A material edit makes the result out of date.
        CHECK_FALSE(app.sunSkyStale());
        app.select(0, false);
        ui::MaterialEdit edit;
        edit.rho = Rgb::Constant(0.3);
        CHECK(app.editMaterial(edit));
        CHECK(app.sunSkyStale());
        app.wait();
    }
}

TEST_CASE("hemirad-gui's Sky and sun refuses a sky it does not know and a time that does not parse, and keeps running") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_box.obj")));
    app.sunSky.sky = "clear";
    app.runSunSky();
    CHECK_FALSE(app.job().running);
    CHECK(logged(app, "sky and sun: sky: 'clear' is not a sky model"));
    app.sunSky.sky = "isotropic";
    app.sunSky.time = "2026-13-01T10:00";
    app.runSunSky();
    runToEnd(app);
    CHECK(app.sunSkyResult() == nullptr);
    bool named = false;
    for (const auto& e : app.log()) named |= e.error && e.text.find("sky and sun: ") == 0 && e.text.find("2026-13-01T10:00") != std::string::npos;
    CHECK(named);
    app.sunSky.byTime = false;
    app.sunSky.direction = Vec3(0, 1, 0.3);
    app.runSunSky();
    runToEnd(app);
    CHECK(app.sunSkyResult() != nullptr);
}

TEST_CASE("hemirad-gui's Sky and sun at night: the sun below the horizon lights nothing, the sky still comes") {
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_mirror.obj")));
    app.setUpAxis(1);
    app.sunSky.time = "2026-06-21T23:00Z";  // Munich, 21 degrees below the horizon
    app.sunSky.latitude = 48.1;
    app.sunSky.longitude = 11.6;
    app.sunSky.dni = 700;
    app.sunSky.dhi = 20;
    app.runSunSky();
    runToEnd(app);
    const ui::SunSkyResult* r = app.sunSkyResult();
    REQUIRE(r != nullptr);
    CHECK(logged(app, "below the horizon (no direct sun)"));
    double sun = 0.0, sky = 0.0;
    for (PatchId i = 0; i < app.scene().size(); ++i) {
        sun += r->sunlit[i] + r->irradiance.directSun[i] + r->irradiance.reflectedSun[i];
        sky += r->irradiance.directSky[i];
    }
    CHECK(sun == 0.0);
    CHECK(sky > 0.0);
    CHECK(r->irradiance.balance <= 1e-9);
}
