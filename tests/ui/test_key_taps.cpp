// KeyTaps: a key tapped between two frames is seen by a frame, and each key changes once per frame.
#include "ui/key_taps.hpp"

#include <doctest/doctest.h>

using namespace hemirad::ui;

namespace {
constexpr int kEnter = 257, kCtrl = 341, kO = 79;
KeyEvent press(int key) { return {key, 0, KeyTaps::kPress, 0}; }
KeyEvent release(int key) { return {key, 0, KeyTaps::kRelease, 0}; }
}  // namespace

TEST_CASE("GUI key taps: a press and release between two frames reach ImGui on two frames") {
    KeyTaps taps;
    CHECK(taps.frameEnded().empty());
    // A tap between frames: the press goes on, the release waits for the frame that sees the press.
    CHECK(taps.pass(press(kEnter)));
    CHECK_FALSE(taps.pass(release(kEnter)));
    CHECK(taps.pending());
    const std::vector<KeyEvent> later = taps.frameEnded();
    REQUIRE(later.size() == 1);
    CHECK(later[0].key == kEnter);
    CHECK(later[0].action == KeyTaps::kRelease);
    CHECK_FALSE(taps.pending());
    // A second tap before the frame that sees that release: its press waits for the next frame.
    CHECK_FALSE(taps.pass(press(kEnter)));
    CHECK_FALSE(taps.pass(release(kEnter)));
    std::vector<KeyEvent> now = taps.frameEnded();
    REQUIRE(now.size() == 1);
    CHECK(now[0].action == KeyTaps::kPress);
    now = taps.frameEnded();
    REQUIRE(now.size() == 1);
    CHECK(now[0].action == KeyTaps::kRelease);
    CHECK(taps.frameEnded().empty());
    // A press a frame has seen is released at once; repeats are never held.
    CHECK(taps.pass(press(kEnter)));
    CHECK(taps.frameEnded().empty());
    CHECK(taps.pass({kEnter, 0, 2, 0}));
    CHECK(taps.pass(release(kEnter)));
}

TEST_CASE("GUI key taps: a release then a press of a held key between two frames keep the break for a frame") {
    KeyTaps taps;
    CHECK(taps.pass(press(kO)));
    CHECK(taps.frameEnded().empty());  // a frame sees O down
    CHECK(taps.pass(release(kO)));     // the release goes on ...
    CHECK_FALSE(taps.pass(press(kO)));  // ... the new press waits, or the next frame would see no change
    const std::vector<KeyEvent> now = taps.frameEnded();
    REQUIRE(now.size() == 1);
    CHECK(now[0].action == KeyTaps::kPress);
}

TEST_CASE("GUI key taps: two taps of one key within a frame give two presses, one change per frame, other keys unaffected") {
    KeyTaps taps;
    CHECK(taps.pass(press(kCtrl)));
    CHECK(taps.pass(press(kO)));
    CHECK_FALSE(taps.pass(release(kO)));
    CHECK_FALSE(taps.pass(press(kO)));  // behind its own release
    CHECK_FALSE(taps.pass(release(kO)));
    CHECK_FALSE(taps.pass(release(kCtrl)));
    std::vector<KeyEvent> now = taps.frameEnded();  // ordered by key: O (79), then Ctrl (341)
    REQUIRE(now.size() == 2);
    CHECK(now[0].key == kO);
    CHECK(now[0].action == KeyTaps::kRelease);
    CHECK(now[1].key == kCtrl);
    CHECK(now[1].action == KeyTaps::kRelease);
    now = taps.frameEnded();  // O's second press, a frame later
    REQUIRE(now.size() == 1);
    CHECK(now[0].key == kO);
    CHECK(now[0].action == KeyTaps::kPress);
    CHECK(taps.pass(press(kEnter)));  // another key is not held behind O
    now = taps.frameEnded();  // O's second release, once a frame has seen its press
    REQUIRE(now.size() == 1);
    CHECK(now[0].key == kO);
    CHECK(now[0].action == KeyTaps::kRelease);
    CHECK_FALSE(taps.pending());
}
