// The material editor's fields: loaded from the first selected patch, after edits, undo and refusals.
#include "support.hpp"

#include "ui/material_fields.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;
using hemirad::ui::AppState;
using hemirad::ui::MaterialEdit;
using hemirad::ui::MaterialFields;

TEST_CASE("Material fields: a refused edit puts the patch's values back, an applied one stays (issue 38 #10)") {
    // On the mirror (s = 0.9, rho 0.05) Diffuse 0.5 is refused (rho + s = 1.4); the field and its
    // swatch kept showing 0.5 while the patch kept 0.05.
    AppState app;
    REQUIRE(app.loadScene(sourcePath("scenes/cornell_mirror.obj")));
    PatchId mirror = 0;
    while (!(app.scene().patches[mirror].specular > 0.0)) ++mirror;
    REQUIRE(app.scene().patches[mirror].specular == doctest::Approx(0.9));
    app.select(mirror, false);
    MaterialFields fields;
    fields.sync(app);
    const Rgb before = app.scene().patches[mirror].rho;
    CHECK(fields.rho[0] == before[0]);
    CHECK(fields.specular == doctest::Approx(0.9));

    for (double& c : fields.rho) c = 0.5;  // typed into the field
    MaterialEdit edit;
    edit.rho = Rgb::Constant(0.5);
    CHECK_FALSE(fields.apply(app, edit));
    CHECK(app.log().back().error);
    CHECK(app.log().back().text.find("rho + s = 1.4") != std::string::npos);
    CHECK((app.scene().patches[mirror].rho == before).all());
    for (int c = 0; c < 3; ++c) CHECK(fields.rho[c] == before[c]);
    fields.sync(app);  // the next frame
    for (int c = 0; c < 3; ++c) CHECK(fields.rho[c] == before[c]);

    // An edit that fits (0.08 + 0.9 <= 1) stays in the fields and the patch.
    for (double& c : fields.rho) c = 0.08;
    edit.rho = Rgb::Constant(0.08);
    CHECK(fields.apply(app, edit));
    fields.sync(app);
    for (int c = 0; c < 3; ++c) CHECK(fields.rho[c] == 0.08);
    CHECK((app.scene().patches[mirror].rho == Rgb::Constant(0.08)).all());
    // Undo loads the fields again.
    app.undo();
    fields.sync(app);
    for (int c = 0; c < 3; ++c) CHECK(fields.rho[c] == before[c]);
}
