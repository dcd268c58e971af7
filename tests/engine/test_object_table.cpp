// Per-object summaries and their CSV: the header states the units, objects count when they hold patches.
#include "support.hpp"

#include "engine/csv.hpp"
#include "engine/object_table.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

TEST_CASE("The object-table CSV states units in its header: area in the scene's unit squared, B and H in W/m^2 (issue 38 #13)") {
    ObjectSummary o;
    o.name = "floor, east";
    o.patches = o.hPatches = 2;
    o.area = 3.0;
    o.bMean = o.bMin = o.bMax = 4.0;
    o.hMean = o.hMin = o.hMax = 5.0;
    const auto dir = tempDir("object-table");
    writeObjectTable((dir / "mm.csv").string(), {o}, "mm");
    CHECK(readText(dir / "mm.csv") ==
          "object,patches,area (mm^2),B_mean (W/m^2),B_min (W/m^2),B_max (W/m^2),H_patches,H_mean (W/m^2),H_min (W/m^2),"
          "H_max (W/m^2)\n\"floor, east\",2,3,4,4,4,2,5,5,5\n");
    // A scene without a stated unit: scene units, as the GUI's table says.
    writeObjectTable((dir / "none.csv").string(), {o}, "");
    CHECK(readText(dir / "none.csv").rfind("object,patches,area (scene units^2),B_mean (W/m^2),", 0) == 0);
}

TEST_CASE("A scene's objects are those holding patches: the loader's empty default object is not one (issue 38 #9)") {
    CHECK(bundledScene("cornell_box.obj").objects.size() == 9);  // "default" and the 8 groups
    CHECK(objectsWithPatches(bundledScene("cornell_box.obj")) == 8);
    Scene s = bundledScene("cornell_box.obj");
    for (Patch& p : s.patches) p.object = 0;  // every patch in "default"
    CHECK(objectsWithPatches(s) == 1);
    s.patches.clear();
    CHECK(objectsWithPatches(s) == 0);
}

TEST_CASE("CSV fields: plain names stay as they are, and a comma, quote or line break is quoted with inner quotes doubled") {
    CHECK(hemirad::csvField("wall") == "wall");
    CHECK(hemirad::csvField("north, 2") == "\"north, 2\"");
    CHECK(hemirad::csvField("the \"big\" one") == "\"the \"\"big\"\" one\"");
    CHECK(hemirad::csvField("two\nlines") == "\"two\nlines\"");
}
