// The registry of form-factor back ends: one line per back end.
#include "preprocess/backend_registry.hpp"

#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <map>
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

namespace {

std::string shortest(double value) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value).ptr;
    return std::string(text, end);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> formFactorSettings(const MethodSettings& settings) {
    std::vector<std::pair<std::string, std::string>> out = {{"--method", settings.method},
                                                            {"--max-depth", std::to_string(settings.common.maxDepth)},
                                                            {"min_weight", shortest(settings.common.minWeight)}};
    for (const BackendOption& o : findBackend(settings.method).options) out.emplace_back(o.flag, o.get(settings));
    return out;
}

std::string formFactorSettingsText(const MethodSettings& settings) {
    std::string text;
    for (const auto& [flag, value] : formFactorSettings(settings)) text += (text.empty() ? "" : " ") + flag + "=" + value;
    return text;
}

std::string formFactorSettingsDifference(const std::string& made, const MethodSettings& now) {
    std::map<std::string, std::string> recorded;
    for (std::size_t at = 0; at < made.size();) {
        std::size_t end = made.find(' ', at);
        if (end == std::string::npos) end = made.size();
        const std::string item = made.substr(at, end - at);
        const std::size_t eq = item.find('=');
        if (eq != std::string::npos) recorded[item.substr(0, eq)] = item.substr(eq + 1);
        at = end + 1;
    }
    std::string out;
    auto differ = [&](const std::string& flag, const std::string& was, const std::string& is) {
        const bool first = out.empty();
        out += (first ? "" : ", ") + flag + " " + was + (first ? " (the file)" : "") + " against " + is +
               (first ? " (this run)" : "");
    };
    const std::vector<std::pair<std::string, std::string>> current = formFactorSettings(now);
    const auto method = recorded.find("--method");
    if (method == recorded.end() || method->second != now.method) {
        differ("--method", method == recorded.end() ? "(not recorded)" : method->second, now.method);
        return out;  // another back end: its options are not this one's
    }
    // An option a file does not record came after it: the file was made with its default.
    const BackendDescriptor& backend = findBackend(now.method);
    MethodSettings defaults = now;
    if (backend.defaults) defaults.own = backend.defaults();
    for (const auto& [flag, value] : current) {
        const auto it = recorded.find(flag);
        if (it != recorded.end()) {
            if (it->second != value) differ(flag, it->second, value);
            continue;
        }
        const BackendOption* option = nullptr;
        for (const BackendOption& o : backend.options)
            if (o.flag == flag) option = &o;
        if (!option || !backend.defaults || option->get(defaults) != value) differ(flag, "(not recorded)", value);
    }
    return out;
}

bool sameFormFactorSettings(const MethodSettings& a, const MethodSettings& b) {
    return formFactorSettingsDifference(formFactorSettingsText(a), b).empty();
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
