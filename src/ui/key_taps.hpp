// Key taps that outlast a frame: ImGui 1.86 reads key state once a frame (io.KeysDown), so a key pressed
// and released between two frames (a quick tap while a frame is slow: a big scene, a software
// renderer, a sanitizer build) is never seen, nor is a second tap of a key whose release a frame has
// not seen. KeyTaps holds a key's second change back until a frame has seen the first: at most one
// change of state per key per frame. (Keys are ordered per key only: a held-back modifier release
// does not hold back other keys.)
#pragma once

#include <deque>
#include <map>
#include <set>
#include <vector>

namespace hemirad::ui {

/// One key event as GLFW reports it (action: 0 release, 1 press, 2 repeat).
struct KeyEvent {
    int key = 0;
    int scancode = 0;
    int action = 0;
    int mods = 0;
};

/// Not thread-safe: called from the thread that polls the window's events.
class KeyTaps {
public:
    static constexpr int kRelease = 0;
    static constexpr int kPress = 1;

    /// True when the event goes on to ImGui now; false when it is held back for frameEnded().
    bool pass(const KeyEvent& event);
    /// Call once a frame after ImGui::Render, never between NewFrame and Render (ImGui asserts that the
    /// modifiers do not change within a frame): the held-back events to deliver now, at most one per key.
    std::vector<KeyEvent> frameEnded();
    /// True while events are held back (the event loop should draw another frame without waiting).
    bool pending() const { return !m_heldBack.empty(); }

private:
    std::set<int> m_changedSinceFrame;              ///< keys whose last change no frame has seen yet
    std::map<int, std::deque<KeyEvent>> m_heldBack;  ///< per key, in the order they arrived
};

}  // namespace hemirad::ui
