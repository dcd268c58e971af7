// hemirad-gui application state: the Sky and sun run on the worker thread, its result and the
// false-colour quantities it gives (sunlit fraction, sky view factor, the irradiance's parts).
#include "ui/app_state.hpp"

#include "engine/error.hpp"
#include "environment/sky_model.hpp"
#include "ui/sun_sky_job.hpp"

#include <exception>

namespace hemirad::ui {

namespace {

struct SunQuantity {
    FalseColourSettings::Sun quantity;
    const char* name;
    const char* title;
    const char* unit;
};
constexpr SunQuantity kSunQuantities[] = {
    {FalseColourSettings::Sun::SunlitFraction, "sunlit_fraction", "sunlit fraction", "of the patch's area, 0..1"},
    {FalseColourSettings::Sun::SkyView, "sky_view_factor", "sky view factor", "unitless, 0..1 (the sky seen directly)"},
    {FalseColourSettings::Sun::DirectSun, "direct_sun", "direct sun", "W/m^2"},
    {FalseColourSettings::Sun::DirectSky, "direct_sky", "direct sky", "W/m^2"},
    {FalseColourSettings::Sun::Reflected, "reflected_solar", "reflected (sun and sky)", "W/m^2, from the other patches"},
    {FalseColourSettings::Sun::Total, "total_solar", "total irradiance (sun and sky)", "W/m^2"},
    {FalseColourSettings::Sun::Absorbed, "absorbed_solar", "absorbed (sun and sky)", "W/m^2"},
};

}  // namespace

const char* sunQuantityName(FalseColourSettings::Sun quantity) {
    for (const SunQuantity& q : kSunQuantities)
        if (q.quantity == quantity) return q.name;
    return "";
}

std::optional<FalseColourSettings::Sun> parseSunQuantity(const std::string& name) {
    for (const SunQuantity& q : kSunQuantities)
        if (name == q.name) return q.quantity;
    return std::nullopt;
}

std::pair<std::string, std::string> AppState::sunSkyLegend(FalseColourSettings::Sun quantity) {
    for (const SunQuantity& q : kSunQuantities)
        if (q.quantity == quantity) return {q.title, q.unit};
    return {"", ""};
}

void AppState::runSunSky() {
    if (!hasScene()) return;
    if (busy()) {
        error("a computation is running; cancel it first");
        return;
    }
    try {  // the inputs the job would refuse late, refused now
        if (sunSky.sky != "isotropic") parseSkyModel(sunSky.sky);
        if (!(sunSky.dni >= 0.0 && sunSky.dni <= 1e5) || !(sunSky.dhi >= 0.0 && sunSky.dhi <= 1e5))
            throw Error("DNI and DHI must be 0 .. 1e5 W/m^2");
        if (sunSky.subdivision < 1 || sunSky.subdivision > 8) throw Error("the sky's subdivision must be 1..8");
    } catch (const std::exception& e) {
        error("sky and sun: " + std::string(e.what()));
        return;
    }
    double metres = 1.0;
    if (!m_scene->unit.empty()) metres = metresPerUnit(m_scene->unit);
    else info("sky and sun: the scene states no length unit: lengths are taken as metres (powers in W)");
    const bool reuse = m_F && !m_fStale && formFactorsMatchSettings();
    info(reuse ? "running: sky and sun (every row of F, then the hour)" : "running: sky and sun (form factors, then the hour)");
    m_sunSkyJob.reset();
    m_sunSkyJob = std::make_unique<SunSkyJob>(*m_scene, reuse ? m_F : nullptr, sunSky, upAxis(), metres, settings);
    m_sunSkyJobMaterials = m_materialsRevision;
}

void AppState::pollSunSky() {
    std::unique_ptr<SunSkyJob> job = std::move(m_sunSkyJob);
    if (!finishWorkerJob(*job, "sky and sun")) return;
    if (job->scene().size() != m_scene->size() || job->scene().geometryHash() != m_scene->geometryHash()) {
        info("sky and sun: the scene changed while it ran; its result is dropped (Run sky and sun again)");
        return;
    }
    m_sunSkyResult = std::move(job->result);
    m_sunSkyResult->materialsRevision = m_sunSkyJobMaterials;
    m_timings = job->timings;
    bump();
}

const SunSkyResult* AppState::sunSkyResult() const {
    if (!hasScene() || !m_sunSkyResult || m_sunSkyResult->sunlit.size() != m_scene->size()) return nullptr;
    return &*m_sunSkyResult;
}

bool AppState::sunSkyStale() const {
    const SunSkyResult* r = sunSkyResult();
    return r && (r->geometryHash != m_scene->geometryHash() || r->materialsRevision != m_materialsRevision);
}

std::vector<double> AppState::sunSkyValues(FalseColourSettings::Sun quantity) const {
    const SunSkyResult* r = sunSkyResult();
    if (!r) throw Error("no sky-and-sun result: press Run sky and sun (Scene panel)");
    const IrradianceResult& e = r->irradiance;
    switch (quantity) {
    case FalseColourSettings::Sun::SunlitFraction: return r->sunlit;
    case FalseColourSettings::Sun::SkyView:
        if (r->skyView.empty()) throw Error("the sky view factor comes with the isotropic sky: run Sky and sun with it");
        return r->skyView;
    case FalseColourSettings::Sun::DirectSun: return e.directSun;
    case FalseColourSettings::Sun::DirectSky: return e.directSky;
    case FalseColourSettings::Sun::Reflected: return e.reflected;
    case FalseColourSettings::Sun::Total: return e.total;
    case FalseColourSettings::Sun::Absorbed: return e.absorbed;
    case FalseColourSettings::Sun::None: break;
    }
    throw Error("no sky-and-sun quantity chosen");
}

}  // namespace hemirad::ui
