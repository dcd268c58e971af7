// The form-factor back ends by name: each registers a descriptor (its flags, defaults, validation,
// factory, work estimate and run description). The CLI, the GUI and the bench list the registry and
// never name a back end; adding one is its own folder plus one line in backend_registry.cpp.
#pragma once

#include "preprocess/form_factor_backend.hpp"

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hemirad {

enum class OptionKind { Switch, Integer, Choice };

/// One flag a back end takes, bound to a field of its options struct. Values are text in and out,
/// so the CLI parses, the GUI edits and the bench forwards them without knowing the struct.
struct BackendOption {
    std::string flag;                  ///< "--samples"
    std::string label;                 ///< GUI label
    std::string placeholder;           ///< usage text: "N" (empty for a switch)
    std::string help;                  ///< one usage line
    OptionKind kind = OptionKind::Integer;
    std::vector<std::string> choices;  ///< Choice: the accepted values
    long min = 0, max = 0;             ///< Integer: the accepted range
    bool even = false;                 ///< Integer: must be even
    /// Sets the field from text (a switch takes "yes" or "no"); throws hemirad::Error naming the flag
    /// and the value when it is not accepted.
    std::function<void(MethodSettings&, const std::string&)> set;
    /// The field as text, in the form set() takes.
    std::function<std::string(const MethodSettings&)> get;
    /// Empty when the option can change F for this scene and settings; else why it does not (e.g.
    /// directions the analytic estimator never casts), for front ends to say so next to the field.
    /// Unset: the option always matters.
    std::function<std::string(const Scene&, const MethodSettings&)> unusedBecause;
};

/// What a run of a back end is, for the report and the bench (settings that change nothing, e.g.
/// directions the analytic estimator never casts, are left out, so equal text means an equal run).
/// F's predicted size for a set of rows (form_factor_job.hpp): a cheap upper bound, or sample rows
/// computed and extrapolated.
struct MemoryPrediction {
    double bytes = 0;             ///< while F is built
    double nonzerosPerRow = 0;    ///< the bound's, or the samples' mean
    std::size_t sampledRows = 0;  ///< 0: the bound alone
    double secondsPerRow = 0;     ///< the samples' compute time per row (0 without samples)
};

struct RunDescription {
    std::string settings;           ///< "3072 directions x 1 origin (centroid)", ...
    bool lossFromRays = true;       ///< misses and back faces counted ray by ray (else 1 - row sum)
    std::vector<std::pair<std::string, std::string>> record;  ///< bench fields, e.g. {"samples", "3072"}
};

/// How a back end sees the hemisphere above a patch (what the GUI's inspector draws): directions
/// over the Nusselt disk (equal areas = equal form factor), or the five faces of a hemicube.
enum class Projection { NusseltDisk, HemicubeAtlas };

struct BackendDescriptor {
    std::string name;       ///< the --method value
    std::string summary;    ///< one line for usage texts and the GUI
    std::string workUnit;   ///< what workPerRow counts: "rays" or "pixels"
    /// Empty when the back end is in this build; else why not and how to get it ("configure with
    /// -DHEMIRAD_WITH_OPENGL=ON ..."): it is listed, and choosing it is an error saying so.
    std::string notBuilt;
    Projection projection = Projection::NusseltDisk;
    std::vector<BackendOption> options;
    std::function<std::any()> defaults;
    /// Checks combinations the per-flag checks cannot see; throws hemirad::Error.
    std::function<void(const MethodSettings&)> validate;
    std::function<std::unique_ptr<FormFactorBackend>(const MethodSettings&)> create;
    /// Rays (or pixels) one row costs, for progress rates and the memory estimate.
    std::function<double(const Scene&, const MethodSettings&)> workPerRow;
    /// Optional: bytes of scratch each worker thread holds while rows are computed (dense per-patch
    /// rows and flags: O(N) per thread), which the memory estimate counts once per thread.
    std::function<double(const Scene&, const MethodSettings&)> bytesPerThread;
    std::function<RunDescription(const Scene&, const MethodSettings&)> describe;
    /// Optional: settings the back end leaves to the scene and the machine (the hemisphere's
    /// --estimator auto) made definite in place, with a note for the report saying what was chosen
    /// and why; `predict` gives F's size for settings (form_factor_job.hpp), `budget` the bytes F
    /// may take (0: unknown). Must decide alike on every MPI rank for the same budget.
    std::function<std::string(const Scene&, MethodSettings&, const std::function<MemoryPrediction(const MethodSettings&)>& predict,
                              double budget)>
        resolve;

    /// The option with this flag, or null.
    const BackendOption* option(std::string_view flag) const;
};

/// Every back end this program knows, the hemisphere first; those left out of this build are listed
/// with notBuilt set.
const std::vector<const BackendDescriptor*>& formFactorBackends();

/// The back end used when none is named: the first one built (the hemisphere, or the hemicube in a
/// build without Embree).
const BackendDescriptor& defaultBackend();

/// Adds a back end defined outside this library (a plug-in, a test). `descriptor` must outlive its
/// use. Call before any thread reads the registry (from main() or a test's setup). Throws
/// hemirad::Error for a name in use or a descriptor without defaults, create, workPerRow or describe.
void registerFormFactorBackend(const BackendDescriptor& descriptor);

/// Removes a back end added by registerFormFactorBackend() (a plug-in unloaded, a test done); the
/// built-in back ends stay. Same threading rule as registering.
void unregisterFormFactorBackend(std::string_view name);

/// The named back end; throws hemirad::Error listing the known names.
const BackendDescriptor& findBackend(std::string_view name);

/// The back end's default settings. Throws hemirad::Error for an unknown back end or one not built.
MethodSettings defaultSettings(std::string_view method);

/// The settings that make F, as (flag, value) pairs in a fixed order: --method, --max-depth,
/// min_weight (the mirror chains' cut-off, which has no flag), then every option of the back end
/// as the registry's text. The thread count is left out: it changes how fast F is made, not F.
std::vector<std::pair<std::string, std::string>> formFactorSettings(const MethodSettings& settings);

/// formFactorSettings on one line, "--method=hemisphere --max-depth=8 ...": F records it in its
/// parameters ("settings"), so that a reuse can compare it (formFactorSettingsDifference).
std::string formFactorSettingsText(const MethodSettings& settings);

/// What differs between the settings an F was made with (`made`, formFactorSettingsText's line) and
/// `now`, for people: "--samples 512 (the file) against 4096 (this run), --origins 1 against 4"
/// (the back end alone when it differs); empty when they make the same F.
std::string formFactorSettingsDifference(const std::string& made, const MethodSettings& now);

/// True when `a` and `b` make the same F: the same back end, mirror depth and weight, and every one
/// of the back end's options equal (formFactorSettingsDifference of a's text and b is empty). The
/// rule the GUI and `--ff` reuse by.
bool sameFormFactorSettings(const MethodSettings& a, const MethodSettings& b);

/// Validates and creates the back end of `settings`. Throws hemirad::Error.
std::unique_ptr<FormFactorBackend> makeBackend(const MethodSettings& settings);

/// The option `flag` of any back end (null if none takes it): tells front ends whether it takes a value.
const BackendOption* findBackendOption(std::string_view flag);

/// Sets a back-end flag on `settings` from text. Throws hemirad::Error when the value is not
/// accepted, or when settings.method does not take the flag ("does not apply to --method X (it
/// takes ...)": options that would be silently ignored are errors).
void setBackendOption(MethodSettings& settings, const std::string& flag, const std::string& value);

/// `text` as an integer in [lo, hi]; throws hemirad::Error "FLAG expects an integer, got 'x'" or
/// "FLAG x is out of range [lo, hi]". Shared by the back ends' flags and hemirad's own.
long parseFlagInteger(const std::string& flag, const std::string& text, long lo, long hi);

/// Field-bound option builders for descriptors (T: the back end's options struct).
template <class T, class M>
BackendOption integerOption(std::string flag, std::string label, std::string placeholder, std::string help,
                            M T::*field, long min, long max, bool even = false) {
    BackendOption o{flag, std::move(label), std::move(placeholder), std::move(help), OptionKind::Integer, {}, min, max, even, {}, {}, {}};
    o.set = [=](MethodSettings& s, const std::string& text) {
        const long v = parseFlagInteger(flag, text, min, max);
        if (even && v % 2) throw Error(flag + " must be even, got " + text);
        s.as<T>().*field = static_cast<M>(v);
    };
    o.get = [=](const MethodSettings& s) { return std::to_string(s.as<T>().*field); };
    return o;
}

/// A flag without a value that sets `field` to `given`; the GUI shows it as a checkbox.
template <class T>
BackendOption switchOption(std::string flag, std::string label, std::string help, bool T::*field, bool given) {
    BackendOption o{flag, std::move(label), "", std::move(help), OptionKind::Switch, {}, 0, 0, false, {}, {}, {}};
    o.set = [=](MethodSettings& s, const std::string& text) {
        if (text != "yes" && text != "no") throw Error(flag + " is a switch (yes or no), got '" + text + "'");
        s.as<T>().*field = text == "yes" ? given : !given;
    };
    o.get = [=](const MethodSettings& s) { return s.as<T>().*field == given ? std::string("yes") : std::string("no"); };
    return o;
}

/// A flag whose value names an enumerator.
template <class T, class E>
BackendOption choiceOption(std::string flag, std::string label, std::string help, E T::*field,
                           std::vector<std::pair<std::string, E>> names) {
    std::vector<std::string> choices;
    for (const auto& n : names) choices.push_back(n.first);
    std::string placeholder;
    for (const auto& c : choices) placeholder += (placeholder.empty() ? "" : "|") + c;
    BackendOption o{flag, std::move(label), placeholder, std::move(help), OptionKind::Choice, choices, 0, 0, false, {}, {}, {}};
    o.set = [=](MethodSettings& s, const std::string& text) {
        for (const auto& [name, value] : names)
            if (name == text) {
                s.as<T>().*field = value;
                return;
            }
        std::string list;
        for (std::size_t k = 0; k < names.size(); ++k)
            list += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k].first;
        throw Error(flag + " expects " + list + ", got '" + text + "'");
    };
    o.get = [=](const MethodSettings& s) {
        for (const auto& [name, value] : names)
            if (s.as<T>().*field == value) return name;
        return std::string("?");
    };
    return o;
}

}  // namespace hemirad
