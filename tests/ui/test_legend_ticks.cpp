// Round tick values for the colour bars, and hemirad-gui's frame pacing, without a window.
#include "ui/frame_pacing.hpp"
#include "ui/legend_ticks.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::ui;

namespace {

std::vector<std::string> labels(double min, double max, FalseColourScale scale) {
    FalseColourRange r;
    r.min = min;
    r.max = max;
    r.scale = scale;
    std::vector<std::string> out;
    for (const LegendTick& t : legendTicks(r)) {
        CHECK(t.position >= 0.0);
        CHECK(t.position <= 1.0);
        out.push_back(t.label);
    }
    return out;
}

}  // namespace

TEST_CASE("Legend ticks are round values inside the range, not fractions of it (issue 38 #15: a tick read 0.8751)") {
    CHECK(labels(0.0012, 0.8751, FalseColourScale::Linear) == std::vector<std::string>{"0.2", "0.4", "0.6", "0.8"});
    CHECK(labels(0.0, 100.0, FalseColourScale::Linear) == std::vector<std::string>{"0", "20", "40", "60", "80", "100"});
    CHECK(labels(-1.0, 1.0, FalseColourScale::Linear) == std::vector<std::string>{"-1.0", "-0.5", "0.0", "0.5", "1.0"});
    CHECK(labels(1.07e-4, 1.07, FalseColourScale::Log) == std::vector<std::string>{"0.001", "0.01", "0.1", "1"});
    CHECK(labels(0.3, 2.5, FalseColourScale::Log) == std::vector<std::string>{"0.5", "1", "2"});
}

TEST_CASE("Frame pacing: input that comes while the loop settles restarts the settling frames (issue 38 #15)") {
    FramePacing pacing;
    // Idle: it sleeps until an event.
    while (pacing.next(false, false, false) != FramePacing::Wait::Idle) pacing.eventsProcessed(false);
    // A press wakes it; the release comes with its last settling frame: three frames more follow.
    pacing.eventsProcessed(true);
    CHECK(pacing.next(false, false, false) == FramePacing::Wait::Poll);
    pacing.eventsProcessed(false);
    CHECK(pacing.next(false, false, false) == FramePacing::Wait::Poll);
    pacing.eventsProcessed(true);  // the release
    int after = 0;                 // frames after the one that took the release
    while (pacing.next(false, false, false) == FramePacing::Wait::Poll) {
        pacing.eventsProcessed(false);
        ++after;
    }
    CHECK(after >= 2);
    CHECK(pacing.leastFramesAfterInput() >= FramePacing::kSettleFrames);
    // A running job redraws; a scripted run polls.
    CHECK(pacing.next(false, true, false) == FramePacing::Wait::Job);
    CHECK(pacing.next(true, false, false) == FramePacing::Wait::Poll);
}
