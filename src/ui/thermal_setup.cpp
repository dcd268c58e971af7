// hemirad-gui's thermal inputs: the files read by src/thermal, the per-object edits laid over them.
#include "ui/thermal_setup.hpp"

#include "engine/error.hpp"
#include "thermal/thermal_files.hpp"

#include <sstream>

namespace hemirad::ui {
namespace {

std::string figure(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

/// The files and edits per patch and per object, before they become one model.
struct Layers {
    std::vector<thermal::SurfaceProperties> surface, solar;
    thermal::BandProperties bands;
    std::vector<std::string> propertySource, conditionSource;
    std::vector<std::optional<ObjectCondition>> condition;  ///< per object
    std::optional<double> environment;
    std::vector<double> solarIncident;  ///< per patch, W/m^2
};

ObjectCondition fromFile(const thermal::Conditions& c, PatchId i) {
    const thermal::Condition& p = c.perPatch[i];
    switch (p.kind) {
    case thermal::Condition::Kind::Temperature: return {ObjectCondition::Kind::Temperature, p.value};
    case thermal::Condition::Kind::Isothermal: return {ObjectCondition::Kind::Power, c.isothermal[p.node].power};
    case thermal::Condition::Kind::Flux: break;
    }
    // adiabatic = true and flux_W_m2 = 0 are the same condition.
    return p.value == 0.0 ? ObjectCondition{ObjectCondition::Kind::Adiabatic, 0.0}
                          : ObjectCondition{ObjectCondition::Kind::Flux, p.value};
}

std::string describe(const ObjectCondition& c) {
    switch (c.kind) {
    case ObjectCondition::Kind::Temperature: return "temperature " + figure(c.value) + " K";
    case ObjectCondition::Kind::Flux: return "flux " + figure(c.value) + " W/m^2";
    case ObjectCondition::Kind::Power: return "isothermal, power " + figure(c.value) + " W";
    case ObjectCondition::Kind::Adiabatic: break;
    }
    return "adiabatic";
}

Layers layers(const Scene& scene, const ThermalSetup& setup) {
    Layers l;
    // The properties file sets its specular reflectances on a copy; the scene's own (applied when the
    // file was loaded, edited since in the Material editor) are what F was made with, so they stay.
    Scene copy = scene;
    l.surface = thermal::applyPropertiesText(setup.propertiesText, setup.propertiesPath, copy, l.propertySource, &l.solar, &l.bands);
    for (PatchId i = 0; i < scene.size(); ++i) {
        // A reflectance edited since the file was loaded holds in every band (as an edited emissivity).
        if (scene.patches[i].specular != copy.patches[i].specular)
            for (std::vector<double>& band : l.bands.specular) band[i] = scene.patches[i].specular;
        l.surface[i].specular = scene.patches[i].specular;
    }
    for (const auto& [object, eps] : setup.emissivity) {
        if (object >= scene.objects.size()) continue;
        for (PatchId i = 0; i < scene.size(); ++i) {
            if (scene.patches[i].object != object) continue;
            l.surface[i].emissivity = eps;
            for (std::vector<double>& band : l.bands.emissivity) band[i] = eps;  // gray in every band
            if (!l.bands.curveOf.empty()) l.bands.curveOf[i] = -1;              // and constant
        }
        l.propertySource.push_back("object '" + scene.objects[object] + "': emissivity " + figure(eps) + " (edited)");
    }
    l.condition.assign(scene.objects.size(), std::nullopt);
    l.solarIncident.assign(scene.size(), 0.0);
    if (!setup.conditionsPath.empty()) {
        const thermal::Conditions c =
            thermal::readConditionsText(setup.conditionsText, setup.conditionsPath, scene, thermalMetresPerUnit(scene));
        for (PatchId i = 0; i < scene.size(); ++i)
            if (!l.condition[scene.patches[i].object]) l.condition[scene.patches[i].object] = fromFile(c, i);
        l.environment = c.environment;
        l.solarIncident = c.solarIncident;
        l.conditionSource = c.sources;
    }
    for (const auto& [object, condition] : setup.condition) {
        if (object >= scene.objects.size()) continue;
        l.condition[object] = condition;
        l.conditionSource.push_back("object '" + scene.objects[object] + "': " + describe(condition) + " (edited)");
    }
    if (setup.environment) l.environment = *setup.environment;
    return l;
}

/// The model from the layers; objects without a condition are adiabatic when `allowMissing`, else an error.
ThermalInputs assemble(const Scene& scene, Layers l, bool allowMissing) {
    ThermalInputs inputs;
    thermal::ThermalModel& model = inputs.model;
    model.metresPerUnit = thermalMetresPerUnit(scene);
    model.surface = std::move(l.surface);
    thermal::takeBandProperties(model, std::move(l.bands));
    model.environment = l.environment;
    model.propertySource = std::move(l.propertySource);
    model.conditionSource = std::move(l.conditionSource);
    std::vector<bool> used(scene.objects.size(), false);
    for (const Patch& p : scene.patches) used[p.object] = true;
    std::vector<std::optional<std::uint32_t>> node(scene.objects.size());
    std::string missing;
    for (std::uint32_t o = 0; o < scene.objects.size(); ++o) {
        if (!used[o]) continue;
        if (!l.condition[o]) {
            if (!allowMissing) missing += (missing.empty() ? "'" : ", '") + scene.objects[o] + "'";
            continue;
        }
        if (l.condition[o]->kind == ObjectCondition::Kind::Power) {
            node[o] = std::uint32_t(model.isothermal.size());
            model.isothermal.push_back({scene.objects[o], l.condition[o]->value});
        }
    }
    if (!missing.empty())
        throw Error("no boundary condition for " + missing + ": load a boundary-condition file or set one per object");
    model.condition.resize(scene.size());
    for (PatchId i = 0; i < scene.size(); ++i) {
        const std::uint32_t o = scene.patches[i].object;
        const ObjectCondition c = l.condition[o].value_or(ObjectCondition{});
        thermal::Condition& m = model.condition[i];
        switch (c.kind) {
        case ObjectCondition::Kind::Temperature: m = {thermal::Condition::Kind::Temperature, c.value, 0}; break;
        case ObjectCondition::Kind::Flux: m = {thermal::Condition::Kind::Flux, c.value, 0}; break;
        case ObjectCondition::Kind::Power: m = {thermal::Condition::Kind::Isothermal, 0.0, *node[o]}; break;
        case ObjectCondition::Kind::Adiabatic: m = {thermal::Condition::Kind::Flux, 0.0, 0}; break;
        }
    }
    inputs.solar.surface = std::move(l.solar);
    inputs.solar.incident = std::move(l.solarIncident);
    if (!inputs.solar.active()) inputs.solar = {};
    thermal::checkModel(scene, model);
    return inputs;
}

}  // namespace

const char* conditionKindName(ObjectCondition::Kind kind) {
    switch (kind) {
    case ObjectCondition::Kind::Temperature: return "temperature";
    case ObjectCondition::Kind::Flux: return "flux";
    case ObjectCondition::Kind::Power: return "power";
    case ObjectCondition::Kind::Adiabatic: break;
    }
    return "adiabatic";
}

double thermalMetresPerUnit(const Scene& scene) { return scene.unit.empty() ? 1.0 : metresPerUnit(scene.unit); }

ThermalInputs buildThermalInputs(const Scene& scene, const ThermalSetup& setup) {
    return assemble(scene, layers(scene, setup), false);
}

void checkThermalSetup(const Scene& scene, const ThermalSetup& setup) { assemble(scene, layers(scene, setup), true); }

namespace {

/// ObjectThermalRow::emissivityCurve for object o: its patches' curve (or how many they follow).
std::string curveText(const Scene& scene, const thermal::BandProperties& bands, std::uint32_t o) {
    if (bands.curveOf.empty()) return "";
    std::int32_t curve = -1;
    std::size_t distinct = 0, constant = 0;
    std::vector<std::uint8_t> seen(bands.emissivityCurves.size(), 0);
    for (PatchId i = 0; i < scene.size(); ++i) {
        if (scene.patches[i].object != o) continue;
        const std::int32_t c = bands.curveOf[i];
        if (c < 0) {
            ++constant;
            continue;
        }
        if (!seen[std::size_t(c)]++) ++distinct;
        curve = c;
    }
    if (distinct == 0) return "";
    std::string text;
    if (distinct > 1) {
        text = "eps(T) from the properties file: " + std::to_string(distinct) + " curves over its patches";
    } else {
        const thermal::EmissivityCurve& e = bands.emissivityCurves[std::size_t(curve)];
        text = "eps(T) from the properties file:";
        for (std::size_t k = 0; k < e.temperatureK.size(); ++k)
            text += (k ? ", " : " ") + figure(e.emissivity[k]) + " at " + figure(e.temperatureK[k]) + " K";
    }
    if (constant > 0) text += "; " + std::to_string(constant) + " of its patches constant";
    return text + " (shown: the value at " + figure(bands.referenceTemperature) + " K)";
}

}  // namespace

std::vector<ObjectThermalRow> objectThermalRows(const Scene& scene, const ThermalSetup& setup,
                                                std::optional<double>& environment) {
    const Layers l = layers(scene, setup);
    environment = l.environment;
    std::vector<ObjectThermalRow> rows(scene.objects.size());
    std::vector<double> area(scene.objects.size(), 0.0);
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        ObjectThermalRow& r = rows[p.object];
        if (r.patches++ == 0) r.solar = l.solarIncident[i];
        area[p.object] += p.area;
        r.emissivity += p.area * l.surface[i].emissivity;
        r.specular += p.area * p.specular;
    }
    std::vector<ObjectThermalRow> shown;
    for (std::uint32_t o = 0; o < scene.objects.size(); ++o) {
        ObjectThermalRow r = rows[o];
        if (r.patches == 0) continue;
        r.object = o;
        r.name = scene.objects[o];
        r.emissivity = area[o] > 0 ? r.emissivity / area[o] : 0.0;
        r.specular = area[o] > 0 ? r.specular / area[o] : 0.0;
        r.condition = l.condition[o];
        r.emissivityEdited = setup.emissivity.count(o) > 0;
        r.conditionEdited = setup.condition.count(o) > 0;
        r.emissivityCurve = curveText(scene, l.bands, o);
        shown.push_back(std::move(r));
    }
    return shown;
}

}  // namespace hemirad::ui
