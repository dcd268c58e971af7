// hemirad-gui's Sky and sun under Xvfb: --sun-sky runs the hour as the Scene panel's section does;
// the section draws its report, the legend the quantity's title and unit, and the sun is drawn over
// the view, from the scene's centre toward it.
#include "ui/gui_run.hpp"

#include <cstdio>
#include <string>

using namespace hemirad::test;

TEST_CASE("hemirad-gui --sun-sky: the section's report, the total irradiance in false colour with its legend, the sun drawn") {
    std::string log;
    const Image image = runGui("gui-sun-sky", sourcePath("scenes/cornell_mirror.obj") +
                                                  " --up y --sun-sky --sun-direction 0.2,1,0.5 --dni 700 --dhi 100 --sky perez"
                                                  " --false-color total_solar",
                               log);
    INFO(log);
    CHECK(log.find("hemirad-gui: sky and sun panel: sun: direction 0.1761 0.8805 0.4402 (given)\n") != std::string::npos);
    CHECK(log.find("hemirad-gui: sky and sun panel: sky: perez, DNI 700 W/m^2, DHI 100 W/m^2\n") != std::string::npos);
    const std::size_t balance = log.find("hemirad-gui: sky and sun panel: ");
    REQUIRE(balance != std::string::npos);
    CHECK(log.find(" W absorbed, ", balance) != std::string::npos);
    CHECK(log.find("hemirad-gui: legend: total irradiance (sun and sky) | W/m^2\n") != std::string::npos);
    CHECK(log.find("hemirad-gui: false colour: total irradiance (sun and sky), linear scale ") != std::string::npos);
    // The sun's disc, where no panel covers it, in its yellow.
    float x = 0, y = 0;
    const std::size_t at = log.find("hemirad-gui: sun drawn at ");
    REQUIRE(at != std::string::npos);
    REQUIRE(std::sscanf(log.c_str() + at, "hemirad-gui: sun drawn at %f,%f", &x, &y) == 2);
    bool covered = false;
    for (std::size_t p = log.find("hemirad-gui: panel "); p != std::string::npos; p = log.find("hemirad-gui: panel ", p + 1)) {
        float px = 0, py = 0, w = 0, h = 0;
        if (std::sscanf(log.c_str() + log.find(" at ", p), " at %f,%f size %fx%f", &px, &py, &w, &h) == 4)
            covered |= x >= px && x <= px + w && y >= py && y <= py + h;
    }
    if (!covered) {
        const unsigned char* pixel = image.at(int(x), int(y));
        CHECK(int(pixel[0]) == 255);
        CHECK(int(pixel[1]) == 214);
        CHECK(int(pixel[2]) == 40);
    }
    MESSAGE("the sun drawn at " << x << "," << y << std::string(covered ? " under a panel" : ""));
}
