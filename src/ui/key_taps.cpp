// KeyTaps: holds back a key's second change until a frame has seen the first.
#include "ui/key_taps.hpp"

#include <iterator>

namespace hemirad::ui {

bool KeyTaps::pass(const KeyEvent& event) {
    if (event.action != kPress && event.action != kRelease) return true;  // repeats change no state
    auto queued = m_heldBack.find(event.key);
    if (queued != m_heldBack.end()) {  // keep the key's order: behind what is already held back
        queued->second.push_back(event);
        return false;
    }
    // A second change before a frame has seen the first (a release after a press, or a press after
    // a release) waits: the frame would see no change at all.
    if (m_changedSinceFrame.count(event.key)) {
        m_heldBack[event.key].push_back(event);
        return false;
    }
    m_changedSinceFrame.insert(event.key);
    return true;
}

std::vector<KeyEvent> KeyTaps::frameEnded() {
    m_changedSinceFrame.clear();
    std::vector<KeyEvent> now;
    for (auto it = m_heldBack.begin(); it != m_heldBack.end();) {
        now.push_back(it->second.front());
        it->second.pop_front();
        m_changedSinceFrame.insert(it->first);  // its next change waits a frame
        it = it->second.empty() ? m_heldBack.erase(it) : std::next(it);
    }
    return now;
}

}  // namespace hemirad::ui
