// The Scene panel's thermal fields, driven without a window: they show the values in effect, a value
// AppState refuses is put back, temperatures are typed in K or C.
#include "support.hpp"

#include "ui/thermal_fields.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;
using hemirad::ui::AppState;
using hemirad::ui::ObjectCondition;
using hemirad::ui::ThermalFields;

namespace {

void loadRadiator(AppState& app) {
    REQUIRE(app.loadScene(sourcePath("examples/thermal/radiator.obj")));
    REQUIRE(app.loadThermalProperties(sourcePath("examples/thermal/radiator_properties.toml")));
    REQUIRE(app.loadThermalConditions(sourcePath("examples/thermal/radiator_bc.toml")));
}

}  // namespace

TEST_CASE("Thermal fields put a refused emissivity back and keep an accepted one") {
    AppState app;
    loadRadiator(app);
    ThermalFields fields;
    fields.sync(app);
    REQUIRE(fields.rows.size() == 3);
    CHECK(fields.rows[0].emissivity == doctest::Approx(0.88));
    fields.rows[0].emissivity = 1.5;  // typed
    fields.sync(app);                 // a frame passes: the typed value stays while nothing changed
    CHECK(fields.rows[0].emissivity == 1.5);
    CHECK_FALSE(fields.applyEmissivity(app, 0));
    CHECK(fields.rows[0].emissivity == doctest::Approx(0.88));  // the value in effect, not 1.5
    fields.rows[1].emissivity = 0.2;  // the shield's s = 0.9: eps + s > 1
    CHECK_FALSE(fields.applyEmissivity(app, 1));
    CHECK(fields.rows[1].emissivity == doctest::Approx(0.05));
    fields.rows[0].emissivity = 0.6;
    CHECK(fields.applyEmissivity(app, 0));
    CHECK(fields.rows[0].emissivity == doctest::Approx(0.6));
    CHECK(fields.rows[0].object.emissivityEdited);
}

TEST_CASE("Thermal fields type temperatures in C or K, put a temperature below 0 K back, and start a new kind") {
    AppState app;
    loadRadiator(app);
    ThermalFields fields;
    fields.celsius = true;
    fields.sync(app);
    REQUIRE(fields.rows.size() == 3);
    CHECK(fields.rows[2].kind == ObjectCondition::Kind::Temperature);
    CHECK(fields.rows[2].value == doctest::Approx(-20.0));  // temperature_C = -20
    CHECK(fields.environment == doctest::Approx(3.0 - 273.15));
    fields.rows[2].value = -300.0;  // below 0 K
    CHECK_FALSE(fields.applyValue(app, 2));
    CHECK(fields.rows[2].value == doctest::Approx(-20.0));
    fields.rows[2].value = 25.0;
    CHECK(fields.applyValue(app, 2));
    fields.celsius = false;
    fields.sync(app);
    CHECK(fields.rows[2].value == doctest::Approx(298.15));
    // A new kind starts from a value the user types over; the environment off is a closed scene.
    fields.rows[1].kind = ObjectCondition::Kind::Flux;
    CHECK(fields.applyKind(app, 1));
    CHECK(fields.rows[1].kind == ObjectCondition::Kind::Flux);
    CHECK(fields.rows[1].value == 0.0);
    fields.closed = true;
    CHECK(fields.applyEnvironment(app));
    CHECK(fields.closed);
    fields.closed = false;
    fields.environment = -10.0;  // K: refused
    CHECK_FALSE(fields.applyEnvironment(app));
    CHECK(fields.closed);  // back to what is in effect: no environment
}
