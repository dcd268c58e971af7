// Sensor points: points with normals where a user wants what a surface there would receive (mean
// radiant temperature, daylight), without a patch of their own. Read from a CSV or laid as a grid
// over an object's faces; each sensor gets its point-to-patch factors (Lambert's exact factor to the
// part of every patch it sees, past every other patch: shadow polygons, no rays), its direct sky
// view factor, and one hour's irradiance from the sun, the isotropic sky and the patches' radiosity.
// Sensors see the scene and are not part of it: they block nothing, not even one another.
#pragma once

#include "engine/math.hpp"
#include "engine/scene.hpp"
#include "environment/sunlit.hpp"
#include "rays/mirror_chain.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hemirad {

struct Sensors {
    std::vector<Vec3> position;
    std::vector<Vec3> normal;  ///< unit
    std::vector<std::string> name;
    std::size_t size() const { return position.size(); }
};

/// Sensors from CSV text: one per line, x,y,z,nx,ny,nz[,name]; lines starting with '#' and empty
/// lines are skipped, and a first line whose first field is not a number is a header. The normal is
/// normalised; a sensor without a name is named by its index. Throws hemirad::Error naming `file`,
/// the line and the value for a field that is not a finite number, a zero normal or a wrong number
/// of fields, and for a file without sensors.
Sensors parseSensorsCsv(const std::string& text, const std::string& file);
/// The same from a file (hemirad::Error when it cannot be read).
Sensors readSensorsCsv(const std::string& path);

/// Whether c lies inside the counter-clockwise convex polygon p (2D), a point on an edge counted for
/// the polygon on one side of it only (the top-left rule of rasterisers; two polygons sharing the
/// edge get exactly opposite signs for it), and not at all on an edge that `open` marks.
bool insideTopLeft(const std::vector<std::array<double, 2>>& p, const std::vector<std::uint8_t>& open,
                   const std::array<double, 2>& c);

/// A grid over the faces of `object`: on each of its patches, the points of a square lattice of
/// `spacing` in the patch's plane (axes from its normal, lattice offset half a spacing from the
/// origin, so a horizontal face's grid runs along x and y) that lie inside it, each lifted `height`
/// along the normal and facing it. A point on an edge two of its patches share belongs to one of
/// them; one on the object's boundary (an edge of one patch only: a ground's edge at a wall's foot)
/// to none. Named OBJECT:PATCH:K. Throws hemirad::Error for an unknown object, a spacing that is not
/// > 0, a height that is not finite, or more than `limit` points.
Sensors sensorGrid(const Scene& scene, const std::string& object, double spacing, double height,
                   std::size_t limit = 10000000);

/// Sensors x patches, CSR: F[s][j] the factor from sensor s to the part of patch j's front that it
/// sees (0 where it sees j's back or nothing of it), straight and through the scene's mirrors
/// (weighted by the product of the s met: Sillion & Puech's extended factors), and each sensor's
/// direct sky view factor: 1 less the factors to every patch it sees straight, front or back (every
/// surface blocks the sky), and the sky it sees in mirrors.
struct SensorFactors {
    std::vector<std::uint64_t> rowStart;  ///< sensors + 1
    std::vector<PatchId> columns;
    std::vector<double> values;
    std::vector<double> skyView;
    /// Per sensor: the sky seen through mirrors, weighted by the s met (empty where the scene has no
    /// mirror or they were not followed).
    std::vector<double> skyMirrored;
    /// How the mirrors were treated, for the report: empty without mirrors, else what was followed
    /// or why not.
    std::string mirrors;
    double cutoffWeight = 0.0;  ///< summed over the sensors: what chains past the limits carry (counted as sky)
    std::size_t patches = 0;
    std::uint64_t terms = 0;  ///< sensor-patch terms whose visible part was computed (the work)
    std::uint64_t rays = 0;   ///< rays cast (the ray estimator's work; 0 for the exact factors)
};

/// The factors of every sensor. Exact for convex planar patches (as the analytic estimator's exact
/// terms): each term is Lambert's factor to what the blockers leave of the patch's part above the
/// sensor's plane; a patch whose plane holds the sensor (within 1e-12 of the extent) is seen edge-on
/// and counts for nothing. Through mirrors (planar, convex, as the analytic estimator's image terms;
/// environment/sensor_mirrors.hpp) to `limits`, with shadow rays along the reflected paths: a build
/// without ray casting, or mirrors that are not planar and convex, leave them out and say so in
/// `mirrors`. Sensors run in parallel on `threads` threads (0: every core). The work is a term per
/// sensor and patch above its plane (a few microseconds each): a large grid against a large scene
/// takes the ray estimator.
SensorFactors sensorFactors(const Scene& scene, const Sensors& sensors, int threads = 0,
                            const MirrorChainLimits& limits = MirrorChainLimits());

/// How the sensors' factors are computed: exactly (sensorFactors), by rays (sensorFactorsByRays),
/// or `Auto`: exact while sensors x patches stays within kExactSensorTerms, else rays.
enum class SensorEstimator { Auto, Exact, Rays };
/// "auto", "exact" or "rays"; hemirad::Error naming the value otherwise.
SensorEstimator parseSensorEstimator(const std::string& text);
struct SensorOptions {
    SensorEstimator estimator = SensorEstimator::Auto;
    std::uint32_t rays = 4096;  ///< per sensor (the ray estimator), >= 1
    int threads = 0;            ///< 0: every core
    MirrorChainLimits limits;   ///< chains of mirrors: --max-depth, --min-weight
};
/// Auto's budget of sensor-patch terms for the exact factors (about a minute on 2 cores).
constexpr double kExactSensorTerms = 2.5e7;
/// The estimator `options` picks for this many sensors and patches, and why (for the report).
SensorEstimator chooseSensorEstimator(const SensorOptions& options, std::size_t sensors, std::size_t patches,
                                      std::string& why);
/// The sensors' factors by the chosen estimator; `why` (optional) receives chooseSensorEstimator's reason.
SensorFactors sensorFactors(const Scene& scene, const Sensors& sensors, const SensorOptions& options,
                            std::string* why = nullptr);

/// The factors by rays (Embree): from each sensor, lifted off its plane, `rays` directions, one
/// jittered in each cell of Beckers & Beckers' partition of the hemisphere into cells of equal
/// projected solid angle (each carries 1 / rays of the factor), drawn from a generator seeded by
/// the sensor's index (the same factors on any number of threads). F[s][j] is the share of the
/// rays that meet patch j's front first, the sky view factor the share that meets nothing; the
/// rays that meet a back face count for neither. Each sensor's direct row, its back faces and its
/// sky share sum to 1 exactly. A ray that meets a mirror's front goes on reflected with the s met
/// (rays/mirror_chain.hpp) to `limits`: each patch front it meets adds that weight, and a miss adds
/// it to skyMirrored (so does a chain cut off at the limits, as the exact factors count it). Stratified, unbiased, with an error that falls faster than 1 / sqrt(rays)
/// (about 1e-3 on a sky view factor at 4096 rays; README). Throws hemirad::Error in a build without
/// Embree (rayCastingNotBuilt()) and for rays = 0.
SensorFactors sensorFactorsByRays(const Scene& scene, const Sensors& sensors, std::uint32_t rays, int threads = 0,
                                  const MirrorChainLimits& limits = MirrorChainLimits());

/// Per sensor, 1 where the sun (direction `toSun`, any length > 0) reaches the point past every
/// patch (front or back), else 0; 0 where the sensor faces away from it. Throws hemirad::Error for a
/// direction that is zero or not finite.
std::vector<double> sensorSunlit(const Scene& scene, const Sensors& sensors, const Vec3& toSun);
/// The same with the scene's shadow set-up kept for many suns: each sensor's ray searched in its tree.
std::vector<double> sensorSunlit(const BeamShadows& beams, const Sensors& sensors, const Vec3& toSun);

/// One hour at the sensors, W/m^2: direct sun DNI cos(theta) x sunlit, direct sky DHI x sky view
/// factor (isotropic), the sun reflected by mirrors (`reflectedSun`, SensorReflections::sun, or
/// empty), the sky seen in mirrors (DHI x skyMirrored), reflected sum_j F[s][j] J_j from the
/// patches' diffuse radiosity J (e.g. IrradianceResult::radiosity; seen straight and in mirrors),
/// and their total.
/// With `modelSky` (a sky model's hour at the sensors, environment/sensor_sky.hpp), its direct sky
/// and the sky its mirrors show replace the isotropic sky's (dhi is then not used).
struct SensorIrradiance {
    std::vector<double> directSun, directSky, reflectedSun, reflectedSky, reflected, total;
};
/// A sky model's hour at the sensors, W/m^2: the direct sky and the sky seen by way of mirrors
/// (empty without mirrors).
struct SensorSky {
    std::vector<double> direct, mirrored;
};
SensorIrradiance sensorIrradiance(const Sensors& sensors, const SensorFactors& factors, const std::vector<double>& sunlit,
                                  const Vec3& toSun, double dni, double dhi, const std::vector<double>& radiosity,
                                  const std::vector<double>& reflectedSun = {}, const SensorSky* modelSky = nullptr);

/// sensor,name,x,y,z,nx,ny,nz,sky_view_factor[,sky_direct,sky_through_mirrors]
/// [,direct_sun,direct_sky[,reflected_sun,reflected_sky],reflected,total (W/m^2)] (CSV, atomic); the
/// bracketed mirror columns where the factors followed mirrors (sky_view_factor is then their sum).
void writeSensorsCsv(const std::string& path, const Sensors& sensors, const SensorFactors& factors,
                     const SensorIrradiance* irradiance);
/// The sensors x patches factors as a Matrix Market coordinate file (1-based, general, atomic).
void writeSensorFactorsMtx(const std::string& path, const SensorFactors& factors);

}  // namespace hemirad
