// TOML readers for the thermal properties and boundary conditions (docs/thermal.md).
#include "thermal/thermal_files.hpp"

#include "engine/error.hpp"
#include "thermal/blackbody.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

namespace hemirad::thermal {
namespace {

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, 0, "cannot open the file");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw Error(path, 0, "read error");
    return text.str();
}

toml::table parse(const std::string& text, const std::string& name) {
    try {
        return toml::parse(text, std::string_view(name));
    } catch (const toml::parse_error& e) {
        throw Error(name, int(e.source().begin.line), std::string(e.description()));
    }
}

int lineOf(const toml::node& node) { return int(node.source().begin.line); }

/// A number (integer or float), finite; else an error at its line.
double number(const toml::node& node, const std::string& file, const std::string& key) {
    std::optional<double> v;
    if (const auto* f = node.as_floating_point()) v = f->get();
    if (const auto* i = node.as_integer()) v = double(i->get());
    if (!v || !std::isfinite(*v)) throw Error(file, lineOf(node), "'" + key + "' must be a finite number");
    return *v;
}

const toml::table& tableAt(const toml::node& node, const std::string& file, const std::string& what) {
    const toml::table* t = node.as_table();
    if (!t) throw Error(file, lineOf(node), what + " must be a table");
    return *t;
}

/// Partial properties of one table: what it sets.
struct Entry {
    std::optional<double> emissivity, specular, solarAbsorptance, solarSpecular;
    std::vector<double> emissivityBands;  ///< emissivity = [...]: one per band (emissivity holds the largest)
    std::vector<double> specularBands;    ///< specular = [...]: one per band (specular then unset)
    std::optional<EmissivityCurve> curve;  ///< emissivity = [[T_K, eps], ...] (emissivity holds the largest)
    int line = 0;
    std::string label;
};

Entry readEntry(const toml::table& t, const std::string& file, const std::string& label) {
    Entry e;
    e.line = lineOf(t);
    e.label = label;
    for (const auto& [key, node] : t) {
        const std::string k(key.str());
        if (k == "emissivity" && node.as_array() && !node.as_array()->empty() && (*node.as_array())[0].as_array()) {
            // Against temperature: [[T_K, eps], ...], temperatures increasing.
            EmissivityCurve curve;
            for (const toml::node& point : *node.as_array()) {
                const toml::array* pair = point.as_array();
                if (!pair || pair->size() != 2)
                    throw Error(file, lineOf(point), "emissivity in " + label +
                                                         ": a curve against temperature is a list of [T_K, eps] pairs");
                const double T = number((*pair)[0], file, k), x = number((*pair)[1], file, k);
                std::ostringstream msg;
                if (!(T >= 0.0) || (!curve.temperatureK.empty() && !(T > curve.temperatureK.back())))
                    msg << "emissivity in " << label << ": temperature " << T
                        << " K must be >= 0 and above the previous point's";
                else if (x < 0.0 || x > 1.0)
                    msg << "emissivity " << x << " at " << T << " K in " << label << " is outside [0, 1]";
                if (!msg.str().empty()) throw Error(file, lineOf(point), msg.str());
                curve.temperatureK.push_back(T);
                curve.emissivity.push_back(x);
            }
            e.emissivity = *std::max_element(curve.emissivity.begin(), curve.emissivity.end());
            e.curve = std::move(curve);
            continue;
        }
        if ((k == "emissivity" || k == "specular") && node.as_array()) {
            std::vector<double>& list = k == "emissivity" ? e.emissivityBands : e.specularBands;
            for (const toml::node& v : *node.as_array()) {
                const double x = number(v, file, k);
                if (x < 0.0 || x > 1.0) {
                    std::ostringstream msg;
                    msg << k << " " << x << " in " << label << " is outside [0, 1]";
                    throw Error(file, lineOf(node), msg.str());
                }
                list.push_back(x);
            }
            if (list.empty()) throw Error(file, lineOf(node), k + " in " + label + " is an empty list");
            if (k == "emissivity") e.emissivity = *std::max_element(list.begin(), list.end());
            continue;
        }
        std::optional<double>* field = k == "emissivity"          ? &e.emissivity
                                       : k == "specular"          ? &e.specular
                                       : k == "solar_absorptance" ? &e.solarAbsorptance
                                       : k == "solar_specular"    ? &e.solarSpecular
                                                                  : nullptr;
        if (!field)
            throw Error(file, lineOf(node), "unknown key '" + k + "' in " + label +
                                                " (emissivity, specular, solar_absorptance, solar_specular)");
        *field = number(node, file, k);
        const double v = **field;
        if (v < 0.0 || v > 1.0) {
            std::ostringstream msg;
            msg << k << " " << v << " in " << label << " is outside [0, 1]";
            throw Error(file, lineOf(node), msg.str());
        }
    }
    if (e.emissivity && e.specular && *e.emissivity + *e.specular > 1.0 + 1e-12) {
        std::ostringstream msg;
        msg << label << ": emissivity " << *e.emissivity << " + specular " << *e.specular << " = "
            << *e.emissivity + *e.specular << " > 1 (an opaque surface reflects 1 - eps)";
        throw Error(file, e.line, msg.str());
    }
    if (e.solarAbsorptance && e.solarSpecular && *e.solarAbsorptance + *e.solarSpecular > 1.0 + 1e-12) {
        std::ostringstream msg;
        msg << label << ": solar_absorptance " << *e.solarAbsorptance << " + solar_specular " << *e.solarSpecular << " = "
            << *e.solarAbsorptance + *e.solarSpecular << " > 1";
        throw Error(file, e.line, msg.str());
    }
    return e;
}

/// name -> (index, line of its table) for the scene's materials or objects.
std::map<std::string, std::size_t> indexOf(const std::vector<std::string>& names) {
    std::map<std::string, std::size_t> index;
    for (std::size_t k = 0; k < names.size(); ++k) index.emplace(names[k], k);
    return index;
}

}  // namespace

void takeBandProperties(ThermalModel& model, BandProperties&& bands) {
    model.bandLimitsUm = std::move(bands.limitsUm);
    model.bandEmissivity = std::move(bands.emissivity);
    model.bandSpecular = std::move(bands.specular);
    model.referenceTemperature = bands.referenceTemperature;
    model.emissivityCurves = std::move(bands.emissivityCurves);
    model.curveOf = std::move(bands.curveOf);
}

std::vector<SurfaceProperties> applyProperties(const std::string& path, Scene& scene, std::vector<std::string>& sources,
                                               std::vector<SurfaceProperties>* solar, BandProperties* bands) {
    if (path.empty()) return applyPropertiesText("", "", scene, sources, solar, bands);
    return applyPropertiesText(readText(path), path, scene, sources, solar, bands);
}

std::vector<SurfaceProperties> applyPropertiesText(const std::string& text, const std::string& name, Scene& scene,
                                                   std::vector<std::string>& sources, std::vector<SurfaceProperties>* solar,
                                                   BandProperties* bands) {
    BandProperties limits;  // [bands]
    int bandsLine = 0;
    std::optional<Entry> fallback;
    std::map<std::size_t, Entry> byMaterial, byObject;
    if (!name.empty()) {
        const toml::table root = parse(text, name);
        std::vector<std::string> materialNames;
        for (const Material& m : scene.materials) materialNames.push_back(m.name);
        const auto materials = indexOf(materialNames), objects = indexOf(scene.objects);
        for (const auto& [key, node] : root) {
            const std::string k(key.str());
            if (k == "bands") {
                bandsLine = lineOf(node);
                for (const auto& [bandKey, bandNode] : tableAt(node, name, "[bands]")) {
                    const std::string bk(bandKey.str());
                    if (bk == "limits_um") {
                        const toml::array* list = bandNode.as_array();
                        if (!list || list->empty()) throw Error(name, lineOf(bandNode), "[bands]: limits_um must be a list of wavelengths (um)");
                        for (const toml::node& v : *list) {
                            const double x = number(v, name, bk);
                            if (!(x > (limits.limitsUm.empty() ? 0.0 : limits.limitsUm.back())))
                                throw Error(name, lineOf(bandNode), "[bands]: limits_um must be positive and increasing");
                            limits.limitsUm.push_back(x);
                        }
                    } else if (bk == "reference_temperature_K") {
                        limits.referenceTemperature = number(bandNode, name, bk);
                        if (!(limits.referenceTemperature > 0.0))
                            throw Error(name, lineOf(bandNode), "[bands]: reference_temperature_K must be above 0 K");
                    } else {
                        throw Error(name, lineOf(bandNode), "unknown key '" + bk + "' in [bands] (limits_um, reference_temperature_K)");
                    }
                }
                if (limits.limitsUm.empty()) throw Error(name, bandsLine, "[bands] gives no limits_um");
            } else if (k == "default") {
                fallback = readEntry(tableAt(node, name, "[default]"), name, "[default]");
            } else if (k == "materials" || k == "objects") {
                const bool isObject = k == "objects";
                for (const auto& [entryKey, entryNode] : tableAt(node, name, "[" + k + "]")) {
                    const std::string entryName(entryKey.str());
                    const std::string label = "[" + k + "." + entryName + "]";
                    const auto& index = isObject ? objects : materials;
                    const auto found = index.find(entryName);
                    if (found == index.end())
                        throw Error(name, lineOf(entryNode),
                                    label + " names no " + (isObject ? "object" : "material") + " of " +
                                        (scene.path.empty() ? std::string("the scene") : scene.path));
                    (isObject ? byObject : byMaterial)[found->second] = readEntry(tableAt(entryNode, name, label), name, label);
                }
            } else {
                throw Error(name, lineOf(node), "unknown table '" + k + "' (bands, default, materials, objects)");
            }
        }
    }

    // Every band list must match the bands.
    const std::size_t bandCount = limits.limitsUm.empty() ? 0 : limits.limitsUm.size() + 1;
    bool specularPerBand = false;
    auto checkBands = [&](const Entry& e) {
        for (const auto& [key, list] : {std::pair<const char*, const std::vector<double>*>{"emissivity", &e.emissivityBands},
                                        {"specular", &e.specularBands}}) {
            if (list->empty()) continue;
            if (!bandCount)
                throw Error(name, e.line, e.label + ": " + key + " has " + std::to_string(list->size()) +
                                              " values but no [bands] table gives their limits");
            if (list->size() != bandCount)
                throw Error(name, e.line, e.label + ": " + key + " has " + std::to_string(list->size()) + " values for " +
                                              std::to_string(bandCount) + " bands ([bands] line " + std::to_string(bandsLine) + ")");
        }
        if (!e.specularBands.empty()) specularPerBand = true;
    };
    auto checkCurve = [&](const Entry& e) {
        if (e.curve && bandCount)
            throw Error(name, e.line, e.label + ": an emissivity curve against temperature takes the gray model; with "
                                                "[bands] (line " + std::to_string(bandsLine) + ") give one emissivity per band");
    };
    for (const Entry* e : {fallback ? &*fallback : nullptr}) if (e) checkBands(*e), checkCurve(*e);
    for (const auto& [index, e] : byMaterial) checkBands(e), checkCurve(e);
    for (const auto& [index, e] : byObject) checkBands(e), checkCurve(e);
    if (bands) {
        *bands = limits;
        bands->emissivity.assign(bandCount, std::vector<double>(scene.size(), 0.0));
        if (specularPerBand) bands->specular.assign(bandCount, std::vector<double>(scene.size(), 0.0));
    }
    auto bandRange = [&](std::size_t k) {
        return std::pair<double, double>{k ? limits.limitsUm[k - 1] : 0.0,
                                         k < limits.limitsUm.size() ? limits.limitsUm[k] : std::numeric_limits<double>::infinity()};
    };
    std::map<const Entry*, std::int32_t> curveIndex;  // one curve per table that gives it

    std::vector<SurfaceProperties> surface = propertiesFromMaterials(scene);
    std::vector<std::string> objectSource(scene.objects.size());
    for (PatchId i = 0; i < scene.size(); ++i) {
        Patch& p = scene.patches[i];
        const Entry* layers[3] = {nullptr, nullptr, nullptr};  // object, material, default
        if (auto it = byObject.find(p.object); it != byObject.end()) layers[0] = &it->second;
        if (auto it = byMaterial.find(p.material); it != byMaterial.end()) layers[1] = &it->second;
        if (fallback) layers[2] = &*fallback;
        std::optional<double> eps, s, alpha, sSolar;
        const std::vector<double>*epsBands = nullptr, *sBands = nullptr;
        const Entry* curveFrom = nullptr;
        std::string from;
        int line = 0, solarLine = 0;
        for (const Entry* e : layers) {
            if (!e) continue;
            if (!alpha && e->solarAbsorptance) alpha = e->solarAbsorptance, solarLine = e->line;
            if (!sSolar && e->solarSpecular) sSolar = e->solarSpecular, solarLine = e->line;
            if (!eps && e->emissivity) {
                eps = e->emissivity;
                if (!e->emissivityBands.empty()) epsBands = &e->emissivityBands;
                if (e->curve) curveFrom = e;
                from += (from.empty() ? "" : ", ") + std::string(e->curve ? "emissivity against temperature from "
                                                                           : "emissivity from ") + e->label;
                line = e->line;
            }
            if (!s && !sBands && (e->specular || !e->specularBands.empty())) {
                if (e->specularBands.empty()) s = e->specular;
                else sBands = &e->specularBands;
                from += (from.empty() ? "" : ", ") + std::string(sBands ? "specular per band from " : "specular from ") + e->label;
                line = e->line;
            }
        }
        if (sBands) {  // the scene's (F's) reflectance: the bands' weighted at the reference temperature
            double weighted = 0.0;
            for (std::size_t k = 0; k < bandCount; ++k) {
                const auto [lo, hi] = bandRange(k);
                weighted += (*sBands)[k] * bandFraction(lo, hi, limits.referenceTemperature);
            }
            // Equal values are that value, not a sum off by an ulp (which would ask for an F of its own).
            const bool equal = std::all_of(sBands->begin(), sBands->end(), [&](double v) { return v == sBands->front(); });
            p.specular = equal ? sBands->front() : weighted;
        }
        if (s) p.specular = *s;
        surface[i].specular = p.specular;
        if (eps) surface[i].emissivity = *eps;
        else {
            surface[i].emissivity = std::max(0.0, 1.0 - p.rho.mean() - p.specular);
            from += (from.empty() ? "" : ", ") + std::string("emissivity 1 - mean(Kd) - s from the MTL");
        }
        if (curveFrom) {
            // The curve's value at the reference temperature until a solve knows the patch's own.
            surface[i].emissivity = curveFrom->curve->at(limits.referenceTemperature);
            if (bands) {
                auto [at, added] = curveIndex.emplace(curveFrom, std::int32_t(bands->emissivityCurves.size()));
                if (added) bands->emissivityCurves.push_back(*curveFrom->curve);
                bands->curveOf.resize(scene.size(), -1);
                bands->curveOf[i] = at->second;
            }
        }
        if (bandCount) {
            // Per band: the list, or the one value in every band; the gray value weighted at T_ref.
            double weighted = 0.0;
            for (std::size_t k = 0; k < bandCount; ++k) {
                const double sk = sBands ? (*sBands)[k] : p.specular;
                // Without a given emissivity, each band's is 1 - mean(Kd) - its own s.
                const double e = epsBands ? (*epsBands)[k]
                                 : eps || curveFrom ? surface[i].emissivity
                                                    : std::max(0.0, 1.0 - p.rho.mean() - sk);
                if (bands) bands->emissivity[k][i] = e;
                if (bands && specularPerBand) bands->specular[k][i] = sk;
                const auto [lo, hi] = bandRange(k);
                weighted += e * bandFraction(lo, hi, limits.referenceTemperature);
                if (e + sk > 1.0 + 1e-12) {
                    std::ostringstream msg;
                    msg << "object '" << scene.objects[p.object] << "' (material '" << scene.materials[p.material].name
                        << "'): in band " << k + 1 << " emissivity " << e << " + specular " << sk << " = " << e + sk
                        << " > 1 (" << from << ")";
                    throw Error(name.empty() ? scene.path : name, line, msg.str());
                }
            }
            surface[i].emissivity = weighted;
        }
        const bool largest = (epsBands && !bandCount) || curveFrom;  // check the largest of a curve
        if (surface[i].emissivity + surface[i].specular > 1.0 + 1e-12 || (largest && *eps + surface[i].specular > 1.0 + 1e-12)) {
            std::ostringstream msg;
            msg << "object '" << scene.objects[p.object] << "' (material '" << scene.materials[p.material].name
                << "'): emissivity " << (largest ? *eps : surface[i].emissivity) << " + specular " << surface[i].specular
                << " = " << (largest ? *eps : surface[i].emissivity) + surface[i].specular << " > 1 (" << from << ")";
            throw Error(name.empty() ? scene.path : name, line, msg.str());
        }
        if (solar) {
            solar->resize(scene.size());
            SurfaceProperties& sp = (*solar)[i];
            sp.specular = sSolar.value_or(p.specular);
            sp.emissivity = alpha.value_or(std::max(0.0, 1.0 - p.rho.mean() - sp.specular));
            if (sp.emissivity + sp.specular > 1.0 + 1e-12) {
                std::ostringstream msg;
                msg << "object '" << scene.objects[p.object] << "' (material '" << scene.materials[p.material].name
                    << "'): solar absorptance " << sp.emissivity << " + solar specular " << sp.specular << " = "
                    << sp.emissivity + sp.specular << " > 1" << (alpha ? "" : " (absorptance 1 - mean(Kd) - s from the MTL)");
                throw Error(name.empty() ? scene.path : name, solarLine, msg.str());
            }
            from += std::string(", solar absorptance ") + (alpha ? "given" : "1 - mean(Kd) - s from the MTL");
        }
        if (objectSource[p.object].empty()) objectSource[p.object] = from;
        else if (objectSource[p.object] != from && objectSource[p.object].find("(varies") == std::string::npos)
            objectSource[p.object] += " (varies by material)";
    }
    sources.clear();
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
        if (!objectSource[o].empty()) sources.push_back(scene.objects[o] + ": " + objectSource[o]);
    return surface;
}

Conditions readConditions(const std::string& path, const Scene& scene, double metresPerUnit) {
    return readConditionsText(readText(path), path, scene, metresPerUnit);
}

Conditions readConditionsText(const std::string& text, const std::string& name, const Scene& scene, double metresPerUnit) {
    const toml::table root = parse(text, name);
    const auto objects = indexOf(scene.objects);
    std::vector<double> objectArea(scene.objects.size(), 0.0);
    for (const Patch& p : scene.patches) objectArea[p.object] += p.area * metresPerUnit * metresPerUnit;

    // One condition per table: temperature (K), flux (W/m^2) or power (W, spread over the area).
    struct Given {
        Condition::Kind kind;
        double value;      // K, W/m^2 or W
        bool power = false;
        std::string text;
        std::optional<double> solar;  // W/m^2 arriving from outside, in the solar band
    };
    auto readCondition = [&](const toml::table& t, const std::string& label) {
        std::optional<Given> given;
        std::optional<double> solar;
        for (const auto& [key, node] : t) {
            const std::string k(key.str());
            if (k == "solar_W_m2") {
                solar = number(node, name, k);
                if (*solar < 0.0) throw Error(name, lineOf(node), label + ": solar_W_m2 must be >= 0");
                continue;
            }
            Given g{Condition::Kind::Flux, 0.0, false, "", std::nullopt};
            std::ostringstream say;
            if (k == "temperature_K" || k == "temperature_C") {
                const double v = number(node, name, k);
                g.kind = Condition::Kind::Temperature;
                g.value = k == "temperature_K" ? v : v + kCelsiusZero;
                if (g.value < 0.0) {
                    std::ostringstream msg;
                    msg << label << ": " << k << " = " << v << " is below absolute zero";
                    throw Error(name, lineOf(node), msg.str());
                }
                say << "temperature " << g.value << " K";
            } else if (k == "flux_W_m2") {
                g.value = number(node, name, k);
                say << "net flux " << g.value << " W/m^2";
            } else if (k == "power_W") {
                g.value = number(node, name, k);
                g.power = true;
                say << "isothermal, net power " << g.value << " W";
            } else if (k == "adiabatic") {
                const auto* b = node.as_boolean();
                if (!b || !b->get()) throw Error(name, lineOf(node), label + ": adiabatic must be true (or leave it out)");
                say << "adiabatic";
            } else {
                throw Error(name, lineOf(node), "unknown key '" + k + "' in " + label +
                                                    " (temperature_K, temperature_C, flux_W_m2, power_W, adiabatic, "
                                                    "solar_W_m2)");
            }
            if (given) throw Error(name, lineOf(node), label + " gives two conditions; give one of temperature_K, "
                                                               "temperature_C, flux_W_m2, power_W or adiabatic");
            g.text = say.str();
            given = g;
        }
        if (!given) throw Error(name, lineOf(t), label + " gives no condition (temperature_K, temperature_C, flux_W_m2, power_W or adiabatic)");
        given->solar = solar;
        if (solar) {
            std::ostringstream say;
            say << ", sun " << *solar << " W/m^2";
            given->text += say.str();
        }
        return *given;
    };

    Conditions out;
    std::optional<Given> fallback;
    std::vector<std::optional<Given>> byObject(scene.objects.size());
    for (const auto& [key, node] : root) {
        const std::string k(key.str());
        if (k == "environment") {
            for (const auto& [envKey, envNode] : tableAt(node, name, "[environment]")) {
                const std::string ek(envKey.str());
                if (ek != "temperature_K" && ek != "temperature_C")
                    throw Error(name, lineOf(envNode), "unknown key '" + ek + "' in [environment] (temperature_K, temperature_C)");
                if (out.environment) throw Error(name, lineOf(envNode), "[environment] gives two temperatures");
                const double v = number(envNode, name, ek);
                out.environment = ek == "temperature_K" ? v : v + kCelsiusZero;
                if (*out.environment < 0.0) {
                    std::ostringstream msg;
                    msg << "[environment]: " << ek << " = " << v << " is below absolute zero";
                    throw Error(name, lineOf(envNode), msg.str());
                }
            }
            if (!out.environment) throw Error(name, lineOf(node), "[environment] gives no temperature (temperature_K or temperature_C)");
        } else if (k == "default") {
            fallback = readCondition(tableAt(node, name, "[default]"), "[default]");
        } else if (k == "objects") {
            for (const auto& [objectKey, objectNode] : tableAt(node, name, "[objects]")) {
                const std::string object(objectKey.str());
                const std::string label = "[objects." + object + "]";
                const auto found = objects.find(object);
                if (found == objects.end() || objectArea[found->second] == 0.0)
                    throw Error(name, lineOf(objectNode),
                                label + " names no object with patches in " + (scene.path.empty() ? std::string("the scene") : scene.path));
                byObject[found->second] = readCondition(tableAt(objectNode, name, label), label);
            }
        } else {
            throw Error(name, lineOf(node), "unknown table '" + k + "' (environment, default, objects)");
        }
    }

    std::vector<std::string> missing;
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        if (objectArea[o] == 0.0) continue;
        if (!byObject[o] && !fallback) missing.push_back("'" + scene.objects[o] + "'");
        else out.sources.push_back(scene.objects[o] + ": " + (byObject[o] ? byObject[o]->text : fallback->text + " ([default])"));
    }
    if (!missing.empty()) {
        std::string list;
        for (std::size_t k = 0; k < missing.size() && k < 10; ++k) list += (k ? ", " : "") + missing[k];
        if (missing.size() > 10) list += ", ... (" + std::to_string(missing.size()) + " in all)";
        throw Error(name, 0, "no boundary condition for object(s) " + list + "; give each one a table under [objects] or add a [default]");
    }
    // A power condition makes its object one isothermal node ([default] power: one node per object).
    std::vector<std::uint32_t> nodeOf(scene.objects.size(), UINT32_MAX);
    out.perPatch.resize(scene.size());
    out.solarIncident.assign(scene.size(), 0.0);
    for (PatchId i = 0; i < scene.size(); ++i) {
        const std::uint32_t o = scene.patches[i].object;
        const Given& g = byObject[o] ? *byObject[o] : *fallback;
        out.solarIncident[i] = g.solar.value_or(byObject[o] && fallback ? fallback->solar.value_or(0.0) : 0.0);
        Condition& c = out.perPatch[i];
        c.kind = g.kind;
        c.value = g.value;
        if (g.power) {
            if (nodeOf[o] == UINT32_MAX) {
                nodeOf[o] = std::uint32_t(out.isothermal.size());
                out.isothermal.push_back({scene.objects[o], g.value});
            }
            c.kind = Condition::Kind::Isothermal;
            c.value = 0.0;
            c.node = nodeOf[o];
        }
    }
    return out;
}

}  // namespace hemirad::thermal
