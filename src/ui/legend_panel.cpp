// hemirad-gui's Legend panel: the false colour's settings and colour bar, or the F-row layer's
// scale; both bars labelled with round values where they fall (legendTicks).
#include "ui/legend_ticks.hpp"
#include "ui/panel_tip.hpp"
#include "ui/panels.hpp"
#include "ui/units.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hemirad::ui {
namespace {

/// The F-row layer's ramp (viewer_present.frag's ramp), 8-bit.
std::array<std::uint8_t, 3> rowRamp(double t) {
    const double c[3] = {-0.3 + 1.6 * t, 0.1 + 0.9 * t * (1.4 - t) + 0.3 * t, 0.6 - 0.5 * t + 0.3 * (1.0 - t)};
    std::array<std::uint8_t, 3> rgb{};
    for (int k = 0; k < 3; ++k) rgb[k] = std::uint8_t(std::lround(std::clamp(c[k], 0.0, 1.0) * 255.0));
    return rgb;
}

}  // namespace

void Panels::legendPanel(AppState& app) {
    // The false-colour settings, then the legend: title, unit, the bar (max on top), round values, the range.
    FalseColourSettings& fc = app.falseColour;
    m_legend = {};
    // Radiosity's three, the thermal two, then Sky and sun's seven (FalseColourSettings::Sun's order).
    static const char* kQuantities[] = {"radiosity B", "irradiance H", "emission E", "temperature T (thermal)",
                                        "net heat flux q (thermal)", "sunlit fraction (sun)", "sky view factor (sun)",
                                        "direct sun (sun)", "direct sky (sun)", "reflected (sun)", "total irradiance (sun)",
                                        "absorbed (sun)"};
    int quantity = fc.sun != FalseColourSettings::Sun::None            ? 4 + int(fc.sun)
                   : fc.thermal == FalseColourSettings::Thermal::None ? int(fc.quantity)
                                                                      : 2 + int(fc.thermal);
    if (ImGui::Combo("##quantity", &quantity, kQuantities, IM_ARRAYSIZE(kQuantities))) {
        fc.sun = quantity < 5 ? FalseColourSettings::Sun::None : FalseColourSettings::Sun(quantity - 4);
        fc.thermal = quantity < 3 || quantity >= 5 ? FalseColourSettings::Thermal::None : FalseColourSettings::Thermal(quantity - 2);
        if (quantity < 3) fc.quantity = FalseColourQuantity(quantity);
    }
    tip("Radiosity B (what leaves), irradiance H = (B - E)/rho (what a meter on the surface reads),\n"
        "or emission E; all in W/m^2 as luminance Y. Thermal: the last Run thermal's temperature T (K)\n"
        "or net heat flux q leaving each patch (W/m^2). Sun: the last Run sky and sun's sunlit fraction,\n"
        "sky view factor, or irradiance's parts (W/m^2)");
    int scale = int(fc.scale);
    ImGui::RadioButton("linear", &scale, 0);
    tip("Colours evenly spaced in the value");
    ImGui::SameLine();
    ImGui::RadioButton("log", &scale, 1);
    tip("Colours evenly spaced in the value's logarithm (for ranges over decades; values <= 0 show as the minimum);\n"
        "the automatic range spans at most 4 decades: its minimum is at least max/1e4");
    fc.scale = FalseColourScale(scale);
    ImGui::Checkbox("automatic range", &fc.automatic);
    tip("The range is the values' minimum and maximum (log: the minimum at least max/1e4); off: type min and max");
    const FalseColourView view = app.falseColourView();
    if (fc.automatic) {
        fc.min = view.range.min;  // the fields start from the data when switched to manual
        fc.max = view.range.max;
    } else {
        ImGui::InputDouble("max", &fc.max, 0.0, 0.0, "%.4g");
        tip("The value at the top of the colour bar (in the legend's unit); larger values show its colour");
        ImGui::InputDouble("min", &fc.min, 0.0, 0.0, "%.4g");
        tip("The value at the bottom of the colour bar (in the legend's unit); smaller values show its colour");
    }
    if (!view.error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.4f, 1.0f));
        ImGui::TextWrapped("%s", view.error.c_str());
        ImGui::PopStyleColor();
    } else {
        m_legend = app.falseColourLegend();
        ImGui::Text("%s", m_legend.first.c_str());
        ImGui::TextDisabled("%s", m_legend.second.c_str());
        char note[160];
        std::snprintf(note, sizeof note, "%s scale %s .. %s%s%s", falseColourScaleName(view.range.scale), formatNumber(view.range.min).c_str(),
                      formatNumber(view.range.max).c_str(), view.range.automatic ? ", " : "", falseColourRangeNote(view.range).c_str());
        colourBar(view.range, [](double t) { return viridis(t); }, note);
    }
    if (view.noData) {
        ImGui::ColorButton("##nodata", ImVec4(0.5f, 0.5f, 0.5f, 1.0f), ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
        ImGui::SameLine();
        ImGui::TextDisabled(!view.error.empty() ? "no data"
                            : fc.sun != FalseColourSettings::Sun::None         ? "no data"
                            : fc.thermal == FalseColourSettings::Thermal::None ? "no data (rho = 0)"
                                                                               : "no data (eps = 0: no temperature)");
    }
}

void Panels::rowLegendPanel(AppState& app) {
    // F from the selected patch i to every patch j: the fraction of the power leaving i that reaches
    // j, coloured on a log scale over the 4 decades below the row's largest factor (as the view).
    if (app.selection().empty()) {
        ImGui::TextWrapped("Select a patch: the view colours every patch by F from it.");
        return;
    }
    const PatchId i = app.selection().front();
    if (m_rowPatch != i || m_rowRevision != app.revision() || m_rowF != app.formFactors()) {
        const std::vector<float> row = app.formFactorRow(i);
        m_rowPatch = i;
        m_rowRevision = app.revision();
        m_rowF = app.formFactors();
        m_rowMax = row.empty() ? 0.0 : double(*std::max_element(row.begin(), row.end()));
    }
    ImGui::Text("F from patch %u", i);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("fraction of the power leaving patch %u that reaches each patch", i);
    ImGui::PopTextWrapPos();
    if (!(m_rowMax > 0.0)) {
        ImGui::TextDisabled("its row of F is not computed (no F yet, or a black patch)");
        return;
    }
    FalseColourRange range;
    range.scale = FalseColourScale::Log;
    range.max = m_rowMax;
    range.min = m_rowMax * 1e-4;
    range.automatic = false;
    colourBar(range, rowRamp, "log scale " + formatNumber(range.min) + " .. " + formatNumber(range.max) +
                                  " (4 decades below the row's largest factor; less shows the bottom colour)");
    ImGui::ColorButton("##unseen", ImVec4(0.05f, 0.05f, 0.05f, 1.0f), ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
    tip("Patches this one does not see (F = 0)");
    ImGui::SameLine();
    ImGui::TextDisabled("F = 0: not seen");
}

void Panels::colourBar(const FalseColourRange& range, const std::function<std::array<std::uint8_t, 3>(double)>& colourAt,
                       const std::string& note) {
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float barWidth = 24.0f, barHeight = std::max(60.0f, std::min(220.0f, ImGui::GetContentRegionAvail().y - 40.0f));
    const float x0 = std::floor(origin.x), y0 = std::floor(origin.y + 6.0f);
    const int rows = int(barHeight);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (int y = 0; y < rows; ++y) {
        const auto c = colourAt(double(rows - 1 - y) / double(rows - 1));
        draw->AddRectFilled(ImVec2(x0, y0 + y), ImVec2(x0 + barWidth, y0 + y + 1), IM_COL32(c[0], c[1], c[2], 255));
    }
    m_panelRects["LegendBar"] = {x0, y0, barWidth, float(rows)};
    // Round values where they fall on the bar (issue 38 #15: five fractions of the range read "0.8751").
    for (const LegendTick& tick : ui::legendTicks(range)) {
        const float y = y0 + float(rows - 1) * float(1.0 - tick.position);
        draw->AddLine(ImVec2(x0 + barWidth, y), ImVec2(x0 + barWidth + 5, y), IM_COL32(230, 230, 230, 255));
        draw->AddText(ImVec2(x0 + barWidth + 9, y - 7), IM_COL32(230, 230, 230, 255), tick.label.c_str());
        m_legendTicks.push_back(tick.label);
    }
    ImGui::Dummy(ImVec2(barWidth + 80, barHeight + 12));
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("%s", note.c_str());
    ImGui::PopTextWrapPos();
}

}  // namespace hemirad::ui
