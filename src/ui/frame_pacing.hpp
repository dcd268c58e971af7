// When hemirad-gui draws: idle, it sleeps until an event; after any input it draws a few frames more,
// since ImGui acts on a click's release a frame later and shows a popup it opens a frame after that.
// No window here: the event loop asks how to wait and says when input came; tests drive it.
#pragma once

#include <algorithm>

namespace hemirad::ui {

class FramePacing {
public:
    enum class Wait { Poll, Job, Idle };  ///< poll events, wait at most 1/30 s, wait for an event (or 2 s)
    /// How to get the next frame's events: a scripted run polls; a running job redraws 30 times a
    /// second; settling frames (and held-back key taps) poll; else the loop may sleep.
    Wait next(bool scripted, bool jobRunning, bool tapsPending);
    /// Once a frame, after its events were processed; `input`: some arrived (key, character, button,
    /// wheel, pointer, drop). Input restarts the settling frames whether it woke the loop or came
    /// while it was settling (issue 38 #15: a release taken by the last settling frame left the popup
    /// it opened undrawn until the next mouse move).
    void eventsProcessed(bool input);
    /// The fewest frames drawn from a frame that took input to the next sleep (-1: none yet); scripted
    /// runs print it.
    int leastFramesAfterInput() const { return m_least; }

    static constexpr int kSettleFrames = 3;

private:
    int m_settle = kSettleFrames;
    int m_framesSinceInput = -1;
    int m_least = -1;
};

inline FramePacing::Wait FramePacing::next(bool scripted, bool jobRunning, bool tapsPending) {
    if (scripted) return Wait::Poll;
    if (jobRunning) {
        m_settle = kSettleFrames;
        return Wait::Job;
    }
    if (m_settle > 0 || tapsPending) {
        m_settle = std::max(m_settle - 1, 0);
        return Wait::Poll;
    }
    if (m_framesSinceInput >= 0) m_least = m_least < 0 ? m_framesSinceInput : std::min(m_least, m_framesSinceInput);
    m_framesSinceInput = -1;
    m_settle = kSettleFrames - 1;  // after the wait: that frame and two more
    return Wait::Idle;
}

inline void FramePacing::eventsProcessed(bool input) {
    if (input) {
        m_settle = std::max(m_settle, kSettleFrames);
        m_framesSinceInput = 0;
    }
    if (m_framesSinceInput >= 0) ++m_framesSinceInput;
}

}  // namespace hemirad::ui
