// The panels' tooltips: one call after each control, drawn above it so that it never hides the
// controls below (the tolerance's tooltip covered the Run buttons, issue 38 #15).
#pragma once

#include <imgui.h>

namespace hemirad::ui {

/// The last control's tooltip (shown also when it is disabled, to say why), beside the pointer with
/// its bottom edge just above the control; below the control only where the window has no room above.
inline void tip(const char* text) {
    if (!ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) return;
    // Its size from the text, not ImGui's auto-fit, which lags a frame behind when the tooltip changes.
    const float height = ImGui::CalcTextSize(text).y + 2.0f * ImGui::GetStyle().WindowPadding.y;
    const float above = ImGui::GetItemRectMin().y - 4.0f - height;
    const float y = above >= 0.0f ? above : ImGui::GetItemRectMax().y + 4.0f;
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetMousePos().x + 12.0f, y));
    ImGui::SetTooltip("%s", text);
}

}  // namespace hemirad::ui
