// The registry of form-factor back ends: one line per back end.
#include "preprocess/backend_registry.hpp"

#include <cerrno>
#include <cstdlib>
#if HEMIRAD_WITH_EMBREE
#include "preprocess/hemisphere/hemisphere_backend.hpp"
#endif
#if HEMIRAD_WITH_OPENGL
#include "preprocess/hemicube/hemicube_backend.hpp"
#endif

namespace hemirad {

namespace {

/// A back end left out of this build by a CMake feature option: listed, refused with the way to get it.
[[maybe_unused]] const BackendDescriptor& notBuilt(const char* name, const char* summary, const char* how) {
    static std::vector<std::unique_ptr<BackendDescriptor>> kept;
    auto d = std::make_unique<BackendDescriptor>();
    d->name = name;
    d->summary = summary;
    d->notBuilt = std::string("not built: configure with ") + how;
    kept.push_back(std::move(d));
    return *kept.back();
}

std::vector<const BackendDescriptor*>& registry() {
    static std::vector<const BackendDescriptor*> backends = {
#if HEMIRAD_WITH_EMBREE
        &hemisphereDescriptor(),
#else
        &notBuilt("hemisphere", "Embree rays along Beckers directions, or Lambert's exact factors with shadow rays",
                  "-DHEMIRAD_WITH_EMBREE=ON (needs libembree-dev)"),
#endif
#if HEMIRAD_WITH_OPENGL
        &hemicubeDescriptor(),
#else
        &notBuilt("hemicube", "OpenGL hemicubes (Cohen & Greenberg)",
                  "-DHEMIRAD_WITH_OPENGL=ON (needs libegl-dev, libosmesa6-dev and libgl-dev)"),
#endif
    };
    return backends;
}

}  // namespace

const std::vector<const BackendDescriptor*>& formFactorBackends() { return registry(); }

const BackendDescriptor& defaultBackend() {
    for (const BackendDescriptor* d : registry())
        if (d->notBuilt.empty()) return *d;
    throw Error("this build has no form-factor back end");  // CMake refuses such a configuration
}

void registerFormFactorBackend(const BackendDescriptor& descriptor) {
    for (const BackendDescriptor* d : registry())
        if (d->name == descriptor.name) throw Error("a form-factor back end named '" + descriptor.name + "' is registered already");
    if (!descriptor.defaults || !descriptor.create || !descriptor.workPerRow || !descriptor.describe)
        throw Error("form-factor back end '" + descriptor.name + "': defaults, create, workPerRow and describe are required");
    registry().push_back(&descriptor);
}

void unregisterFormFactorBackend(std::string_view name) {
    auto& list = registry();
    for (auto it = list.begin(); it != list.end(); ++it)
        if ((*it)->name == name) {
            if (*it == &defaultBackend()) throw Error("the default form-factor back end cannot be removed");
            list.erase(it);
            return;
        }
}

long parseFlagInteger(const std::string& flag, const std::string& text, long lo, long hi) {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno == ERANGE) throw Error(flag + " expects an integer, got '" + text + "'");
    if (v < lo || v > hi)
        throw Error(flag + " " + text + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
}

const BackendOption* BackendDescriptor::option(std::string_view flag) const {
    for (const BackendOption& o : options)
        if (o.flag == flag) return &o;
    return nullptr;
}

const BackendDescriptor& findBackend(std::string_view name) {
    std::string known;
    for (const BackendDescriptor* d : formFactorBackends()) {
        if (d->name == name) return *d;
        known += (known.empty() ? "" : ", ") + d->name;
    }
    throw Error("unknown --method '" + std::string(name) + "' (" + known + ")");
}

MethodSettings defaultSettings(std::string_view method) {
    const BackendDescriptor& d = findBackend(method);
    if (!d.notBuilt.empty()) throw Error("--method " + d.name + " is " + d.notBuilt);
    return {d.name, CommonOptions{}, d.defaults()};
}

bool sameFormFactorSettings(const MethodSettings& a, const MethodSettings& b) {
    if (a.method != b.method || a.common.maxDepth != b.common.maxDepth || a.common.minWeight != b.common.minWeight)
        return false;
    for (const BackendOption& o : findBackend(a.method).options)
        if (o.get(a) != o.get(b)) return false;
    return true;
}

std::unique_ptr<FormFactorBackend> makeBackend(const MethodSettings& settings) {
    const BackendDescriptor& d = findBackend(settings.method);
    if (!d.notBuilt.empty()) throw Error("--method " + d.name + " is " + d.notBuilt);
    if (!(settings.common.minWeight > 0.0 && settings.common.minWeight < 1.0))
        throw Error("minimum ray weight must be in (0, 1)");
    if (d.validate) d.validate(settings);
    return d.create(settings);
}

const BackendOption* findBackendOption(std::string_view flag) {
    for (const BackendDescriptor* d : formFactorBackends())
        if (const BackendOption* o = d->option(flag)) return o;
    return nullptr;
}

void setBackendOption(MethodSettings& settings, const std::string& flag, const std::string& value) {
    const BackendDescriptor& d = findBackend(settings.method);
    if (const BackendOption* o = d.option(flag)) {
        o->set(settings, value);
        return;
    }
    std::string list;
    for (const BackendOption& o : d.options) list += (list.empty() ? "" : ", ") + o.flag;
    if (!findBackendOption(flag)) throw Error("unknown option '" + flag + "'");
    throw Error("option '" + flag + "' does not apply to --method " + d.name + " (it takes " +
                (list.empty() ? std::string("no options of its own") : list) + ")");
}

}  // namespace hemirad
