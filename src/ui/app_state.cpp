// hemirad-gui application state: the scene, selection, the log and what the views read; edits,
// meshing, the worker job and file exports live in app_state_*.cpp.
#include "ui/app_state.hpp"

#include "engine/error.hpp"
#include "engine/obj_writer.hpp"
#include "engine/scene_loader.hpp"
#include "engine/tone_map.hpp"
#include "engine/vertex_radiosity.hpp"

#include <algorithm>
#include <exception>
#include <sstream>

namespace hemirad::ui {

using Clock = std::chrono::steady_clock;

void AppState::addLog(const std::string& text, bool isError) {
    m_log.push_back({std::chrono::duration<double>(Clock::now() - m_start).count(), text, isError});
    if (m_log.size() > 2000) m_log.erase(m_log.begin(), m_log.begin() + 500);
}

bool AppState::isSelected(PatchId id) const {
    return std::find(m_selection.begin(), m_selection.end(), id) != m_selection.end();
}

FalseColourView AppState::falseColourView() const {
    FalseColourView view;
    if (!hasScene()) return view;
    const auto pack = [](const std::array<std::uint8_t, 3>& c) { return std::uint32_t(c[0]) << 16 | std::uint32_t(c[1]) << 8 | c[2]; };
    view.colours.assign(m_scene->size(), pack(kFalseColourNoData));
    try {
        std::vector<double> values;
        if (falseColour.sun != FalseColourSettings::Sun::None) {
            values = sunSkyValues(falseColour.sun);
        } else if (falseColour.thermal == FalseColourSettings::Thermal::None) {
            values = falseColourValues(*m_scene, m_B, falseColour.quantity);
        } else {
            const ThermalResult* t = thermalResult();
            if (!t) throw Error("no thermal result: load the thermal files and press Run thermal (Scene panel)");
            values = falseColour.thermal == FalseColourSettings::Thermal::Temperature ? t->solution.T : t->solution.q;
        }
        view.range = falseColourRange(values, falseColour.scale, falseColour.automatic ? std::nullopt : std::optional<double>(falseColour.min),
                                      falseColour.automatic ? std::nullopt : std::optional<double>(falseColour.max));
        for (PatchId i = 0; i < m_scene->size(); ++i) {
            view.noData |= std::isnan(values[i]);
            view.colours[i] = pack(falseColourOf(values[i], view.range));
        }
    } catch (const std::exception& e) {
        view.error = e.what();
        view.noData = true;  // every patch is the no-data grey
    }
    return view;
}

std::pair<std::string, std::string> AppState::falseColourLegend() const {
    if (falseColour.sun != FalseColourSettings::Sun::None) return sunSkyLegend(falseColour.sun);
    switch (falseColour.thermal) {
    case FalseColourSettings::Thermal::Temperature: return {"temperature T", "K"};
    case FalseColourSettings::Thermal::HeatFlux: return {"net heat flux q", "W/m^2, leaving the surface"};
    case FalseColourSettings::Thermal::None: break;
    }
    return {falseColourTitle(falseColour.quantity), falseColourUnit(falseColour.quantity)};
}

std::optional<PatchReadout> AppState::readout(PatchId j) const {
    if (!hasScene() || j >= m_scene->size()) return std::nullopt;
    const Patch& p = m_scene->patches[j];
    PatchReadout r;
    r.patch = j;
    r.object = p.object < m_scene->objects.size() ? m_scene->objects[p.object] : std::string("?");
    r.sourceLine = p.sourceLine;
    r.area = p.area;
    r.B = j < m_B.size() ? m_B[j] : p.emission;
    for (int c = 0; c < 3; ++c)
        r.H[c] = p.rho[c] > 0.0 ? (r.B[c] - p.emission[c]) / p.rho[c] : std::numeric_limits<double>::quiet_NaN();
    r.emission = p.emission;
    r.rho = p.rho;
    r.specular = p.specular;
    if (!m_selection.empty() && m_selection.front() != j) {
        r.selected = m_selection.front();
        // Only an F of this mesh: after meshing its ids are another mesh's.
        if (m_F && m_F->size() == m_scene->size() && m_F->rowComputed(*r.selected)) r.fromSelected = m_F->at(*r.selected, j);
    }
    return r;
}

SelectionSummary AppState::selectionSummary() const {
    SelectionSummary sum;
    if (!hasScene()) return sum;
    std::vector<bool> objectSeen(m_scene->objects.size() + 1, false);
    for (PatchId i : m_selection) {
        const Patch& p = m_scene->patches[i];
        const std::size_t object = std::min<std::size_t>(p.object, m_scene->objects.size());
        sum.objects += !objectSeen[object];
        objectSeen[object] = true;
        ++sum.patches;
        sum.area += p.area;
        sum.emission += p.area * p.emission;
        sum.rho += p.area * p.rho;
        sum.specular += p.area * p.specular;
        if (i < m_B.size()) sum.power += p.area * m_B[i];
    }
    if (sum.area > 0.0) {
        sum.emission /= sum.area;
        sum.rho /= sum.area;
        sum.specular /= sum.area;
        sum.radiosity = sum.power / sum.area;
    }
    return sum;
}

void AppState::setScene(Scene scene, const std::string& path) {
    cancel();
    wait();
    poll();
    m_scene = std::make_unique<Scene>(std::move(scene));
    m_source = std::make_unique<const Scene>(*m_scene);
    ++m_sceneId;
    ++m_meshRevision;
    m_meshEdges.assign(std::max<std::size_t>(m_scene->objects.size(), 1), 0.0);
    m_scenePath = path;
    m_upSource = m_scene->up ? UpAxisSource::Stated : UpAxisSource::Guessed;
    m_F.reset();
    m_fSettings.reset();
    m_stats.reset();
    m_B.assign(m_scene->size(), Rgb::Zero());
    for (PatchId i = 0; i < m_scene->size(); ++i) m_B[i] = m_scene->patches[i].emission;
    m_reports.clear();
    m_timings.clear();
    m_selection.clear();
    m_undo.clear();
    m_redo.clear();
    m_fStale = false;
    m_bStale = true;
    m_cleanDepth = 0;
    m_pendingResolve = false;
    // Thermal files name objects of the scene they were loaded for.
    m_thermal = {};
    m_thermalLoadError.clear();
    m_thermalResult.reset();
    ++m_thermalRevision;
    m_sunSkyResult.reset();  // another scene's sun and sky (the inputs stay: a place and an hour)
    bump();
}

bool AppState::loadScene(const std::string& path) {
    try {
        std::vector<std::string> warnings;
        Warnings sink([&](const std::string& m) { warnings.push_back(m); });
        Scene scene = hemirad::loadScene(path, sink, loading);
        const int stated = scene.up;
        if (const int remembered = upAxes.recall(path); remembered && remembered != stated) scene.up = remembered;
        setScene(std::move(scene), path);
        if (m_scene->up != stated) m_upSource = UpAxisSource::Remembered;
        for (const std::string& w : warnings) addLog("warning: " + w, false);
        std::ostringstream msg;
        msg << "loaded " << path << ": " << m_scene->size() << " patches" << (m_scene->hasMirrors() ? ", with mirrors" : "");
        if (sink.count()) msg << "; " << sink.summary();
        msg << "; up axis " << upAxisName(upAxis()) << ", " << upAxisSourceText(m_upSource);
        info(msg.str());
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

void AppState::setUnit(const std::string& unit) {
    if (!hasScene() || unit == m_scene->unit) return;
    try {
        metresPerUnit(unit);
    } catch (const std::exception& e) {
        error(e.what());
        return;
    }
    m_scene->unit = unit;
    auto source = std::make_unique<Scene>(*m_source);
    source->unit = unit;
    m_source = std::move(source);
    info(unit.empty() ? std::string("scene unit: not stated") : "scene unit: " + unit + " (saved with the scene)");
}

void AppState::setUpAxis(int axis) {
    if (!hasScene() || (axis != 1 && axis != 2)) return;
    if (!m_scenePath.empty()) upAxes.remember(m_scenePath, axis);
    if (m_scene->up == axis && m_upSource != UpAxisSource::Guessed) return;
    m_scene->up = axis;
    auto source = std::make_unique<Scene>(*m_source);
    source->up = axis;
    m_source = std::move(source);
    m_upSource = UpAxisSource::Remembered;
    info(std::string("up axis: ") + upAxisName(axis) + " (saved with the scene, remembered for this file)");
}

bool AppState::saveScene(const std::string& path) {
    if (!hasScene()) return false;
    try {
        saveObj(*m_scene, path);
        m_scenePath = path;
        m_cleanDepth = m_undo.size();
        info("saved " + path + " (and its .mtl)");
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

void AppState::select(PatchId id, bool additive) {
    if (!hasScene() || id >= m_scene->size()) return;
    if (!additive) m_selection.clear();
    std::vector<PatchId> add{id};
    if (selectionMode == SelectionMode::Object) {
        add.clear();
        const std::uint32_t object = m_scene->patches[id].object;
        for (PatchId i = 0; i < m_scene->size(); ++i)
            if (m_scene->patches[i].object == object) add.push_back(i);
    }
    for (PatchId i : add)
        if (!isSelected(i)) m_selection.push_back(i);
}

void AppState::clearSelection() { m_selection.clear(); }

std::vector<ObjectSummary> AppState::objectTable() const {
    return hasScene() ? summarizeObjects(*m_scene, m_B) : std::vector<ObjectSummary>{};
}

std::vector<float> AppState::formFactorRow(PatchId i) const {
    // An F of another mesh (stale after meshing) has other patch ids.
    if (!m_F || !hasScene() || m_F->size() != m_scene->size() || i >= m_F->size() || !m_F->rowComputed(i)) return {};
    std::vector<float> row(m_scene->size(), 0.0f);
    for (std::uint64_t k = m_F->rowBegin(i); k < m_F->rowEnd(i); ++k)
        row[m_F->columns()[k]] = static_cast<float>(m_F->values()[k]);  // for display: the legend and the GPU's colours
    return row;
}

const std::vector<Rgb>& AppState::cornerRadiosity() {
    if (m_cornerRevision != m_revision || m_corner.size() != (hasScene() ? m_scene->corners.size() : 0)) {
        m_corner = hasScene() ? hemirad::cornerRadiosity(*m_scene, m_B, creaseDegrees) : std::vector<Rgb>{};
        m_cornerRevision = m_revision;
    }
    return m_corner;
}

}  // namespace hemirad::ui
