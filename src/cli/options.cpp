// Strict option parsing: each flag lists the commands that accept it; values are range-checked.
#include "cli/options.hpp"
#include "thermal/conductor_writers.hpp"

#include "engine/atomic_file.hpp"
#include "engine/hash.hpp"
#include "environment/sky_model.hpp"
#include "rays/ray_scene.hpp"
#include "solve/solver_registry.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <set>

namespace hemirad {
namespace {

const std::set<std::string> kCommands = {"formfactors", "solve", "render", "thermal", "sky-view", "sun", "irradiance", "year", "sensors", "info", "subdivide", "check", "bench", "bench-run", "help"};
const std::set<std::string> kComputing = {"formfactors", "solve", "render", "thermal", "sky-view", "irradiance", "year", "sensors", "bench", "bench-run"};
const std::set<std::string> kSolving = {"solve", "render", "thermal", "irradiance", "year", "sensors", "bench", "bench-run"};
const std::set<std::string> kSun = {"sun", "irradiance", "sensors"};
const std::set<std::string> kOrientation = {"sun", "irradiance", "year", "sensors"};
const std::set<std::string> kThermal = {"thermal"};

const std::set<std::string> kBench = {"bench"};

double parseNumber(const std::string& flag, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw UsageError(flag + " expects a number, got '" + text + "'");
    if (v < lo || v > hi)
        throw UsageError(flag + " " + text + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
}

long parseInteger(const std::string& flag, const std::string& text, long lo, long hi) {
    try {
        return parseFlagInteger(flag, text, lo, hi);
    } catch (const Error& e) {
        throw UsageError(e.what());
    }
}

std::vector<std::string> splitCommas(const std::string& text) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = text.find(',', start);
        parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return parts;
}

std::vector<std::uint32_t> parseCounts(const std::string& flag, const std::string& text, long lo, long hi) {
    std::vector<std::uint32_t> values;
    for (const std::string& part : splitCommas(text))
        values.push_back(static_cast<std::uint32_t>(parseInteger(flag, part, lo, hi)));
    return values;
}

std::vector<double> parseList(const std::string& flag, const std::string& text, std::size_t count) {
    std::vector<double> values;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = text.find(',', start);
        const std::string piece = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        values.push_back(parseNumber(flag, piece, -1e300, 1e300));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (values.size() != count)
        throw UsageError(flag + " expects " + std::to_string(count) + " comma-separated numbers, got '" + text + "'");
    return values;
}

/// ".hff" for "F.HFF": the extension as the formats are named.
std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

/// --properties, --bc, --exchange: a file of the given extension.
std::function<void(Options&, const std::string&, const std::string&)> pathWith(std::string Options::*field, std::string ext) {
    return [field, ext](Options& o, const std::string& f, const std::string& v) {
        if (lowerExtension(v) != ext) throw UsageError(f + " expects a " + ext + " file, got '" + v + "'");
        o.*field = v;
    };
}

std::string joined(const std::vector<std::string>& names, const std::string& last) {
    std::string text;
    for (std::size_t k = 0; k < names.size(); ++k)
        text += (k == 0 ? "" : k + 1 == names.size() ? last : ", ") + names[k];
    return text;
}

/// The formats each writing command offers; the first is the default on standard output.
const std::vector<std::string>& outputFormats(const std::string& command) {
    static const std::map<std::string, std::vector<std::string>> formats = {
        {"formfactors", {"mtx", "hff"}}, {"solve", {"csv", "ply"}}, {"render", {"png"}}, {"thermal", {"csv"}}, {"sky-view", {"csv"}}, {"sun", {"csv"}}, {"irradiance", {"csv"}}, {"year", {"csv"}}, {"sensors", {"csv"}}};
    static const std::vector<std::string> none;
    const auto it = formats.find(command);
    return it == formats.end() ? none : it->second;
}

struct Flag {
    std::set<std::string> commands;  // empty: every command
    bool takesValue;
    std::function<void(Options&, const std::string&, const std::string&)> apply;
};

const std::map<std::string, Flag>& flags() {
    static const std::map<std::string, Flag> table = {
        {"-o", {{"formfactors", "solve", "render", "thermal", "sky-view", "sun", "irradiance", "year", "sensors", "subdivide", "bench"}, true,
                [](Options& o, const std::string&, const std::string& v) { o.output = v; }}},
        {"--format", {{"formfactors", "solve", "render"}, true,
                      [](Options& o, const std::string& f, const std::string& v) {
                          const std::vector<std::string>& names = outputFormats(o.command);
                          if (std::find(names.begin(), names.end(), v) == names.end())
                              throw UsageError(f + " for '" + o.command + "' expects " + joined(names, " or ") +
                                               ", got '" + v + "'");
                          o.format = v;
                      }}},
        {"--quiet", {{}, false, [](Options& o, const std::string&, const std::string&) { o.quiet = true; }}},
        {"--subdivide", {kComputing, true,
                         [](Options& o, const std::string& f, const std::string& v) { o.subdivide = parseNumber(f, v, 1e-12, 1e300); }}},
        {"--materials", {{"formfactors", "solve", "render", "thermal", "sky-view", "subdivide", "check", "bench", "bench-run"}, true,
                         [](Options& o, const std::string& f, const std::string& v) {
                             if (v.empty()) throw UsageError(f + " expects an MTL file name");
                             o.materials = v;
                         }}},
        {"--max-depth", {kComputing, true,
                         [](Options& o, const std::string& f, const std::string& v) {
                             o.formFactors.common.maxDepth = static_cast<std::uint32_t>(parseInteger(f, v, 0, 1000));
                         }}},
        {"--threads", {{}, true,
                       [](Options& o, const std::string& f, const std::string& v) {
                           o.formFactors.common.threads = static_cast<int>(parseInteger(f, v, 0, 4096));
                       }}},
        {"--all-rows", {kComputing, false, [](Options& o, const std::string&, const std::string&) { o.allRows = true; }}},
        {"--enforce-reciprocity",
         {kComputing, false, [](Options& o, const std::string&, const std::string&) { o.enforceReciprocity = true; }}},
        {"--drop-below", {{"formfactors", "solve", "render", "thermal"}, true,
                          [](Options& o, const std::string& f, const std::string& v) { o.dropBelow = parseNumber(f, v, 1e-30, 0.5); }}},
        {"--no-memory-check",
         {kComputing, false, [](Options& o, const std::string&, const std::string&) { o.memoryCheck = false; }}},
        {"--normalize-rows",
         {kComputing, false, [](Options& o, const std::string&, const std::string&) { o.normalizeRows = true; }}},
        {"--ff", {{"solve", "render", "thermal", "irradiance", "year"}, true, [](Options& o, const std::string&, const std::string& v) { o.ffPath = v; }}},
        {"--shards", {{"formfactors", "solve", "render", "thermal"}, false,
                      [](Options& o, const std::string&, const std::string&) { o.shards = true; }}},
        {"--recompute-ff", {{"solve", "render", "thermal", "irradiance", "year"}, false, [](Options& o, const std::string&, const std::string&) { o.recomputeFf = true; }}},
        {"--reuse-ff-anyway", {{"solve", "render", "thermal", "irradiance", "year"}, false, [](Options& o, const std::string&, const std::string&) { o.reuseFfAnyway = true; }}},
        {"--solver", {kSolving, true,
                      [](Options& o, const std::string& f, const std::string& v) {
                          try {
                              checkSolverName(v);
                              o.solver.solver = v;
                          } catch (const Error& e) {
                              throw UsageError(f + ": " + e.what());
                          }
                      }}},
        {"--tolerance", {kSolving, true,
                         [](Options& o, const std::string& f, const std::string& v) {
                             o.solver.tolerance = parseNumber(f, v, 1e-15, 0.5);
                         }}},
        {"--max-iterations", {kSolving, true,
                              [](Options& o, const std::string& f, const std::string& v) {
                                  o.solver.maxIterations = static_cast<int>(parseInteger(f, v, 1, 100000000));
                              }}},
        {"--allow-unconverged",
         {kSolving, false, [](Options& o, const std::string&, const std::string&) { o.solver.allowUnconverged = true; }}},
        {"--crease", {{"solve", "render"}, true,
                      [](Options& o, const std::string& f, const std::string& v) { o.crease = parseNumber(f, v, 0, 180); }}},
        {"--size", {{"render"}, true,
                    [](Options& o, const std::string& f, const std::string& v) {
                        const std::size_t x = v.find('x');
                        if (x == std::string::npos) throw UsageError(f + " expects WxH, e.g. 640x480, got '" + v + "'");
                        o.width = static_cast<int>(parseInteger(f, v.substr(0, x), 1, 16384));
                        o.height = static_cast<int>(parseInteger(f, v.substr(x + 1), 1, 16384));
                    }}},
        {"--camera", {{"render"}, true,
                      [](Options& o, const std::string& f, const std::string& v) {
                          const auto c = parseList(f, v, 7);
                          Camera cam;
                          cam.eye = Vec3(c[0], c[1], c[2]);
                          cam.target = Vec3(c[3], c[4], c[5]);
                          cam.fovY = c[6];
                          try {
                              checkCamera(cam);
                          } catch (const Error& e) {
                              throw UsageError(f + ": " + e.what());
                          }
                          o.camera = cam;
                      }}},
        {"--spp", {{"render"}, true,
                   [](Options& o, const std::string& f, const std::string& v) {
                       o.samplesPerPixel = static_cast<int>(parseInteger(f, v, 1, 1024));
                   }}},
        {"--exposure", {{"render", "solve"}, true,
                        [](Options& o, const std::string& f, const std::string& v) { o.exposure = parseNumber(f, v, 1e-30, 1e30); }}},
        {"--flat", {{"render"}, false, [](Options& o, const std::string&, const std::string&) { o.flat = true; }}},
        {"--properties", {kThermal, true, pathWith(&Options::propertiesPath, ".toml")}},
        {"--bc", {kThermal, true, pathWith(&Options::conditionsPath, ".toml")}},
        {"--exchange", {kThermal, true, pathWith(&Options::exchangePath, ".csv")}},
        {"--conductors", {kThermal, true,
                          [](Options& o, const std::string& f, const std::string& v) {
                              if (v.empty()) throw UsageError(f + " expects a file name");
                              o.conductorsPath = v;
                          }}},
        {"--conductor-format", {kThermal, true,
                                [](Options& o, const std::string& f, const std::string& v) {
                                    if (v != "csv" && v != "mtx" && v != "esatan" && v != "sinda")
                                        throw UsageError(f + " expects csv, mtx, esatan or sinda, got '" + v + "'");
                                    o.conductorFormat = v;
                                }}},
        {"--lump", {kThermal, true,
                    [](Options& o, const std::string& f, const std::string& v) {
                        if (v != "objects" && v != "patches") throw UsageError(f + " expects objects or patches, got '" + v + "'");
                        o.lumping = v;
                    }}},
        {"--gebhart", {kThermal, true,
                       [](Options& o, const std::string& f, const std::string& v) {
                           if (v != "auto" && v != "columns" && v != "dense")
                               throw UsageError(f + " expects auto, columns or dense, got '" + v + "'");
                           o.gebhartMethod = v;
                       }}},
        {"--gr-threshold", {kThermal, true,
                            [](Options& o, const std::string& f, const std::string& v) { o.couplingThreshold = parseNumber(f, v, 0.0, 0.5); }}},
        {"--unit", {{"thermal", "irradiance", "year", "sensors"}, true,
                    [](Options& o, const std::string& f, const std::string& v) {
                        try {
                            metresPerUnit(v);
                        } catch (const Error& e) {
                            throw UsageError(f + ": " + e.what());
                        }
                        if (v.empty()) throw UsageError(f + " expects a length unit (m, cm, mm, in, ft)");
                        o.lengthUnit = v;
                    }}},
        {"--sun-direction", {kSun, true,
                             [](Options& o, const std::string& f, const std::string& v) {
                                 const auto c = parseList(f, v, 3);
                                 o.sunDirectionVector = Vec3(c[0], c[1], c[2]);
                                 if (!(o.sunDirectionVector->norm() > 0.0)) throw UsageError(f + " must not be the zero vector");
                             }}},
        {"--sun-time", {kSun, true, [](Options& o, const std::string&, const std::string& v) { o.sunTime = v; }}},
        {"--latitude", {kSun, true, [](Options& o, const std::string& f, const std::string& v) { o.latitude = parseNumber(f, v, -90, 90); }}},
        {"--longitude", {kSun, true, [](Options& o, const std::string& f, const std::string& v) { o.longitude = parseNumber(f, v, -180, 180); }}},
        {"--up", {kOrientation, true,
                  [](Options& o, const std::string& f, const std::string& v) {
                      if (v != "z" && v != "y") throw UsageError(f + " expects z or y, got '" + v + "'");
                      o.upAxis = v;
                  }}},
        {"--north", {kOrientation, true,
                     [](Options& o, const std::string& f, const std::string& v) {
                         const auto c = parseList(f, v, 3);
                         o.north = Vec3(c[0], c[1], c[2]);
                     }}},
        {"--dni", {kSun, true, [](Options& o, const std::string& f, const std::string& v) { o.dni = parseNumber(f, v, 0, 1e5); }}},
        {"--weather", {{"year"}, true, pathWith(&Options::weatherPath, ".epw")}},
        {"--hourly", {{"year"}, true, pathWith(&Options::hourlyPath, ".npy")}},
        {"--dhi", {{"irradiance", "sensors"}, true, [](Options& o, const std::string& f, const std::string& v) { o.dhi = parseNumber(f, v, 0, 1e5); }}},
        {"--sky", {{"irradiance", "year", "sensors"}, true,
                   [](Options& o, const std::string& f, const std::string& v) {
                       if (v != "isotropic") try {
                               parseSkyModel(v);
                           } catch (const Error& e) {
                               throw UsageError(f + ": " + e.what() + " (or isotropic, the default)");
                           }
                       o.skyModel = v;
                   }}},
        {"--svf", {{"irradiance", "year"}, true, pathWith(&Options::skyViewPath, ".csv")}},
        {"--sky-subdivision", {{"irradiance", "year", "sensors"}, true,
                               [](Options& o, const std::string& f, const std::string& v) { o.skySubdivision = int(parseInteger(f, v, 1, 8)); }}},
        {"--sky-samples", {{"irradiance", "year", "sensors"}, true,
                           [](Options& o, const std::string& f, const std::string& v) { o.skySamples = int(parseInteger(f, v, 1, 16)); }}},
        {"--sensors", {{"sensors", "year"}, true, pathWith(&Options::sensorsPath, ".csv")}},
        {"--grid", {{"sensors", "year"}, true,
                    [](Options& o, const std::string& f, const std::string& v) {
                        if (v.empty()) throw UsageError(f + " expects an object name");
                        o.gridObject = v;
                    }}},
        {"--spacing", {{"sensors", "year"}, true, [](Options& o, const std::string& f, const std::string& v) { o.gridSpacing = parseNumber(f, v, 0, 1e300); }}},
        {"--height", {{"sensors", "year"}, true, [](Options& o, const std::string& f, const std::string& v) { o.gridHeight = parseNumber(f, v, -1e300, 1e300); }}},
        {"--factors", {{"sensors"}, true, pathWith(&Options::sensorFactorsPath, ".mtx")}},
        {"--sensor-estimator", {{"sensors", "year"}, true,
                                [](Options& o, const std::string&, const std::string& v) {
                                    try {
                                        o.sensorFactors.estimator = parseSensorEstimator(v);
                                    } catch (const Error& e) {
                                        throw UsageError(e.what());
                                    }
                                }}},
        {"--sensor-rays", {{"sensors", "year"}, true,
                           [](Options& o, const std::string& f, const std::string& v) {
                               o.sensorFactors.rays = std::uint32_t(parseInteger(f, v, 1, 1 << 24));
                           }}},
        {"--sensor-output", {{"year"}, true, pathWith(&Options::sensorOutputPath, ".csv")}},
        {"--glare", {{"sun"}, true, pathWith(&Options::glarePath, ".csv")}},
        {"--sensor-hourly", {{"year"}, true, pathWith(&Options::sensorHourlyPath, ".npy")}},
        {"--objects", {{"solve", "thermal"}, true,
                       [](Options& o, const std::string& f, const std::string& v) {
                           if (lowerExtension(v) != ".csv") throw UsageError(f + " writes a CSV table: '" + v + "' must end in .csv");
                           o.objectsPath = v;
                       }}},
        {"--sky-view", {{"solve"}, false, [](Options& o, const std::string&, const std::string&) { o.skyView = true; }}},
        {"--false-color", {{"render"}, true,
                           [](Options& o, const std::string&, const std::string& v) {
                               try {
                                   o.falseColour = parseFalseColourQuantity(v);
                               } catch (const Error& e) {
                                   throw UsageError(e.what());
                               }
                           }}},
        {"--scale", {{"render"}, true,
                     [](Options& o, const std::string&, const std::string& v) {
                         try {
                             o.falseColourScale = parseFalseColourScale(v);
                         } catch (const Error& e) {
                             throw UsageError(e.what());
                         }
                     }}},
        {"--range", {{"render"}, true,
                     [](Options& o, const std::string& f, const std::string& v) {
                         const std::size_t colon = v.find(':');
                         if (colon == std::string::npos)
                             throw UsageError(f + " expects MIN:MAX (either may be empty: automatic), got '" + v + "'");
                         if (colon > 0) o.rangeMin = parseNumber(f, v.substr(0, colon), -1e300, 1e300);
                         if (colon + 1 < v.size()) o.rangeMax = parseNumber(f, v.substr(colon + 1), -1e300, 1e300);
                         if (o.rangeMin && o.rangeMax && !(*o.rangeMin < *o.rangeMax))
                             throw UsageError(f + " " + v + ": MIN must be below MAX");
                     }}},
        {"--sweep-samples", {kBench, true,
                             [](Options& o, const std::string& f, const std::string& v) {
                                 o.sweepSamples = parseCounts(f, v, 1, 1 << 24);
                             }}},
        {"--sweep-origins", {kBench, true,
                             [](Options& o, const std::string& f, const std::string& v) {
                                 o.sweepOrigins = parseCounts(f, v, 1, 1 << 16);
                             }}},
        {"--sweep-resolutions", {kBench, true,
                                 [](Options& o, const std::string& f, const std::string& v) {
                                     o.sweepResolutions = parseCounts(f, v, 2, 8192);
                                     for (std::uint32_t r : o.sweepResolutions)
                                         if (r % 2) throw UsageError(f + ": resolutions must be even");
                                 }}},
        {"--reference-samples", {kBench, true,
                                 [](Options& o, const std::string& f, const std::string& v) {
                                     o.referenceSamples = static_cast<std::uint32_t>(parseInteger(f, v, 1, 1 << 24));
                                 }}},
        {"--reference-origins", {kBench, true,
                                 [](Options& o, const std::string& f, const std::string& v) {
                                     o.referenceOrigins = static_cast<std::uint32_t>(parseInteger(f, v, 1, 1 << 16));
                                 }}},
        {"--reference-estimator", {kBench, true,
                                   [](Options& o, const std::string& f, const std::string& v) {
                                       if (v != "rays" && v != "analytic")
                                           throw UsageError(f + " expects rays or analytic, got '" + v + "'");
                                       o.referenceEstimator = v;
                                   }}},
        {"--cache", {kBench, true, [](Options& o, const std::string&, const std::string& v) { o.cacheDir = v; }}},
        {"--json", {{"bench", "check"}, true, [](Options& o, const std::string&, const std::string& v) { o.jsonPath = v; }}},
        {"--label", {{"bench", "bench-run"}, true, [](Options& o, const std::string&, const std::string& v) { o.label = v; }}},
        {"--reference", {{"bench-run"}, true, [](Options& o, const std::string&, const std::string& v) { o.referencePath = v; }}},
        {"--reference-radiosity",
         {{"bench-run"}, true, [](Options& o, const std::string&, const std::string& v) { o.referenceRadiosityPath = v; }}},
        {"--max-edge", {{"subdivide"}, true,
                        [](Options& o, const std::string& f, const std::string& v) { o.maxEdge = parseNumber(f, v, 1e-12, 1e300); }}},
        {"--sliver-ratio", {{"check"}, true,
                            [](Options& o, const std::string& f, const std::string& v) { o.sliverRatio = parseNumber(f, v, 1, 1e12); }}},
        {"--relative-tolerance", {{"check"}, true,
                                  [](Options& o, const std::string& f, const std::string& v) {
                                      o.relativeTolerance = parseNumber(f, v, 1e-12, 1e-2);
                                  }}},
    };
    return table;
}

}  // namespace

namespace {

void setOption(MethodSettings& settings, const std::string& flag, const std::string& value) {
    try {
        setBackendOption(settings, flag, value);
    } catch (const Error& e) {
        throw UsageError(e.what());
    }
}

MethodSettings methodSettings(const std::string& name) {
    try {
        return defaultSettings(name);
    } catch (const Error& e) {
        throw UsageError(e.what());
    }
}

/// The back end's checks of combinations of its flags, as usage errors.
void validateSettings(const MethodSettings& settings) {
    const BackendDescriptor& backend = findBackend(settings.method);
    if (!backend.validate) return;
    try {
        backend.validate(settings);
    } catch (const Error& e) {
        throw UsageError(e.what());
    }
}

struct ParsedFlag {
    std::string flag, value;
};

}  // namespace

Options parseOptions(int argc, const char* const* argv) {
    Options o;
    if (argc < 2) throw UsageError("no command given");
    o.command = argv[1];
    if (o.command == "--help" || o.command == "-h") o.command = "help";
    if (!kCommands.count(o.command)) throw UsageError("unknown command '" + o.command + "'");

    // Pass 1: split flags from inputs. Back-end flags are looked up in the registry; the chosen
    // --method (or bench's --methods) decides in pass 2 whether they apply.
    std::vector<ParsedFlag> parsed;
    for (int k = 2; k < argc; ++k) {
        std::string arg = argv[k];
        if (arg == "--help" || arg == "-h") {
            o.command = "help";
            return o;
        }
        if (arg.size() > 1 && arg[0] == '-' && !(std::isdigit(static_cast<unsigned char>(arg[1])) || arg[1] == '.')) {
            std::string value;
            bool inlineValue = false;
            const std::size_t eq = arg.find('=');
            if (arg.rfind("--", 0) == 0 && eq != std::string::npos) {
                value = arg.substr(eq + 1);
                arg = arg.substr(0, eq);
                inlineValue = true;
            }
            bool takesValue;
            if (const auto it = flags().find(arg); it != flags().end()) takesValue = it->second.takesValue;
            else if (arg == "--method" || arg == "--methods") takesValue = true;
            else if (const BackendOption* b = findBackendOption(arg)) takesValue = b->kind != OptionKind::Switch;
            else throw UsageError("unknown option '" + arg + "'");
            if (takesValue && !inlineValue) {
                if (k + 1 >= argc) throw UsageError("option '" + arg + "' needs a value");
                value = argv[++k];
            } else if (!takesValue && inlineValue) {
                throw UsageError("option '" + arg + "' takes no value");
            } else if (!takesValue) {
                value = "yes";
            }
            parsed.push_back({arg, value});
            continue;
        }
        o.inputs.push_back(arg);
    }

    // The back ends: --method for the commands that compute F, --methods for bench.
    const bool computing = kComputing.count(o.command) > 0;
    const bool bench = o.command == "bench";
    std::string method = defaultBackend().name;
    std::vector<std::string> benchNames = {method};
    for (const ParsedFlag& p : parsed) {
        if (p.flag == "--method") {
            if (!computing || bench)
                throw UsageError("option '--method' does not apply to '" + o.command + "'" + (bench ? " (use --methods)" : ""));
            method = p.value;
        } else if (p.flag == "--methods") {
            if (!bench) throw UsageError("option '--methods' does not apply to '" + o.command + "'");
            benchNames = splitCommas(p.value);
        }
    }
    o.formFactors = methodSettings(method);
    if (bench)
        for (const std::string& name : benchNames) o.benchMethods.push_back(methodSettings(name));

    // Pass 2: every flag in command-line order.
    for (const ParsedFlag& p : parsed) {
        if (p.flag == "--method" || p.flag == "--methods") continue;
        if (const auto it = flags().find(p.flag); it != flags().end()) {
            const Flag& flag = it->second;
            if (!flag.commands.empty() && !flag.commands.count(o.command))
                throw UsageError("option '" + p.flag + "' does not apply to '" + o.command + "'");
            flag.apply(o, p.flag, p.value);
            continue;
        }
        // A back end's own flag.
        if (!computing) throw UsageError("option '" + p.flag + "' does not apply to '" + o.command + "'");
        if (bench) {
            bool taken = false;
            for (MethodSettings& m : o.benchMethods)
                if (findBackend(m.method).option(p.flag)) {
                    setOption(m, p.flag, p.value);
                    taken = true;
                }
            if (!taken) throw UsageError("option '" + p.flag + "' does not apply to any of the --methods");
            continue;
        }
        setOption(o.formFactors, p.flag, p.value);
    }
    for (MethodSettings& m : o.benchMethods) m.common = o.formFactors.common;
    // Combinations the per-flag checks cannot see (e.g. --mirrors rays in a build without Embree).
    if (computing && !bench) validateSettings(o.formFactors);
    for (const MethodSettings& m : o.benchMethods) validateSettings(m);
    // Solve flags the chosen solver takes (auto may pick either kind, so it takes them all).
    if (o.solver.solver != "auto") {
        const SolverDescriptor& solver = findSolver(o.solver.solver);
        for (const ParsedFlag& p : parsed)
            if ((p.flag == "--tolerance" || p.flag == "--max-iterations") &&
                std::find(solver.flags.begin(), solver.flags.end(), p.flag) == solver.flags.end())
                throw UsageError("option '" + p.flag + "' does not apply to --solver " + solver.name +
                                 " (a factorisation: it does not iterate)");
    }

    if (o.command == "help") return o;
    if (o.command == "render" && !rayCastingNotBuilt().empty())
        throw UsageError("'render' traces rays with Embree, which is " + rayCastingNotBuilt());
    if (o.inputs.size() != 1)
        throw UsageError("'" + o.command + "' takes exactly one input file, got " + std::to_string(o.inputs.size()));
    const bool needsOutput = o.command == "formfactors" || o.command == "subdivide" || o.command == "bench" || o.command == "sky-view" ||
                             o.command == "sun" || o.command == "irradiance" || o.command == "year" || o.command == "sensors";
    if (needsOutput && o.output.empty()) throw UsageError("'" + o.command + "' needs -o OUTPUT");
    if (o.command == "render" && o.output.empty()) throw UsageError("'render' needs -o IMAGE.png");
    if (!o.falseColour) {
        for (const ParsedFlag& p : parsed)
            if (p.flag == "--scale" || p.flag == "--range") throw UsageError(p.flag + " needs --false-color QUANTITY");
    } else {
        for (const ParsedFlag& p : parsed)
            if (p.flag == "--exposure" || p.flag == "--spp" || p.flag == "--flat" || p.flag == "--crease")
                throw UsageError(p.flag + " does not apply with --false-color (one ray per pixel, one colour per patch)");
        if (o.falseColourScale == FalseColourScale::Log && o.rangeMin && !(*o.rangeMin > 0.0)) throw UsageError("--range: a log scale needs MIN > 0");
        // The sky view factor needs no B: render computes its own F (sky-view's) and solves nothing.
        if (*o.falseColour == FalseColourQuantity::SkyViewFactor)
            for (const ParsedFlag& p : parsed)
                if (p.flag == "--ff" || p.flag == "--recompute-ff" || p.flag == "--reuse-ff-anyway" || p.flag == "--shards" ||
                    p.flag == "--drop-below" || p.flag == "--solver" || p.flag == "--tolerance" ||
                    p.flag == "--max-iterations" || p.flag == "--allow-unconverged")
                    throw UsageError(p.flag + " does not apply with --false-color sky_view_factor (sky view factors "
                                     "need no stored F and no solve)");
    }
    if (o.skyView && o.output.empty())
        throw UsageError("--sky-view adds a column to -o B.csv (a face property to B.ply): it needs -o");
    if (o.command == "solve" && o.output.empty() && o.ffPath.empty() && o.objectsPath.empty())
        throw UsageError("'solve' needs -o B.csv|B.ply (or --ff to only store F, or --objects T.csv)");
    if (o.command == "subdivide" && o.maxEdge <= 0) throw UsageError("'subdivide' needs --max-edge L");
    if (o.command == "year" && o.weatherPath.empty()) throw UsageError("'year' needs --weather FILE.epw");
    if ((o.command == "irradiance" || o.command == "year") &&
        std::none_of(parsed.begin(), parsed.end(), [](const ParsedFlag& p) { return p.flag == "--tolerance"; }))
        o.solver.tolerance = 1e-10;  // the power balance is read to many digits
    if (o.command == "irradiance" && !o.dni) throw UsageError("'irradiance' needs --dni W (and --dhi W for the sky)");
    if (o.command == "sensors" || o.command == "year") {
        const bool given = !o.sensorsPath.empty() || !o.gridObject.empty();
        if (!o.sensorsPath.empty() && !o.gridObject.empty())
            throw UsageError("give --sensors FILE.csv or --grid OBJECT --spacing D, not both");
        if (o.command == "sensors" && !given)
            throw UsageError("'sensors' needs --sensors FILE.csv or --grid OBJECT --spacing D (one of them)");
        const bool spaced = std::any_of(parsed.begin(), parsed.end(), [](const ParsedFlag& p) { return p.flag == "--spacing"; });
        const bool lifted = std::any_of(parsed.begin(), parsed.end(), [](const ParsedFlag& p) { return p.flag == "--height"; });
        if (!o.gridObject.empty() && !(o.gridSpacing > 0.0)) throw UsageError("--grid needs --spacing D > 0");
        if (o.gridObject.empty() && (spaced || lifted)) throw UsageError("--spacing and --height lay a --grid OBJECT");
        if (o.command == "year" && given && o.sensorOutputPath.empty())
            throw UsageError("'year' with sensors writes their annual sums to --sensor-output FILE.csv: give it");
        if (o.command == "year" && !given && (!o.sensorOutputPath.empty() || !o.sensorHourlyPath.empty()))
            throw UsageError("--sensor-output and --sensor-hourly need --sensors FILE.csv or --grid OBJECT --spacing D");
    }
    if (o.command == "sensors") {
        const bool sunGiven = o.sunDirectionVector || !o.sunTime.empty() || o.latitude || o.longitude;
        const bool skyGiven =
            std::any_of(parsed.begin(), parsed.end(), [](const ParsedFlag& p) { return p.flag == "--dhi" || p.flag == "--sky"; });
        if (!o.dni && (sunGiven || skyGiven))
            throw UsageError("'sensors' gives irradiance with --dni W (and the sun, and --dhi W and --sky MODEL for the sky)");
        if (std::none_of(parsed.begin(), parsed.end(), [](const ParsedFlag& p) { return p.flag == "--tolerance"; }))
            o.solver.tolerance = 1e-10;
    }
    if (!o.glarePath.empty() && !o.dni) throw UsageError("--glare needs --dni W (the reflected sun's irradiance)");
    if (o.skyModel == "isotropic" && std::any_of(parsed.begin(), parsed.end(), [](const ParsedFlag& p) {
            return p.flag == "--sky-subdivision" || p.flag == "--sky-samples";
        }))
        throw UsageError("--sky-subdivision and --sky-samples cut a sky model's cells: give --sky MODEL (the isotropic sky has none)");
    if (o.skyModel != "isotropic" && !o.skyViewPath.empty())
        throw UsageError("--svf stores the isotropic sky's view factors; --sky " + o.skyModel + " takes its daylight coefficients instead");
    if (o.command == "sun" || o.command == "irradiance" || (o.command == "sensors" && o.dni)) {
        const bool byTime = !o.sunTime.empty() || o.latitude || o.longitude;
        if (o.sunDirectionVector && byTime)
            throw UsageError("give --sun-direction or --sun-time with --latitude and --longitude, not both");
        if (!o.sunDirectionVector && !(!o.sunTime.empty() && o.latitude && o.longitude))
            throw UsageError("'" + o.command + "' needs --sun-direction x,y,z, or --sun-time T --latitude LAT --longitude LON");
    }
    if (o.command == "thermal") {
        // Heat balances are read to many digits (and a flux condition's row has reflectance 1): the
        // iterative solvers go to 1e-10 unless told otherwise.
        if (std::none_of(parsed.begin(), parsed.end(), [](const ParsedFlag& p) { return p.flag == "--tolerance"; }))
            o.solver.tolerance = 1e-10;
        if (o.conditionsPath.empty()) throw UsageError("'thermal' needs --bc CONDITIONS.toml (docs/thermal.md)");
        if (o.output.empty() && o.objectsPath.empty() && o.conductorsPath.empty() && o.exchangePath.empty())
            throw UsageError("'thermal' needs -o T.csv, --objects O.csv, --conductors GR.txt or --exchange Q.csv");
        if (!o.conductorsPath.empty() && o.conductorFormat.empty() && thermal::conductorFormatFor(o.conductorsPath).empty())
            throw UsageError("--conductors " + o.conductorsPath + ": the extension names no format (.csv, .mtx, .esatan, "
                             ".sinda), so give --conductor-format");
        if (o.conductorsPath.empty() && (!o.conductorFormat.empty()))
            throw UsageError("--conductor-format needs --conductors FILE");
    }
    if (o.recomputeFf && o.ffPath.empty()) throw UsageError("--recompute-ff needs --ff FILE");
    if (o.reuseFfAnyway && o.ffPath.empty()) throw UsageError("--reuse-ff-anyway needs --ff FILE");
    if (o.reuseFfAnyway && o.recomputeFf)
        throw UsageError("--reuse-ff-anyway and --recompute-ff contradict each other: reuse FILE, or compute F again");
    if (isStandardOutput(o.ffPath))
        throw UsageError("--ff names a file that F is read from or stored in; standard output ('-') cannot be either");
    if (o.command == "subdivide" && isStandardOutput(o.output))
        throw UsageError("'subdivide' writes an OBJ and its MTL beside it: -o needs a file name, not '-'");
    if (isStandardOutput(o.output) && isStandardOutput(o.jsonPath))
        throw UsageError("-o - and --json - would both write to standard output; give one of them a file name");
    if (!o.output.empty() && !outputFormats(o.command).empty()) outputFormat(o);  // usage errors before any work
    if (o.shards) {
        const std::string& path = o.command == "formfactors" ? o.output : o.ffPath;
        if (path.empty()) throw UsageError("--shards stores F: it needs --ff FILE.hff");
        const std::string ext = lowerExtension(path);
        if (ext != ".hff")
            throw UsageError("--shards writes .hff shards and a manifest: '" + path + "' must end in .hff");
    }
    return o;
}

bool outputIsBinary(const Options& o) {
    if (outputFormats(o.command).empty()) return false;
    const std::string format = outputFormat(o);
    return format != "mtx" && format != "csv";
}

std::uint64_t optionsHash(const Options& o) {
    Fnv1a h;
    auto text = [&h](const std::string& s) {
        h.addValue(std::uint64_t(s.size()));
        h.add(s.data(), s.size());
    };
    auto texts = [&](const std::vector<std::string>& list) {
        h.addValue(std::uint64_t(list.size()));
        for (const std::string& s : list) text(s);
    };
    auto counts = [&h](const std::vector<std::uint32_t>& list) {
        h.addValue(std::uint64_t(list.size()));
        for (std::uint32_t v : list) h.addValue(v);
    };
    auto optional = [&h](const std::optional<double>& v) {
        h.addValue(v.has_value());
        h.addValue(v.value_or(0.0));
    };
    auto vector = [&h](const Vec3& v) { h.add(v.data(), 3 * sizeof(double)); };
    // Every setting that makes F but the thread count, which each rank takes from its own machine
    // (none for `help`, which stops parsing before a method is set).
    auto settings = [&](const MethodSettings& m) { text(m.method.empty() ? std::string() : formFactorSettingsText(m)); };
    // Each group as Options declares it.
    text(o.command); texts(o.inputs); text(o.output); text(o.format); h.addValue(o.quiet);
    h.addValue(o.subdivide); text(o.materials);
    settings(o.formFactors); h.addValue(o.allRows); h.addValue(o.enforceReciprocity);
    h.addValue(o.dropBelow); h.addValue(o.normalizeRows); h.addValue(o.memoryCheck); text(o.ffPath); text(o.skyViewPath);
    h.addValue(o.recomputeFf); h.addValue(o.reuseFfAnyway); h.addValue(o.shards);
    text(o.solver.solver); h.addValue(o.solver.tolerance); h.addValue(o.solver.maxIterations);
    h.addValue(o.solver.allowUnconverged); h.addValue(std::uint64_t(o.solver.memoryLimit)); h.addValue(o.crease);
    h.addValue(o.width); h.addValue(o.height); h.addValue(o.camera.has_value());
    if (o.camera) {
        vector(o.camera->eye); vector(o.camera->target); vector(o.camera->up); h.addValue(o.camera->fovY);
    }
    h.addValue(o.samplesPerPixel); h.addValue(o.exposure); h.addValue(o.flat); text(o.objectsPath); h.addValue(o.skyView);
    h.addValue(o.falseColour.has_value()); h.addValue(int(o.falseColour.value_or(FalseColourQuantity::Radiosity)));
    h.addValue(int(o.falseColourScale)); optional(o.rangeMin); optional(o.rangeMax);
    text(o.propertiesPath); text(o.conditionsPath); text(o.conductorsPath); text(o.conductorFormat); text(o.lumping);
    text(o.gebhartMethod); h.addValue(o.couplingThreshold); text(o.exchangePath); text(o.lengthUnit);
    h.addValue(o.sunDirectionVector.has_value());
    if (o.sunDirectionVector) vector(*o.sunDirectionVector);
    text(o.sunTime); optional(o.latitude); optional(o.longitude); text(o.upAxis); h.addValue(o.north.has_value());
    if (o.north) vector(*o.north);
    optional(o.dni); h.addValue(o.dhi); text(o.weatherPath); text(o.hourlyPath);
    text(o.skyModel); h.addValue(std::int64_t(o.skySubdivision)); h.addValue(std::int64_t(o.skySamples));
    h.addValue(o.maxEdge); h.addValue(o.sliverRatio); h.addValue(o.relativeTolerance);
    h.addValue(std::uint64_t(o.benchMethods.size()));
    for (const MethodSettings& m : o.benchMethods) settings(m);
    counts(o.sweepSamples); counts(o.sweepOrigins); counts(o.sweepResolutions);
    h.addValue(o.referenceSamples); h.addValue(o.referenceOrigins); text(o.referenceEstimator); text(o.cacheDir);
    text(o.jsonPath); text(o.label); text(o.referencePath); text(o.referenceRadiosityPath);
    return h.value();
}

bool reportsToStandardError(const Options& o) {
    return isStandardOutput(o.output) || isStandardOutput(o.jsonPath);
}

std::string outputFormat(const Options& o) {
    const std::vector<std::string>& names = outputFormats(o.command);
    const std::string ext = lowerExtension(o.output);
    if (!ext.empty() && std::find(names.begin(), names.end(), ext.substr(1)) != names.end()) {
        if (!o.format.empty() && o.format != ext.substr(1))
            throw UsageError("-o " + o.output + " and --format " + o.format + " disagree; the extension names the format");
        return ext.substr(1);
    }
    if (isStandardOutput(o.output)) return o.format.empty() ? names.front() : o.format;
    if (writesInPlace(o.output))  // a FIFO or device: F defaults to the compact .hff (-o /dev/null to time F)
        return !o.format.empty() ? o.format : o.command == "formfactors" ? "hff" : names.front();
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "." : " or .") + name;
    throw UsageError("'" + o.command + "' -o " + o.output + ": unknown output type '" + ext + "' (use " + list +
                     ", or -o - for standard output)");
}

std::string usageText() {
    std::string methodNames, backendSections;
    for (const BackendDescriptor* d : formFactorBackends()) {
        methodNames += (methodNames.empty() ? "" : ", ") + d->name + (d == &defaultBackend() ? " (default)" : "");
        backendSections += d->name + " (--method " + d->name + "): " + d->summary +
                           (d->notBuilt.empty() ? "" : " -- " + d->notBuilt) + "\n";
        for (const BackendOption& o : d->options) {
            std::string left = "  " + o.flag + (o.placeholder.empty() ? "" : " " + o.placeholder);
            left += left.size() < 25 ? std::string(25 - left.size(), ' ') : "\n" + std::string(25, ' ');
            backendSections += left + o.help + "\n";
        }
    }
    return R"(hemirad: radiosity with hemisphere (Embree) or hemicube (OpenGL) form factors and sparse solvers

usage: hemirad COMMAND INPUT [options]

commands:
  formfactors SCENE -o F.hff|F.mtx       compute the form-factor matrix F and store it: the rows of
                                         the patches that reflect (rho > 0; --all-rows: every row)
  solve SCENE -o B.csv|B.ply             compute (or reuse with --ff) F and solve radiosity
  render SCENE -o IMAGE.png              compute, solve and render an image
  thermal SCENE --bc BC.toml -o T.csv    radiative heat transfer: temperatures, fluxes, Gebhart
                                         factors and radiative conductors (docs/thermal.md)
  sky-view SCENE -o SVF.csv              sky view factor per patch: the sky seen directly (every
                                         surface blocks it, front or back) and through mirrors
  sun SCENE -o SUN.csv                   the direct sun per patch: sunlit fraction (exact shadow
                                         polygons) and direct irradiance
  irradiance SCENE --dni W --dhi W -o E.csv   one hour of sun and sky (isotropic, or --sky MODEL):
                                         direct sun, direct sky, reflected, total and absorbed
                                         irradiance per patch
  year SCENE --weather W.epw -o ANNUAL.csv   every hour of a weather file against one F: annual sums
                                         per patch (--hourly H.npy: each hour's total irradiance)
  sensors SCENE --sensors S.csv -o OUT.csv   sensor points (or --grid OBJECT --spacing D): each
                                         point's sky view factor and exact factors to the patches,
                                         straight and through mirrors (--factors F.mtx); with --dni and
                                         the sun, one hour's irradiance (the sun mirrors reflect included)
  info F.hff|F.mtx                       check an F file (or a shard manifest and its shards) and
                                         describe it
  subdivide SCENE -o OUT.obj --max-edge L   split patches until no edge exceeds L
  check SCENE                            diagnose the mesh: T-junctions, coinciding, flipped and sliver
                                         patches, open and non-manifold edges, closed or not; what each
                                         does to F (exit 1 only where F would be meaningless)
  bench SCENE -o RESULTS.csv             time against error over a sweep of methods and sample counts
  help                                   this text

scene: SCENE is an .obj (with the .mtl libraries it names) or an .stl (binary or ASCII: each
  triangle a patch, each ASCII solid an object named by it, a binary file one object named by the
  file; no materials, no units)
  --subdivide L          subdivide patches (edges <= L scene units) before computing
  --materials FILE.mtl   (formfactors, solve, render, subdivide, check, bench) materials by object name:
                         each object (STL solid, OBJ o/g name) takes FILE's material of its name
                         (newmtl NAME), over an OBJ's own; a material named 'default' goes to the
                         objects without a match that have no material; objects left without one,
                         and FILE's names that match no object, are warned
form factors (formfactors, solve, render):
  --method NAME          the form-factor back end: )" + methodNames + R"( (options of each below)
  --max-depth D          mirror reflections followed (default 8)
  --all-rows             also compute rows of black patches (rho = 0; skipped by default: B = E
                         there, and F marks their rows as not computed)
  --enforce-reciprocity  make A_i F_ij = A_j F_ji keeping each row's sum (1 in a closed scene)
  --drop-below EPS       (formfactors, solve, render) drop the pairs whose F_ij and F_ji are both
                         below EPS (at most 5 % of a row; never a pair with an emitting patch) and
                         rebalance: reciprocal, rows keep their sums
  --normalize-rows       rescale every row to sum 1 (closed scenes without mirrors; after reciprocity)
  --no-memory-check      compute F even when its estimated size exceeds the available memory
  --ff FILE              (solve, render, thermal, irradiance, year) reuse F from FILE when its scene
                         hash and form-factor settings match (a file made with other settings is
                         refused, naming them); create FILE when it does not exist (stored
                         post-processed; a reuse applies only the post-processing the file does not
                         record)
  --recompute-ff         (the same commands) recompute F and overwrite FILE
  --reuse-ff-anyway      (the same commands) reuse FILE although it was made with other settings
                         (--method, its options, --max-depth): the difference is warned
  --shards               store F as shard files (one per MPI rank, one in one process), each
                         written by its rank alone, plus a small manifest at the F path that
                         info, solve --ff and the GUI read (an F larger than one machine's memory)
)" + backendSections + R"(solve (solve, render):
  --solver NAME          )" + solverNames() + R"( (auto: lu up to 2000 patches, else sor on up
                         to 2 threads, jacobi with parallel sweeps on more)
  --tolerance T          relative residual to reach (default 1e-6)
  --max-iterations N     iteration limit (default 100000)
  --allow-unconverged    report an unconverged solve instead of failing
  --crease DEG           crease angle for vertex radiosity (default 45)
  --exposure X           display scale for PNG/PLY colours (default automatic)
  --objects T.csv        (solve) per object: patches, area, and radiosity B and irradiance
                         H = (B - E)/rho as luminance Y: area-weighted mean, min and max
  --sky-view             (solve) also each patch's sky view factor (as sky-view's: direct + through
                         mirrors, 0..1): a sky_view_factor column in B.csv, a float face property
                         sky_view_factor in B.ply; costs a second F, over the scene made two-sided
render:
  --size WxH             image size (default 640x640)
  --camera ex,ey,ez,tx,ty,tz,fov   eye, target, vertical field of view in degrees
  --spp N                samples per pixel (default 4)
  --flat                 flat patches instead of Gouraud shading
  --false-color Q        a false-colour map of Q = radiosity (B), irradiance (H = (B - E)/rho, what a
                         meter on the surface reads) or emission (E), W/m^2 as luminance Y, or
                         sky_view_factor (unitless, as sky-view's; no solve, so no --ff or solver
                         flags), per patch, with a legend (colour bar, values, unit) right of the picture
  --scale linear|log     the map's scale (default linear)
  --range MIN:MAX        the map's range (default: the values' extremes, on a log scale the minimum
                         at least max/1e4 (4 decades); sky_view_factor: 0..1; either side may be empty)
bench:
  --methods LIST         back ends to compare, e.g. )" + methodNames + R"(; a back-end option
                         applies to every listed back end that takes it
  --sweep-samples LIST   --samples values, for back ends that take it (default 96,384,768,1536,3072)
  --sweep-origins LIST   --origins values, for back ends that take it (default 1)
  --sweep-resolutions LIST  --resolution values, for back ends that take it (default 64,128,256)
  --reference-estimator analytic|rays   the reference F: Lambert factors from a Gauss-Legendre rule
                         of K origins over each emitter, shadow rays to random points (default), or rays
  --reference-samples N, --reference-origins K   its directions (rays; mirror chains) and origins
                         (default 4096 x 16, jittered)
  --cache DIR            where reference F and B are kept (default bench/cache)
  --json FILE            also write the results as JSON
  --label NAME           scene name in the results (default: the file name)
thermal (gray surfaces; F through mirrors as for solve; --ff, --solver and the F options apply):
  --tolerance T          (thermal) the iterative solvers' relative residual (default 1e-10)
  --bc FILE.toml         boundary conditions per object (temperature_K, temperature_C, flux_W_m2,
                         power_W or adiabatic), a [default] and the [environment] temperature
  --properties FILE.toml emissivity and specular reflectance per material and object (default:
                         eps = 1 - mean(Kd) - s from the MTL); a specular value there is the one F uses
  --unit m|cm|mm|in|ft   the scene's length unit where the OBJ states none (default m, warned)
  -o T.csv               per patch: area, eps, s, condition, T (K and C), J, H, q (W/m^2), Q (W)
  --objects O.csv        per object: area, T mean/min/max, mean q, Q; the environment's Q
  --conductors FILE      radiative conductors GR_ij = eps_i A_i B_ij (m^2, symmetric) between nodes
                         and the environment: .csv, .mtx, .esatan (GR(a, b) = v;) or .sinda (HEADER
                         CONDUCTOR DATA, -ID, a, b, GR); --conductor-format where the extension is other
  --lump objects|patches the conductor network's nodes (default objects: each isothermal)
  --gebhart auto|columns|dense   how the Gebhart factors are found: a column solve per node over F,
                         or one dense Cholesky inverse over every patch pair (n^3 flops, 8 n^2 bytes;
                         LAPACK from OpenBLAS); auto (default) takes the faster that fits in memory
  --gr-threshold B       drop couplings whose Gebhart factors both ways are below B (default 0: keep
                         all); their number and GR sum are reported
  --exchange Q.csv       net power between objects and to the environment (W), from the solved T
sun:
  --sun-direction x,y,z  toward the sun in the scene's frame; or the sun's place at a time:
  --sun-time T --latitude LAT --longitude LON   T = YYYY-MM-DDTHH:MM[:SS][Z|+HH:MM|-HH:MM] (UTC
                         without an offset), degrees north and east (Michalsky 1988, 0.01 deg, 1950-2050)
  --up z|y               the scene's up axis (default z), --north x,y,z its north (default +y for z
                         up, -z for y up)
  --dni W                direct-normal irradiance (W/m^2) for the direct-irradiance column (sun: and,
                         in a scene with mirrors, a reflected_sun column: their first reflections)
  --glare FILE.csv       (sun) each mirror's reflected sun per receiver: irradiance, peak, lit area
  --dhi W                (irradiance, sensors) diffuse-horizontal irradiance of the sky (W/m^2)
  --sky MODEL            (irradiance, year, sensors) the sky's radiance: isotropic (default: DHI x each patch's
                         exact sky view factor), or a model over the upper hemisphere, scaled to the
                         DHI on a horizontal plane: uniform, cie-overcast (1 + 2 sin(altitude)),
                         cie:1 .. cie:15 (ISO 15469 / CIE S 011 general skies; the sun from --sun-*),
                         perez (Perez 1993 all-weather, from DNI, DHI and the sun); the sky through
                         mirrors too (first reflections). Below the horizon is dark: model the ground
  --svf SVF.csv          (irradiance, year; the isotropic sky) the sky view factors stored in SVF.csv
                         as hemirad sky-view writes them: read where the file exists (each patch's
                         object, area, centroid and normal checked), else computed and stored there
                         for the next run
  --sky-subdivision M    (--sky MODEL) Reinhart's 144 M^2 + 1 sky cells, 1..8 (default 2; 1: Tregenza's 145)
  --sky-samples Q        (--sky MODEL) Q x Q directions per cell, each an exact shadow pass, 1..16
                         (default 1; the error falls about as 1/(cells x Q^2))
  --weather FILE.epw     (year) an EnergyPlus weather file: location, hourly DNI and DHI
  --hourly FILE.npy      (year) the total irradiance of each solved hour and patch (NumPy float64)
  --unit m|cm|mm|in|ft   (irradiance) the scene's length unit where the OBJ states none (powers in W)
sensors:
  --sensors FILE.csv     points with normals, a line each: x,y,z,nx,ny,nz[,name] (a header line and
                         # comments allowed)
  --grid OBJECT          or a grid over OBJECT's faces: --spacing D between points (scene units),
  --height H             lifted H along each face's normal (default 0)
  --factors F.mtx        the sensors x patches factors (Matrix Market, 1-based; row s = sensor s)
  --sensor-estimator E   auto (default): exact while sensors x patches <= 2.5e7, else rays; exact:
                         Lambert's factors to the visible parts (a term per sensor and patch); rays:
                         --sensor-rays N stratified directions per sensor (default 4096; the sky view
                         factor's error about 1e-3 at 4096, falling faster than 1/sqrt(N))
  --sensor-output S.csv  (year, with --sensors or --grid) annual sums per sensor: direct sun, direct
                         sky (with mirrors: the sun and sky they reflect), reflected, total (Wh/m^2)
  --sensor-hourly S.npy  (year) each solved hour's total irradiance per sensor (NumPy float64)
check:
  --sliver-ratio R       a sliver's longest edge / minimum width exceeds R (default 20)
  --relative-tolerance R positions within R x the scene extent are one point (default 1e-6)
  --json FILE            also write the report as JSON (schema in README; - for standard output,
                         the text report then goes to standard error)
output (formfactors, solve, render, bench):
  -o -                   standard output; the report then goes to standard error. Text (.mtx,
                         .csv) always, binary (.hff, .ply, .png) into a pipe or file only, never
                         onto a terminal (and not under mpirun, whose forwarding hides it)
  --format NAME          the format where -o has no extension to tell it (-, a FIFO, a device):
                         formfactors mtx (the default on -) or hff (the default on a device),
                         solve csv (default) or ply, render png; with an extension it must agree
general:
  --threads T            worker threads / GL contexts (default: OMP_NUM_THREADS, else all cores)
  --quiet                print errors and warnings only

exit status: 0 success, 1 runtime error, 2 usage error
)";
}

}  // namespace hemirad
