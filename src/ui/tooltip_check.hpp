// A scripted check that every control of the panels has a tooltip: the mouse is moved over a grid of
// points inside each panel, one point per frame, page by page down its scrolled content, and wherever
// ImGui reports an interactive item under it (a button, field, checkbox, slider, combo), a tooltip
// must be drawn in that frame.
#pragma once

#include "ui/panels.hpp"

#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace hemirad::ui {

class TooltipCheck {
public:
    /// Starts the sweep over the named panels (the status bar and the legend's bar have no controls).
    /// The grid's step `dx` x `dy` pixels hits every control: ImGui's smallest (a checkbox, a +/-
    /// button) is a 19 px square.
    void plan(const std::map<std::string, Panels::Rect>& panels, float dx = 12.0f, float dy = 9.0f);
    bool planned() const { return m_planned; }
    bool finished() const { return m_finished; }
    /// Between the platform back end's NewFrame and ImGui::NewFrame: puts the mouse on the next point
    /// (scrolling the panel to its next page, or going to the next panel, when a page is done).
    void placeMouse();
    /// After the panels are drawn (before ImGui::Render): notes the item under the mouse, if any, and
    /// whether a tooltip was drawn for it.
    void observe();
    /// "N points, M controls hovered, K without a tooltip, L below the pointer" and a line per
    /// control without one or whose tooltip reaches below the pointer (over the controls under it)
    /// although the window had room for it above.
    std::string report() const;
    std::size_t missing() const { return m_missing.size(); }
    std::size_t below() const { return m_below.size(); }

private:
    struct Point {
        float x, y, scroll;
        std::string panel;
    };
    /// The points of the current panel's visible content, clear of ImGui's own chrome (title bar,
    /// borders, scrollbar, resize grips).
    void buildPage();
    void nextPage();

    float m_dx = 12.0f, m_dy = 9.0f;
    std::vector<std::string> m_panels;
    std::size_t m_panel = 0;
    float m_scroll = 0.0f;
    std::vector<Point> m_page;
    std::size_t m_next = 0;
    std::size_t m_points = 0;
    bool m_planned = false, m_finished = false;
    std::set<unsigned> m_controls;        ///< ImGui ids of the items hovered
    std::map<unsigned, Point> m_missing;  ///< items hovered without a tooltip: where first
    std::map<unsigned, Point> m_below;    ///< items whose tooltip reached below the pointer: where first
};

}  // namespace hemirad::ui
