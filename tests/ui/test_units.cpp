// The GUI's values with units: areas in the scene's unit and in m^2, power in W where it is known.
#include "support.hpp"

#include "engine/error.hpp"
#include "ui/units.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::ui;

TEST_CASE("GUI units: areas in the scene's unit with m^2 alongside, power in W only when the unit is known") {
    CHECK(formatNumber(3090.0) == "3090");
    CHECK(formatNumber(1.534e5) == "1.534e+05");
    CHECK(formatArea(3090.0, "mm") == "3090 mm^2 (0.00309 m^2)");
    CHECK(formatArea(2.0, "m") == "2 m^2");
    CHECK(formatArea(1.0, "ft") == "1 ft^2 (0.0929 m^2)");
    CHECK(formatArea(3090.0, "") == "3090 (scene units^2)");
    CHECK(lengthUnitLabel("") == "scene units");
    CHECK(lengthUnitLabel("cm") == "cm");
    // 1e6 mm^2 x 1 W/m^2 = 1 W.
    CHECK(formatPower(Rgb(1e6, 2e6, 5e5), "mm") == "1 2 0.5 W");
    CHECK(formatPower(Rgb(1, 2, 3), "") == "1 2 3 W/m^2 x scene units^2");
    CHECK_THROWS_AS(formatArea(1.0, "furlong"), Error);
}
