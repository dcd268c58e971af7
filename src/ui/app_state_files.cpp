// hemirad-gui application state: importing and exporting F, the PLY and the object table.
#include "ui/app_state.hpp"

#include "engine/form_factor_file.hpp"
#include "engine/result_writer.hpp"
#include "engine/tone_map.hpp"

#include <exception>
#include <string>

namespace hemirad::ui {

bool AppState::importFormFactors(const std::string& path) {
    if (!hasScene()) return false;
    // A running job would replace the imported F with its own.
    cancel();
    wait();
    poll();
    try {
        auto F = std::make_shared<FormFactors>(loadFormFactors(path));
        checkFormFactorsMatch(*F, m_scene->geometryHash(), m_scene->size(), path);
        m_stats = computeStats(*F, *m_scene);
        m_F = std::move(F);
        m_fSettings = settings.formFactors;  // Run reuses it until the panel's settings change
        m_fGeometryHash = m_scene->geometryHash();
        m_fStale = false;
        m_bStale = true;
        bump();
        info("imported form factors from " + path);
        if (autoResolve) refreshRadiosity();  // the picture shows the imported F's radiosity
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

bool AppState::exportFormFactors(const std::string& path) {
    if (!m_F) {
        error("no form factors to export yet: run the pipeline");
        return false;
    }
    try {
        saveFormFactors(*m_F, path);
        info("exported form factors to " + path);
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

bool AppState::exportPly(const std::string& path) {
    if (!hasScene()) return false;
    try {
        std::vector<double> lum;
        for (const Rgb& b : m_B) lum.push_back(luminance(b) / kPi);
        const double scale = autoExposure ? hemirad::autoExposure(std::move(lum), 0.9, 0.85) : exposure;
        writeRadiosityPly(path, *m_scene, cornerRadiosity(), scale);
        info("exported " + path);
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

bool AppState::exportObjectTable(const std::string& path) {
    if (!hasScene()) return false;
    try {
        writeObjectTable(path, objectTable(), m_scene->unit);
        info("exported " + path + " (per object: area, B and H)");
        return true;
    } catch (const std::exception& e) {
        error(e.what());
        return false;
    }
}

}  // namespace hemirad::ui
