// hemirad-gui's Sky and sun section and the sun over the view (ImGui).
#include "ui/sun_sky_panel.hpp"

#include <imgui.h>

#include <Eigen/Dense>

#include <cstdio>
#include <sstream>

namespace hemirad::ui {
namespace {

void tip(const char* text) {
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("%s", text);
}

std::string figure(double v, int digits = 6) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    return s.str();
}

/// The sky models the section offers (hemirad irradiance --sky).
const char* kSkies[] = {"isotropic", "uniform", "cie-overcast", "cie:1",  "cie:2",  "cie:3",  "cie:4",  "cie:5", "cie:6",
                        "cie:7",     "cie:8",   "cie:9",        "cie:10", "cie:11", "cie:12", "cie:13", "cie:14", "cie:15", "perez"};

struct Shown {
    FalseColourSettings::Sun quantity;
    const char* label;
    const char* help;
};
const Shown kShown[] = {
    {FalseColourSettings::Sun::SunlitFraction, "Sunlit", "Each patch's sunlit fraction (exact shadow polygons), 0..1"},
    {FalseColourSettings::Sun::SkyView, "Sky view", "The sky view factor: the sky seen directly (the isotropic sky's run)"},
    {FalseColourSettings::Sun::DirectSun, "Direct sun", "DNI x cos x the sunlit fraction, W/m^2"},
    {FalseColourSettings::Sun::DirectSky, "Direct sky", "The sky's irradiance past the scene's shadows, W/m^2"},
    {FalseColourSettings::Sun::Reflected, "Reflected", "What the other patches reflect onto it (through F), W/m^2"},
    {FalseColourSettings::Sun::Total, "Total", "Everything arriving: sun, sky, mirrors' reflections and the rest, W/m^2"},
    {FalseColourSettings::Sun::Absorbed, "Absorbed", "(1 - rho - s) x the total, W/m^2"},
};

}  // namespace

void SunSkyPanel::section(AppState& app) {
    m_resultLines.clear();
    if (!app.hasScene()) return;
    // The section opens by itself the first time there is a result (--sun-sky, or a run from elsewhere).
    const bool result = app.sunSkyResult() != nullptr;
    if (result && !m_openedForResult) ImGui::SetNextItemOpen(true);
    m_openedForResult = result;
    const bool open = ImGui::CollapsingHeader("Sky and sun");
    tip("One hour of sun and sky on the scene (hemirad irradiance): sunlit fractions, sky view factors,\n"
        "the direct, reflected, total and absorbed irradiance per patch, in false colour");
    // The results stay readable (scripted runs print them) with the section closed.
    if (const SunSkyResult* r = app.sunSkyResult()) {
        const IrradianceResult& e = r->irradiance;
        m_resultLines.push_back("sun: " + r->where);
        m_resultLines.push_back("sky: " + r->setup.sky + ", DNI " + figure(r->setup.dni) + " W/m^2, DHI " + figure(r->setup.dhi) + " W/m^2");
        m_resultLines.push_back(figure(e.incidentPower) + " W arrive, " + figure(e.absorbedPower) + " W absorbed, " +
                                figure(e.escapedPower) + " W leave; balance " + figure(e.balance, 3));
    }
    if (!open) return;
    SunSkySetup& s = app.sunSky;
    if (!m_synced) {
        std::snprintf(m_time, sizeof m_time, "%s", s.time.c_str());
        m_synced = true;
    }
    if (ImGui::RadioButton("Time and place", s.byTime)) s.byTime = true;
    tip("The sun's position at a time (UTC, or with an offset) and a place (Michalsky 1988)");
    ImGui::SameLine();
    if (ImGui::RadioButton("Direction", !s.byTime)) s.byTime = false;
    tip("A direction toward the sun in the scene's frame");
    if (s.byTime) {
        ImGui::SetNextItemWidth(200);
        if (ImGui::InputText("Time", m_time, sizeof m_time)) s.time = m_time;
        tip("YYYY-MM-DDTHH:MM[:SS] with Z, +HH:MM or -HH:MM (none: UTC)");
        ImGui::SetNextItemWidth(90);
        ImGui::InputDouble("Latitude", &s.latitude, 0.0, 0.0, "%.4f");
        tip("Degrees north (south negative)");
        ImGui::SameLine();
        ImGui::SetNextItemWidth(90);
        ImGui::InputDouble("Longitude", &s.longitude, 0.0, 0.0, "%.4f");
        tip("Degrees east (west negative)");
    } else {
        float d[3] = {float(s.direction.x()), float(s.direction.y()), float(s.direction.z())};
        ImGui::SetNextItemWidth(240);
        if (ImGui::InputFloat3("Toward the sun", d, "%.3f")) s.direction = Vec3(d[0], d[1], d[2]);
        tip("x, y, z in the scene's frame (any length)");
    }
    ImGui::SetNextItemWidth(90);
    ImGui::InputDouble("DNI", &s.dni, 0.0, 0.0, "%.6g");
    tip("Direct-normal irradiance, W/m^2");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(90);
    ImGui::InputDouble("DHI", &s.dhi, 0.0, 0.0, "%.6g");
    tip("Diffuse-horizontal irradiance of the sky, W/m^2");
    ImGui::SetNextItemWidth(140);
    if (ImGui::BeginCombo("Sky", s.sky.c_str())) {
        for (const char* sky : kSkies)
            if (ImGui::Selectable(sky, s.sky == sky)) s.sky = sky;
        ImGui::EndCombo();
    }
    tip("isotropic: DHI x each patch's exact sky view factor; a model (CIE, Perez): its radiance over the\n"
        "sky's cells through daylight coefficients, the sky through mirrors too (hemirad help: --sky)");
    const bool busy = app.job().running;
    ImGui::BeginDisabled(busy);
    if (ImGui::Button("Run sky and sun")) app.runSunSky();
    ImGui::EndDisabled();
    tip("Every row of F (reused when current), then the hour: sunlit fractions, the sky, the inter-reflection");
    if (m_resultLines.empty()) {
        ImGui::TextDisabled("no sky-and-sun result yet");
        return;
    }
    ImGui::PushTextWrapPos(0.0f);
    for (const std::string& line : m_resultLines) ImGui::TextUnformatted(line.c_str());
    if (app.sunSkyStale()) ImGui::TextColored(ImVec4(1, 0.9f, 0.3f, 1), "out of date: the scene changed since; Run sky and sun");
    ImGui::PopTextWrapPos();
    ImGui::TextUnformatted("Show");
    for (const Shown& q : kShown) {
        ImGui::SameLine();
        const bool on = app.layer == Layer::FalseColour && app.falseColour.sun == q.quantity;
        if (ImGui::RadioButton(q.label, on)) {
            app.layer = Layer::FalseColour;
            app.falseColour.sun = q.quantity;
            app.falseColour.automatic = true;
        }
        tip(q.help);
    }
}

void SunSkyPanel::drawSun(const AppState& app, const OrbitCamera& camera, float width, float height) {
    m_sunMark.clear();
    const SunSkyResult* r = app.sunSkyResult();
    if (!r || !(width > 0 && height > 0)) return;
    const Scene& scene = app.scene();
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const Vec3& v : scene.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    if (!(lo.array() <= hi.array()).all()) return;
    const Vec3 centre = 0.5 * (lo + hi);
    const Vec3 end = centre + 0.6 * (hi - lo).norm() * r->toSun;
    const Eigen::Matrix4d clip = camera.projection(double(width) / double(height)) * camera.view();
    const auto screen = [&](const Vec3& p, ImVec2& out) {
        const Eigen::Vector4d c = clip * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
        if (!(c.w() > 1e-9)) return false;  // behind the eye
        out = ImVec2(float((c.x() / c.w() * 0.5 + 0.5) * width), float((0.5 - c.y() / c.w() * 0.5) * height));
        return true;
    };
    ImVec2 a, b;
    if (!screen(centre, a) || !screen(end, b)) return;
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const ImU32 yellow = IM_COL32(255, 214, 40, 255);
    draw->AddLine(a, b, yellow, 2.0f);
    draw->AddCircleFilled(b, 9.0f, yellow);
    draw->AddText(ImVec2(b.x + 12, b.y - 7), yellow, "sun");
    m_sunMark = {b.x, b.y};
}

}  // namespace hemirad::ui
