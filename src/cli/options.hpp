// Command-line options of `hemirad`: one Options struct, strict parsing, usage text.
#pragma once

#include "engine/error.hpp"
#include "engine/scene.hpp"
#include "environment/sensors.hpp"
#include "solve/solver.hpp"
#include "preprocess/backend_registry.hpp"
#include "render/false_colour.hpp"

#include <optional>
#include <string>
#include <vector>

namespace hemirad {

/// A command-line mistake: main() prints it with the usage hint and exits with status 2.
class UsageError : public Error {
public:
    explicit UsageError(const std::string& message) : Error(message) {}
};

/// Every field also goes into optionsHash(), by which the ranks of an MPI job check that they agree.
struct Options {
    std::string command;                 ///< formfactors, solve, render, thermal, info, subdivide, check, bench, help
    std::vector<std::string> inputs;     ///< positional arguments
    std::string output;                  ///< -o ("-": standard output)
    std::string format;                  ///< --format: for an -o without an extension to tell it
    bool quiet = false;

    // Scene.
    double subdivide = 0.0;              ///< --subdivide L: max edge length, 0 = off
    std::string materials;               ///< --materials FILE.mtl: materials by object name ("" = none)

    // Form factors: --method and its back end's options (flags from the back-end registry).
    MethodSettings formFactors;
    bool allRows = false;
    bool enforceReciprocity = false;
    double dropBelow = 0.0;  ///< --drop-below EPS (0: keep every pair)
    bool normalizeRows = false;
    bool memoryCheck = true;             ///< --no-memory-check turns the F memory estimate off
    std::string ffPath;                  ///< --ff: stored F to reuse (or to create)
    std::string skyViewPath;             ///< --svf: stored sky view factors to reuse (or to create)
    bool recomputeFf = false;
    bool reuseFfAnyway = false;          ///< --reuse-ff-anyway: --ff FILE made with other settings is reused
    bool shards = false;                 ///< --shards: F stored as shard files + manifest (one shard per rank)

    // Solve and output.
    SolverOptions solver;
    double crease = 45.0;

    // Render.
    int width = 640, height = 640;
    std::optional<Camera> camera;
    int samplesPerPixel = 4;
    double exposure = 0.0;               ///< 0 = automatic
    bool flat = false;
    std::string objectsPath;             ///< solve --objects: the per-object table (CSV)
    bool skyView = false;                ///< solve --svf: a sky_view_factor column (CSV) or face property (PLY)
    std::optional<FalseColourQuantity> falseColour;  ///< --false-color (none: a picture)
    FalseColourScale falseColourScale = FalseColourScale::Linear;  ///< --scale
    std::optional<double> rangeMin, rangeMax;  ///< --range MIN:MAX (either may be empty: automatic)

    // thermal command (src/thermal, docs/thermal.md).
    std::string propertiesPath;          ///< --properties FILE.toml ("": eps = 1 - mean(Kd) - s from the MTL)
    std::string conditionsPath;          ///< --bc FILE.toml: boundary conditions and the environment
    std::string conductorsPath;          ///< --conductors FILE: radiative conductors GR
    std::string conductorFormat;         ///< --conductor-format csv|mtx|esatan|sinda ("": the extension's)
    std::string lumping = "objects";     ///< --lump objects|patches: the conductor network's nodes
    std::string gebhartMethod = "auto";  ///< --gebhart auto|columns|dense: how the Gebhart factors are found
    double couplingThreshold = 0.0;      ///< --gr-threshold B: couplings with both Gebhart factors below B dropped
    std::string exchangePath;            ///< --exchange FILE.csv: net power between objects
    std::string lengthUnit;              ///< --unit: the scene's length unit where the OBJ states none

    // sun command (src/environment).
    std::optional<Vec3> sunDirectionVector;  ///< --sun-direction x,y,z: toward the sun, scene frame
    std::string sunTime;                 ///< --sun-time YYYY-MM-DDTHH:MM[:SS][Z|+HH:MM]
    std::optional<double> latitude, longitude;  ///< --latitude, --longitude (degrees, north and east positive)
    std::string upAxis = "z";            ///< --up z|y
    std::optional<Vec3> north;           ///< --north x,y,z (default +y for z up, -z for y up)
    std::optional<double> dni;           ///< --dni W/m^2: direct-normal irradiance
    double dhi = 0.0;                    ///< --dhi W/m^2: diffuse-horizontal irradiance (irradiance command)
    std::string weatherPath;             ///< year --weather FILE.epw
    std::string hourlyPath;              ///< year --hourly FILE.npy: total irradiance per hour and patch
    std::string sensorsPath;             ///< sensors --sensors FILE.csv: x,y,z,nx,ny,nz[,name] per line
    std::string gridObject;              ///< sensors --grid OBJECT: a grid over the object's faces
    double gridSpacing = 0.0;            ///< --spacing D (scene units)
    double gridHeight = 0.0;             ///< --height H above the faces (scene units)
    std::string sensorFactorsPath;       ///< sensors --factors F.mtx: sensors x patches
    SensorOptions sensorFactors;         ///< --sensor-estimator auto|exact|rays, --sensor-rays N (threads: --threads)
    std::string sensorOutputPath;        ///< year --sensor-output FILE.csv: annual sums per sensor
    std::string glarePath;               ///< sun --glare FILE.csv: the sun reflected by mirrors, per (mirror, receiver)
    std::string sensorHourlyPath;        ///< year --sensor-hourly FILE.npy: hours x sensors, W/m^2
    std::string skyModel = "isotropic";  ///< --sky: isotropic (DHI x sky view factor) or a model (environment/sky_model.hpp)
    int skySubdivision = 2;              ///< --sky-subdivision M: Reinhart's 144 M^2 + 1 cells (1: Tregenza's 145)
    int skySamples = 1;                  ///< --sky-samples Q: Q x Q directions per cell

    // subdivide command.
    double maxEdge = 0.0;

    // check command (the mesh diagnosis).
    double sliverRatio = 20.0;           ///< --sliver-ratio: longest edge / minimum width above which a patch is a sliver
    double relativeTolerance = 1e-6;     ///< --relative-tolerance: welding distance as a fraction of the scene extent

    // bench command: the sweep and its reference.
    /// bench: one settings per --methods entry; back-end flags go to every method that takes them.
    std::vector<MethodSettings> benchMethods;
    std::vector<std::uint32_t> sweepSamples = {96, 384, 768, 1536, 3072};
    std::vector<std::uint32_t> sweepOrigins = {1};
    std::vector<std::uint32_t> sweepResolutions = {64, 128, 256};
    std::uint32_t referenceSamples = 4096, referenceOrigins = 16;
    std::string referenceEstimator = "analytic";  ///< "analytic" (Lambert, jittered visibility) or "rays" (jittered)
    std::string cacheDir = "bench/cache";
    std::string jsonPath;
    std::string label;
    // bench-run (one measurement, run by bench in a child process).
    std::string referencePath, referenceRadiosityPath;
};

/// Parses argv; throws UsageError for unknown commands/flags, missing or malformed values.
Options parseOptions(int argc, const char* const* argv);

/// The format -o is written in ("mtx", "hff", "csv", "ply", "png"): the extension's; for standard
/// output ("-"), a FIFO or a device, --format's or the command's default (text on standard output).
/// Throws UsageError for an unknown extension or a --format that contradicts it.
std::string outputFormat(const Options& options);

/// Whether outputFormat(options) is binary (hff, ply, png), not text (mtx, csv); false for a command
/// without formats (bench writes CSV).
bool outputIsBinary(const Options& options);

/// A hash of every parsed option but the thread count (each rank's own machine may set that): the
/// ranks of an MPI job must agree on it, or one of them would compute or solve something else.
std::uint64_t optionsHash(const Options& options);

/// Whether standard output carries a result (-o -, --json -), so that the report goes to stderr.
bool reportsToStandardError(const Options& options);

/// The full usage text (`hemirad help`).
std::string usageText();

}  // namespace hemirad
