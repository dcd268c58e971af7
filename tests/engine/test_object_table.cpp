// Per-object summaries: objects count when they hold patches.
#include "support.hpp"

#include "engine/object_table.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

TEST_CASE("A scene's objects are those holding patches: the loader's empty default object is not one (issue 38 #9)") {
    CHECK(bundledScene("cornell_box.obj").objects.size() == 9);  // "default" and the 8 groups
    CHECK(objectsWithPatches(bundledScene("cornell_box.obj")) == 8);
    Scene s = bundledScene("cornell_box.obj");
    for (Patch& p : s.patches) p.object = 0;  // every patch in "default"
    CHECK(objectsWithPatches(s) == 1);
    s.patches.clear();
    CHECK(objectsWithPatches(s) == 0);
}
