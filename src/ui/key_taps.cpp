// KeyTaps: holds back a key's release until a frame has seen its press.
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
    if (event.action == kRelease && m_pressedSinceFrame.count(event.key)) {
        m_heldBack[event.key].push_back(event);
        return false;
    }
    if (event.action == kPress) m_pressedSinceFrame.insert(event.key);
    return true;
}

std::vector<KeyEvent> KeyTaps::frameEnded() {
    m_pressedSinceFrame.clear();
    std::vector<KeyEvent> now;
    for (auto it = m_heldBack.begin(); it != m_heldBack.end();) {
        const KeyEvent event = it->second.front();
        it->second.pop_front();
        now.push_back(event);
        if (event.action == kPress) m_pressedSinceFrame.insert(event.key);  // its release waits a frame
        it = it->second.empty() ? m_heldBack.erase(it) : std::next(it);
    }
    return now;
}

}  // namespace hemirad::ui
