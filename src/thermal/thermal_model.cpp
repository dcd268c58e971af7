// Thermal model checks and the MTL fallback for IR properties.
#include "thermal/thermal_model.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hemirad::thermal {
namespace {

/// Properties and conditions are given per object: name it in every message.
std::string describe(const Scene& scene, PatchId i) {
    const Patch& p = scene.patches[i];
    std::string where = "patch " + std::to_string(i);
    if (p.object < scene.objects.size()) where += " (object '" + scene.objects[p.object] + "')";
    if (p.sourceLine > 0) where += " from " + (scene.path.empty() ? std::string("the scene") : scene.path) + ":" + std::to_string(p.sourceLine);
    return where;
}

}  // namespace

std::vector<SurfaceProperties> propertiesFromMaterials(const Scene& scene) {
    std::vector<SurfaceProperties> surface(scene.size());
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        surface[i].specular = p.specular;
        surface[i].emissivity = std::max(0.0, 1.0 - p.rho.mean() - p.specular);
    }
    return surface;
}

bool bandNeedsOwnFormFactors(const Scene& scene, const ThermalModel& model, std::size_t k) {
    if (model.bandSpecular.empty()) return false;
    for (PatchId i = 0; i < scene.size(); ++i)
        if (model.bandSpecular[k][i] != scene.patches[i].specular) return true;
    return false;
}

void checkModel(const Scene& scene, const ThermalModel& model) {
    const std::size_t n = scene.size();
    if (model.surface.size() != n || model.condition.size() != n)
        throw Error("thermal: the model has " + std::to_string(model.surface.size()) + " properties and " +
                    std::to_string(model.condition.size()) + " conditions for " + std::to_string(n) + " patches");
    if (!model.absorbedExternal.empty() && model.absorbedExternal.size() != n)
        throw Error("thermal: the absorbed external heat has " + std::to_string(model.absorbedExternal.size()) +
                    " values for " + std::to_string(n) + " patches");
    for (const double a : model.absorbedExternal)
        if (!(std::isfinite(a) && a >= 0.0)) throw Error("thermal: an absorbed external heat flux is negative or not finite");
    if (!(model.metresPerUnit > 0.0) || !std::isfinite(model.metresPerUnit))
        throw Error("thermal: the length unit must be a positive number of metres");
    if (model.environment && !(std::isfinite(*model.environment) && *model.environment >= 0.0)) {
        std::ostringstream msg;
        msg << "thermal: the environment temperature " << *model.environment << " K is below 0 K or not finite";
        throw Error(msg.str());
    }
    for (PatchId i = 0; i < n; ++i) {
        const SurfaceProperties& sp = model.surface[i];
        const Condition& c = model.condition[i];
        std::ostringstream msg;
        msg.precision(12);
        if (!(sp.emissivity >= 0.0 && sp.emissivity <= 1.0) || !(sp.specular >= 0.0 && sp.specular <= 1.0)) {
            msg << "thermal: " << describe(scene, i) << ": emissivity " << sp.emissivity << " and specular reflectance "
                << sp.specular << " must each be in [0, 1]";
        } else if (sp.emissivity + sp.specular > 1.0 + 1e-12) {
            msg << "thermal: " << describe(scene, i) << ": emissivity " << sp.emissivity << " + specular reflectance "
                << sp.specular << " = " << sp.emissivity + sp.specular << " > 1 (an opaque surface reflects 1 - eps)";
        } else if (sp.specular != scene.patches[i].specular) {
            msg << "thermal: " << describe(scene, i) << ": specular reflectance " << sp.specular
                << " differs from the scene's " << scene.patches[i].specular
                << ", which F was computed with; set it on the scene before computing F";
        } else if (!std::isfinite(c.value)) {
            msg << "thermal: " << describe(scene, i) << ": the boundary condition is not a finite number";
        } else if (c.kind == Condition::Kind::Temperature && c.value < 0.0) {
            msg << "thermal: " << describe(scene, i) << ": temperature " << c.value << " K is below 0 K";
        } else if (c.kind == Condition::Kind::Isothermal && c.node >= model.isothermal.size()) {
            msg << "thermal: " << describe(scene, i) << ": isothermal node " << c.node << " does not exist";
        } else if (c.kind == Condition::Kind::Flux && largestEmissivity(model, i) == 0.0 &&
                   c.value != -(model.absorbedExternal.empty() ? 0.0 : model.absorbedExternal[i])) {
            msg << "thermal: " << describe(scene, i) << ": a net flux of " << c.value
                << " W/m^2 on a surface with IR emissivity 0, which neither emits nor absorbs in the IR (its net flux "
                   "can only be minus what it absorbs of the sun)";
        } else {
            continue;
        }
        throw Error(msg.str());
    }
    if (!model.bandEmissivity.empty()) {
        if (model.bandEmissivity.size() != model.bandLimitsUm.size() + 1)
            throw Error("thermal: " + std::to_string(model.bandLimitsUm.size()) + " band limits make " +
                        std::to_string(model.bandLimitsUm.size() + 1) + " bands, but " +
                        std::to_string(model.bandEmissivity.size()) + " emissivities per patch were given");
        for (std::size_t k = 0; k < model.bandLimitsUm.size(); ++k)
            if (!(model.bandLimitsUm[k] > (k ? model.bandLimitsUm[k - 1] : 0.0)) || !std::isfinite(model.bandLimitsUm[k]))
                throw Error("thermal: band limits must be finite, positive and increasing (um)");
        if (!model.bandSpecular.empty() && model.bandSpecular.size() != model.bandEmissivity.size())
            throw Error("thermal: " + std::to_string(model.bandSpecular.size()) + " bands of specular reflectances for " +
                        std::to_string(model.bandEmissivity.size()) + " bands of emissivities");
        for (std::size_t k = 0; k < model.bandEmissivity.size(); ++k) {
            if (model.bandEmissivity[k].size() != n) throw Error("thermal: band emissivities need one value per patch");
            if (!model.bandSpecular.empty() && model.bandSpecular[k].size() != n)
                throw Error("thermal: band specular reflectances need one value per patch");
            for (PatchId i = 0; i < n; ++i) {
                const double e = model.bandEmissivity[k][i], s = specularIn(model, k, i);
                if (!(e >= 0.0 && s >= 0.0 && e + s <= 1.0 + 1e-12)) {
                    std::ostringstream msg;
                    msg << "thermal: " << describe(scene, i) << ": band " << k + 1 << " emissivity " << e << " + specular "
                        << s << " must be in [0, 1]";
                    throw Error(msg.str());
                }
            }
        }
    } else if (!model.bandSpecular.empty()) {
        throw Error("thermal: specular reflectances per band need bands (emissivities per band and their limits)");
    }
    if (!model.curveOf.empty()) {
        if (model.curveOf.size() != n)
            throw Error("thermal: emissivity curves need one index per patch (-1: none): " + std::to_string(model.curveOf.size()) +
                        " for " + std::to_string(n) + " patches");
        if (!model.bandEmissivity.empty() && hasEmissivityCurves(model))
            throw Error("thermal: emissivity against temperature takes the gray model: give per-band emissivities or "
                        "curves, not both");
        for (std::size_t c = 0; c < model.emissivityCurves.size(); ++c) {
            const EmissivityCurve& curve = model.emissivityCurves[c];
            if (curve.temperatureK.empty() || curve.temperatureK.size() != curve.emissivity.size())
                throw Error("thermal: emissivity curve " + std::to_string(c + 1) + " has " +
                            std::to_string(curve.temperatureK.size()) + " temperatures and " +
                            std::to_string(curve.emissivity.size()) + " emissivities: it needs as many of each, at least one");
            for (std::size_t k = 0; k < curve.temperatureK.size(); ++k) {
                const double T = curve.temperatureK[k], e = curve.emissivity[k];
                if (!(std::isfinite(T) && T >= 0.0 && (k == 0 || T > curve.temperatureK[k - 1])) || !(e >= 0.0 && e <= 1.0)) {
                    std::ostringstream msg;
                    msg << "thermal: emissivity curve " << c + 1 << ": point (" << T << " K, " << e
                        << ") must have a temperature >= 0 K above the previous one and an emissivity in [0, 1]";
                    throw Error(msg.str());
                }
            }
        }
        for (PatchId i = 0; i < n; ++i) {
            const std::int32_t c = model.curveOf[i];
            if (c < 0) continue;
            if (std::size_t(c) >= model.emissivityCurves.size())
                throw Error("thermal: " + describe(scene, i) + ": emissivity curve " + std::to_string(c + 1) + " does not exist");
            for (const double e : model.emissivityCurves[std::size_t(c)].emissivity)
                if (e + model.surface[i].specular > 1.0 + 1e-12) {
                    std::ostringstream msg;
                    msg << "thermal: " << describe(scene, i) << ": emissivity " << e << " of its curve + specular "
                        << model.surface[i].specular << " > 1";
                    throw Error(msg.str());
                }
        }
    }
    std::vector<double> emitting(model.isothermal.size(), 0.0);
    for (PatchId i = 0; i < n; ++i)
        if (model.condition[i].kind == Condition::Kind::Isothermal)
            emitting[model.condition[i].node] += largestEmissivity(model, i) * scene.patches[i].area;
    for (std::size_t k = 0; k < model.isothermal.size(); ++k) {
        std::ostringstream msg;
        if (!std::isfinite(model.isothermal[k].power))
            msg << "thermal: the power of isothermal node '" << model.isothermal[k].name << "' is not a finite number";
        else if (!(emitting[k] > 0.0))
            msg << "thermal: isothermal node '" << model.isothermal[k].name
                << "' has no patch that emits (eps > 0): its temperature is not defined";
        else
            continue;
        throw Error(msg.str());
    }
}

double EmissivityCurve::at(double T) const {
    if (!(T > temperatureK.front())) return emissivity.front();  // NaN too
    if (T >= temperatureK.back()) return emissivity.back();
    const std::size_t k = std::size_t(std::upper_bound(temperatureK.begin(), temperatureK.end(), T) - temperatureK.begin());
    const double t = (T - temperatureK[k - 1]) / (temperatureK[k] - temperatureK[k - 1]);
    return emissivity[k - 1] + t * (emissivity[k] - emissivity[k - 1]);
}

double largestEmissivity(const ThermalModel& model, std::size_t i) {
    const std::int32_t c = model.curveOf.empty() ? -1 : model.curveOf[i];
    if (c < 0 || std::size_t(c) >= model.emissivityCurves.size()) return model.surface[i].emissivity;
    const std::vector<double>& e = model.emissivityCurves[std::size_t(c)].emissivity;
    return e.empty() ? 0.0 : *std::max_element(e.begin(), e.end());
}

double emissivityAt(const ThermalModel& model, std::size_t i, double T) {
    const std::int32_t c = model.curveOf.empty() ? -1 : model.curveOf[i];
    return c < 0 ? model.surface[i].emissivity : model.emissivityCurves[std::size_t(c)].at(T);
}

void setEmissivitiesAt(ThermalModel& model, const std::vector<double>& T) {
    for (std::size_t i = 0; i < model.curveOf.size(); ++i)
        if (model.curveOf[i] >= 0 && std::isfinite(T[i])) model.surface[i].emissivity = emissivityAt(model, i, T[i]);
}

}  // namespace hemirad::thermal
