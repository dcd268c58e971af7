// The Scene panel's thermal fields and their reloading.
#include "ui/thermal_fields.hpp"

#include "thermal/thermal_model.hpp"

namespace hemirad::ui {

double ThermalFields::kelvin(double shown) const { return celsius ? shown + thermal::kCelsiusZero : shown; }

void ThermalFields::sync(const AppState& app) {
    // A new mesh changes the objects' patch counts (not app.revision(): it moves with every progressive
    // solve and would reload a field while it is typed into).
    if (!app.hasScene()) return;
    if (app.thermalRevision() == m_thermalRevision && app.materialsRevision() == m_materialsRevision &&
        app.sceneId() == m_sceneId && app.scene().size() == m_patches && celsius == m_shownCelsius)
        return;
    reload(app);
}

void ThermalFields::reload(const AppState& app) {
    m_patches = app.scene().size();
    m_thermalRevision = app.thermalRevision();
    m_materialsRevision = app.materialsRevision();
    m_sceneId = app.sceneId();
    m_shownCelsius = celsius;
    const double offset = celsius ? thermal::kCelsiusZero : 0.0;
    std::optional<double> env;
    rows.clear();
    for (ObjectThermalRow& o : app.thermalObjects(env, error)) {
        Row r;
        r.emissivity = o.emissivity;
        if (o.condition) {
            r.kind = o.condition->kind;
            r.value = o.condition->value - (o.condition->kind == ObjectCondition::Kind::Temperature ? offset : 0.0);
        }
        r.object = std::move(o);
        rows.push_back(std::move(r));
    }
    closed = !env;
    if (env) environment = *env - offset;
}

bool ThermalFields::applyEmissivity(AppState& app, std::size_t k) {
    const bool ok = app.setObjectEmissivity(rows.at(k).object.object, rows[k].emissivity);
    reload(app);
    return ok;
}

bool ThermalFields::applyKind(AppState& app, std::size_t k) {
    const ObjectCondition::Kind kind = rows.at(k).kind;
    const double start = kind == ObjectCondition::Kind::Temperature ? 293.15 : 0.0;  // a value the user types over
    const bool ok = app.setObjectCondition(rows[k].object.object, {kind, start});
    reload(app);
    return ok;
}

bool ThermalFields::applyValue(AppState& app, std::size_t k) {
    const Row& r = rows.at(k);
    const double value = r.kind == ObjectCondition::Kind::Temperature ? kelvin(r.value) : r.value;
    const bool ok = app.setObjectCondition(r.object.object, {r.kind, value});
    reload(app);
    return ok;
}

bool ThermalFields::applyEnvironment(AppState& app) {
    const bool ok = app.setThermalEnvironment(closed ? std::nullopt : std::optional<double>(kelvin(environment)));
    reload(app);
    return ok;
}

}  // namespace hemirad::ui
