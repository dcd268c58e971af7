// hemirad-gui's Sky and sun: the Scene panel's section (the sun from a date, hour and place or a
// direction, DNI and DHI, the sky model, Run and its report, the quantities to show in false colour)
// and the sun's direction drawn over the view. It presents AppState and calls its actions.
#pragma once

#include "ui/app_state.hpp"
#include "ui/orbit_camera.hpp"

#include <string>
#include <vector>

namespace hemirad::ui {

class SunSkyPanel {
public:
    /// The Scene panel's Sky and sun section.
    void section(AppState& app);
    /// The last result's sun as a line from the scene's centre toward it, with a disc at its end,
    /// over the view (the background draw list: under the panels); nothing without a result.
    void drawSun(const AppState& app, const OrbitCamera& camera, float width, float height);
    /// The result lines the section drew in the last frame, and where the sun's disc was drawn
    /// (window pixels; none when it was not): scripted runs print them.
    const std::vector<std::string>& resultLines() const { return m_resultLines; }
    const std::vector<float>& sunMark() const { return m_sunMark; }

private:
    char m_time[64] = {};
    bool m_synced = false;
    bool m_openedForResult = false;  ///< the section was opened for the result there is
    std::vector<std::string> m_resultLines;
    std::vector<float> m_sunMark;
};

}  // namespace hemirad::ui
