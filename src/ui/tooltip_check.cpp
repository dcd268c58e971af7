// The tooltip sweep: ImGui's hovered id says an interactive item is under the mouse, the tooltip
// window's activity says whether one was drawn this frame.
#include "ui/tooltip_check.hpp"

#include <imgui.h>
#include <imgui_internal.h>

#include <algorithm>
#include <cstdio>

namespace hemirad::ui {

void TooltipCheck::plan(const std::map<std::string, Panels::Rect>& panels, float dx, float dy) {
    m_dx = dx;
    m_dy = dy;
    for (const auto& [name, rect] : panels)
        if (name != "Status" && name != "LegendBar") m_panels.push_back(name);
    m_planned = true;
    m_finished = m_panels.empty();
    if (!m_finished) {
        if (ImGuiWindow* w = ImGui::FindWindowByName(m_panels.front().c_str())) ImGui::SetScrollY(w, 0.0f);
        m_scroll = 0.0f;
    }
}

void TooltipCheck::buildPage() {
    m_page.clear();
    m_next = 0;
    const ImGuiWindow* w = ImGui::FindWindowByName(m_panels[m_panel].c_str());
    if (!w) return;
    // Borders can be dragged (resize), and a grip sits in each bottom corner.
    const float border = 6.0f, grip = 20.0f;
    const ImRect& inner = w->InnerRect;
    const ImRect outer = w->Rect();
    for (float y = inner.Min.y + 1.0f; y < inner.Max.y - border; y += m_dy)
        for (float x = inner.Min.x + border; x < inner.Max.x - border; x += m_dx) {
            if (y > outer.Max.y - grip && (x < outer.Min.x + grip || x > outer.Max.x - grip)) continue;
            m_page.push_back({x, y, m_scroll, m_panels[m_panel]});
        }
    m_points += m_page.size();
}

void TooltipCheck::nextPage() {
    ImGuiWindow* w = ImGui::FindWindowByName(m_panels[m_panel].c_str());
    if (w && m_scroll + 1.0f < w->ScrollMax.y) {
        // The next page of this panel, overlapping the last by a row of controls. The scroll asked
        // for only grows, so a panel that scrolls itself (the log follows its end) cannot loop.
        const float scroll = std::min(m_scroll + std::max(w->InnerRect.GetHeight() - 30.0f, 20.0f), w->ScrollMax.y);
        ImGui::SetScrollY(w, scroll);  // applied when the panel begins in the coming frame
        m_scroll = scroll;
        buildPage();
        return;
    }
    if (++m_panel >= m_panels.size()) {
        m_finished = true;
        return;
    }
    m_scroll = 0.0f;
    if (ImGuiWindow* next = ImGui::FindWindowByName(m_panels[m_panel].c_str())) ImGui::SetScrollY(next, 0.0f);
    buildPage();
}

void TooltipCheck::placeMouse() {
    if (m_finished) return;
    if (m_page.empty() && m_points == 0) buildPage();
    while (!m_finished && m_next >= m_page.size()) nextPage();
    if (m_finished) return;
    ImGui::GetIO().MousePos = ImVec2(m_page[m_next].x, m_page[m_next].y);
}

void TooltipCheck::observe() {
    if (m_finished || m_next >= m_page.size()) return;
    const Point& at = m_page[m_next++];
    const ImGuiContext& g = *GImGui;
    if (g.HoveredId == 0) return;
    // Only the panel's own items: a point can fall on another window drawn over it.
    if (!g.HoveredWindow || at.panel != g.HoveredWindow->Name) return;
    m_controls.insert(g.HoveredId);
    char name[32];
    std::snprintf(name, sizeof name, "##Tooltip_%02d", g.TooltipOverrideCount);
    const ImGuiWindow* tooltip = ImGui::FindWindowByName(name);
    if (!(tooltip && tooltip->Active)) m_missing.emplace(g.HoveredId, at);
    // Put over the controls below the pointer (ImGui's place, down right of it) where the window had
    // room above (the panels' tooltips are at most 5 lines, under 120 px). Its position, not its
    // size: ImGui's auto-fit size lags a frame behind when the tooltip changes.
    else if (tooltip->Pos.y > at.y && at.y > 150.0f) m_below.emplace(g.HoveredId, at);
}

std::string TooltipCheck::report() const {
    char line[256];
    std::snprintf(line, sizeof line, "tooltips: %zu points, %zu controls hovered, %zu without a tooltip, %zu below the pointer\n",
                  m_points, m_controls.size(), m_missing.size(), m_below.size());
    std::string text = line;
    for (const auto& [id, at] : m_missing) {
        std::snprintf(line, sizeof line, "no tooltip: panel %s at %.0f,%.0f (scrolled %.0f)\n", at.panel.c_str(), at.x, at.y,
                      at.scroll);
        text += line;
    }
    for (const auto& [id, at] : m_below) {
        std::snprintf(line, sizeof line, "tooltip below the pointer: panel %s at %.0f,%.0f (scrolled %.0f)\n", at.panel.c_str(), at.x,
                      at.y, at.scroll);
        text += line;
    }
    return text;
}

}  // namespace hemirad::ui
