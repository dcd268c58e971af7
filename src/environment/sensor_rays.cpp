// Sensor points' factors by rays: stratified directions over each sensor's hemisphere (Beckers &
// Beckers' cells of equal projected solid angle), the first patch each meets, for grids too large
// for the exact factors (a term per sensor and patch); and the choice between the two.
#include "engine/error.hpp"
#include "engine/parallel_failure.hpp"
#include "environment/sensors.hpp"
#include "preprocess/hemisphere/beckers.hpp"
#include "preprocess/hemisphere/patch_sampler.hpp"
#include "rays/mirror_chain.hpp"
#include "rays/ray_scene.hpp"

#include <algorithm>
#include <sstream>

#include <omp.h>

namespace hemirad {

SensorEstimator parseSensorEstimator(const std::string& text) {
    if (text == "auto") return SensorEstimator::Auto;
    if (text == "exact") return SensorEstimator::Exact;
    if (text == "rays") return SensorEstimator::Rays;
    throw Error("--sensor-estimator: '" + text + "' is not one of auto, exact, rays");
}

SensorEstimator chooseSensorEstimator(const SensorOptions& options, std::size_t sensors, std::size_t patches,
                                      std::string& why) {
    const double terms = double(sensors) * double(patches);
    std::ostringstream text;
    text.precision(2);
    if (options.estimator != SensorEstimator::Auto) {
        why = options.estimator == SensorEstimator::Exact ? "exact, as asked" : "rays, as asked";
        return options.estimator;
    }
    if (terms <= kExactSensorTerms) {
        text << "auto: exact, " << sensors << " sensors x " << patches << " patches = " << terms
             << " terms at most, within the budget of " << kExactSensorTerms;
        why = text.str();
        return SensorEstimator::Exact;
    }
    if (!rayCastingNotBuilt().empty()) {
        text << "auto: exact, " << terms << " terms (over the budget of " << kExactSensorTerms
             << "), as this build casts no rays";
        why = text.str();
        return SensorEstimator::Exact;
    }
    text << "auto: rays, " << sensors << " sensors x " << patches << " patches = " << terms
         << " terms would exceed the exact factors' budget of " << kExactSensorTerms
         << " (--sensor-estimator exact insists)";
    why = text.str();
    return SensorEstimator::Rays;
}

SensorFactors sensorFactors(const Scene& scene, const Sensors& sensors, const SensorOptions& options, std::string* why) {
    std::string reason;
    const SensorEstimator chosen = chooseSensorEstimator(options, sensors.size(), scene.size(), reason);
    if (why) *why = reason;
    return chosen == SensorEstimator::Rays ? sensorFactorsByRays(scene, sensors, options.rays, options.threads, options.limits)
                                           : sensorFactors(scene, sensors, options.threads, options.limits);
}

namespace {

/// What followMirrorChain counts; a chain that ends in a miss carries its weight to the sky.
struct ChainCounts {
    std::uint64_t bounces = 0, misses = 0, backfaces = 0;
    double lostWeight = 0.0, cutoffWeight = 0.0;
};

}  // namespace

SensorFactors sensorFactorsByRays(const Scene& scene, const Sensors& sensors, std::uint32_t rays, int threads,
                                  const MirrorChainLimits& limits) {
    if (rays == 0 || rays > (1u << 24))
        throw Error("sensor factors: the ray estimator takes 1 to 16777216 rays per sensor, not " + std::to_string(rays));
    if (!rayCastingNotBuilt().empty()) throw Error("sensor factors by rays: " + rayCastingNotBuilt());
    const std::size_t n = scene.size();
    const RayScene cast(scene, threads);
    const std::vector<std::uint32_t> rings = beckersDiskCounts(rays);
    const double lift = cast.originOffset();
    const double share = 1.0 / double(rays);

    SensorFactors out;
    out.patches = n;
    out.skyView.assign(sensors.size(), 1.0);
    out.rowStart.assign(sensors.size() + 1, 0);
    const bool mirrors = scene.hasMirrors();
    if (mirrors) {
        out.mirrors = "followed by rays (reflected at each mirror met)";
        out.skyMirrored.assign(sensors.size(), 0.0);
    }
    double cutoff = 0.0;
    // Sensors in blocks: a block's rows are gathered in parallel, then appended in sensor order, so
    // that only one block's rows wait beside the matrix.
    const std::size_t block = 4096;
    std::vector<std::vector<std::pair<PatchId, double>>> rows(std::min(block, sensors.size()));
    ParallelFailure failure;
    for (std::size_t first = 0; first < sensors.size(); first += block) {
        const std::size_t last = std::min(sensors.size(), first + block);
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads()) reduction(+ : cutoff)
        {
            std::vector<float> local(3 * std::size_t(rays)), dirs(3 * std::size_t(rays)), distances(mirrors ? rays : 0);
            std::vector<PatchId> hits(rays);
            std::vector<double> count(n, 0.0);  // rays (whole, or weighted by the s met through mirrors)
            std::vector<PatchId> touched;
#pragma omp for schedule(dynamic, 16)
            for (std::int64_t ss = std::int64_t(first); ss < std::int64_t(last); ++ss) {
                if (failure.failed()) continue;
                failure.run([&] {
                    const std::size_t s = std::size_t(ss);
                    const Vec3& normal = sensors.normal[s];
                    Vec3 t, b;
                    orthonormalBasis(normal, t, b);
                    Random random(0x5e7502ULL * 0x9e3779b97f4a7c15ULL ^ (std::uint64_t(s) << 20));
                    beckersJitteredDirections(rings, [&] { return random.uniform(); }, local.data());
                    for (std::size_t k = 0; k < rays; ++k) {
                        const Vec3 d = double(local[3 * k]) * t + double(local[3 * k + 1]) * b + double(local[3 * k + 2]) * normal;
                        for (int c = 0; c < 3; ++c) dirs[3 * k + std::size_t(c)] = float(d[c]);
                    }
                    float origin[3];
                    cast.toLocal(sensors.position[s] + lift * normal, origin);
                    // A surface through the sensor (a wall it stands in) is seen edge-on, as by the
                    // exact factors: its hit at the origin is passed over.
                    cast.intersectFan(origin, dirs.data(), rays, hits.data(), mirrors ? distances.data() : nullptr, float(2.0 * lift));
                    std::uint32_t sky = 0;
                    ChainCounts chains;
                    double skyMirrored = 0.0;
                    touched.clear();
                    for (std::size_t k = 0; k < rays; ++k) {
                        const PatchId j = hits[k];
                        if (j == RayScene::kNoHit) {
                            ++sky;
                            continue;
                        }
                        const Vec3& nj = scene.patches[j].normal;
                        const double facing =
                            nj.x() * dirs[3 * k] + nj.y() * dirs[3 * k + 1] + nj.z() * dirs[3 * k + 2];
                        if (!(facing < 0.0)) continue;  // its back: hides the sky, receives nothing
                        if (count[j] == 0.0) touched.push_back(j);
                        count[j] += 1.0;
                        if (scene.patches[j].specular <= 0.0) continue;
                        // A mirror's front: the ray goes on, reflected, with the s met.
                        const std::uint64_t misses = chains.misses;
                        const double lost = chains.lostWeight, cut = chains.cutoffWeight;
                        const Vec3 d(dirs[3 * k], dirs[3 * k + 1], dirs[3 * k + 2]);
                        followMirrorChain(scene, cast, sensors.position[s] + lift * normal, d, j, distances[k], 1.0, 1.0, limits,
                                          [&](PatchId r, double weight) {
                                              if (count[r] == 0.0) touched.push_back(r);
                                              count[r] += weight;
                                          },
                                          chains);
                        // A miss reaches the sky; so is counted what a chain past the limits carries
                        // (as the exact factors and the patches' sky view factors count it).
                        if (chains.misses != misses) skyMirrored += chains.lostWeight - lost;
                        skyMirrored += chains.cutoffWeight - cut;
                    }
                    std::sort(touched.begin(), touched.end());
                    auto& row = rows[s - first];
                    row.clear();
                    for (const PatchId j : touched) {
                        row.emplace_back(j, count[j]);
                        count[j] = 0.0;
                    }
                    out.skyView[s] = double(sky) * share;
                    if (mirrors) {
                        out.skyMirrored[s] = skyMirrored * share;
                        cutoff += chains.cutoffWeight * share;
                    }
                });
            }
        }
        failure.rethrowIfFailed();
        for (std::size_t s = first; s < last; ++s) {
            const auto& row = rows[s - first];
            out.rowStart[s + 1] = out.rowStart[s] + row.size();
            for (const auto& [j, hitsOfJ] : row) {
                out.columns.push_back(j);
                out.values.push_back(double(hitsOfJ) * share);
            }
        }
    }
    out.rays = std::uint64_t(sensors.size()) * rays;
    out.cutoffWeight = cutoff;
    return out;
}

}  // namespace hemirad
