// Issue #2 benchmark: hemirad's hemisphere F against a bare rtcIntersect1 loop casting the same rays
// (same BVH build, origins, directions and rotations) that stores nothing; then every iterative solver.
#include "engine/obj_loader.hpp"
#include "solve/solver.hpp"
#include "engine/subdivide.hpp"
#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "preprocess/hemisphere/beckers.hpp"
#include "preprocess/hemisphere/patch_sampler.hpp"

#include <embree3/rtcore.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

using namespace hemirad;
using Clock = std::chrono::steady_clock;

namespace {

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

/// The bare loop: per patch, per origin, per direction one rtcIntersect1; only a hit count survives.
double bareLoop(const Scene& scene, const HemisphereOptions& options, double offset, std::uint64_t& hits, double& buildSeconds) {
    const auto t0 = Clock::now();
    RTCDevice device = rtcNewDevice(nullptr);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    Vec3 lo, hi;
    scene.bounds(lo, hi);
    const Vec3 centre = 0.5 * (lo + hi);
    std::size_t triangles = 0;
    for (const Patch& p : scene.patches) triangles += p.cornerCount - 2;
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          12, scene.vertices.size()));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               12, triangles));
    for (std::size_t k = 0; k < scene.vertices.size(); ++k)
        for (int c = 0; c < 3; ++c) v[3 * k + c] = float(scene.vertices[k][c] - centre[c]);
    std::size_t t = 0;
    for (const Patch& p : scene.patches)
        for (std::uint32_t k = 1; k + 1 < p.cornerCount; ++k, ++t) {
            idx[3 * t] = scene.corners[p.firstCorner];
            idx[3 * t + 1] = scene.corners[p.firstCorner + k];
            idx[3 * t + 2] = scene.corners[p.firstCorner + k + 1];
        }
    rtcCommitGeometry(geometry);
    RTCScene rtc = rtcNewScene(device);
    rtcSetSceneBuildQuality(rtc, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(rtc, RTC_SCENE_FLAG_ROBUST);
    rtcAttachGeometry(rtc, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(rtc);
    const auto t1 = Clock::now();
    buildSeconds = seconds(t0, t1);

    const std::vector<float> dirs = beckersDirections(options.samples);
    std::uint64_t total = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(+ : total)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(scene.size()); ++i) {
        const Patch& patch = scene.patches[i];
        Random random(options.seed * 0x9e3779b97f4a7c15ULL ^ (std::uint64_t(i) << 20));
        const std::vector<Vec3> origins = patchOrigins(scene, PatchId(i), options.origins, random);
        Vec3 tb, bb;
        orthonormalBasis(patch.normal, tb, bb);
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (const Vec3& point : origins) {
            const double angle = 2.0 * kPi * random.uniform();
            const Vec3 tr = std::cos(angle) * tb + std::sin(angle) * bb;
            const Vec3 br = patch.normal.cross(tr);
            const Vec3 o = point + offset * patch.normal - centre;
            for (std::uint32_t k = 0; k < options.samples; ++k) {
                const float* d = &dirs[3 * k];
                RTCRayHit rh;
                rh.ray.org_x = float(o.x());
                rh.ray.org_y = float(o.y());
                rh.ray.org_z = float(o.z());
                rh.ray.dir_x = float(d[0] * tr.x() + d[1] * br.x() + d[2] * patch.normal.x());
                rh.ray.dir_y = float(d[0] * tr.y() + d[1] * br.y() + d[2] * patch.normal.y());
                rh.ray.dir_z = float(d[0] * tr.z() + d[1] * br.z() + d[2] * patch.normal.z());
                rh.ray.tnear = 0.0f;
                rh.ray.tfar = INFINITY;
                rh.ray.mask = 0xffffffffu;
                rh.ray.flags = 0;
                rh.ray.time = 0.0f;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(rtc, &context, &rh);
                total += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        }
    }
    const auto t2 = Clock::now();
    rtcReleaseScene(rtc);
    rtcReleaseDevice(device);
    hits = total;
    return seconds(t1, t2);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_rays SCENE.obj [--subdivide L] [--samples N] [--origins K] [--repeat R] [--rho r,g,b]\n");
        return 2;
    }
    std::string path = argv[1];
    double subdivideLength = 0.0;
    int repeat = 1;
    HemisphereOptions options;
    options.estimator = Estimator::Rays;  // the comparison is ray for ray with the bare loop
    Rgb rho = Rgb::Constant(-1.0);  // keep the scene's reflectances unless --rho is given
    for (int k = 2; k + 1 < argc; k += 2) {
        const std::string flag = argv[k];
        if (flag == "--subdivide") subdivideLength = std::atof(argv[k + 1]);
        else if (flag == "--samples") options.samples = std::uint32_t(std::atoi(argv[k + 1]));
        else if (flag == "--origins") options.origins = std::uint32_t(std::atoi(argv[k + 1]));
        else if (flag == "--repeat") repeat = std::atoi(argv[k + 1]);
        else if (flag == "--rho") {
            if (std::sscanf(argv[k + 1], "%lf,%lf,%lf", &rho[0], &rho[1], &rho[2]) != 3) {
                std::fprintf(stderr, "--rho expects r,g,b\n");
                return 2;
            }
        }
        else {
            std::fprintf(stderr, "unknown option %s\n", flag.c_str());
            return 2;
        }
    }
    try {
        Warnings warnings(nullptr);
        Scene scene = loadObj(path, warnings);
        if (subdivideLength > 0) scene = subdivide(scene, subdivideLength);
        if (rho[0] >= 0.0)
            for (Patch& p : scene.patches) p.rho = rho;
        const std::vector<PatchId> rows = neededRows(scene, true);
        const double rays = double(scene.size()) * options.samples * options.origins;
        std::printf("scene %s: %zu patches, %u directions x %u origins = %.1f M rays, %d threads\n", path.c_str(),
                    scene.size(), options.samples, options.origins, rays / 1e6, omp_get_max_threads());
        double bestBare = 1e300, bestHemirad = 1e300;
        for (int r = 0; r < repeat; ++r) {
            std::uint64_t hits = 0;
            double bareBuild = 0.0;
            // Same offset rule as the adapter: max(1e-6 extent, 64 eps_float half-extent).
            Vec3 lo, hi;
            scene.bounds(lo, hi);
            const double offset = std::max(1e-6 * (hi - lo).norm(), 64.0 * 1.1920929e-7 * 0.5 * (hi - lo).maxCoeff());
            const double bare = bareLoop(scene, options, offset, hits, bareBuild);
            const FormFactorRun run = computeFormFactors(scene, MethodSettings::of(options), rows);
            bestBare = std::min(bestBare, bare);
            bestHemirad = std::min(bestHemirad, run.computeSeconds);
            std::printf("run %d: bare rtcIntersect1 loop %.3f s (%.2f M rays/s, BVH %.3f s, %.4f%% hit)\n", r + 1, bare,
                        rays / bare / 1e6, bareBuild, 100.0 * double(hits) / rays);
            std::printf("run %d: hemirad formfactors  %.3f s (%.2f M rays/s, BVH %.3f s) -> ratio %.3f\n", r + 1,
                        run.computeSeconds, rays / run.computeSeconds / 1e6, run.prepareSeconds, run.computeSeconds / bare);
            std::printf("        F: %zu nonzeros, %.1f MiB (%.2f bytes/nonzero); row sums %.6f..%.6f\n",
                        run.F.nonZeros(), run.F.memoryBytes() / 1048576.0,
                        double(run.F.memoryBytes()) / double(std::max<std::size_t>(1, run.F.nonZeros())),
                        run.stats.rowSumMin, run.stats.rowSumMax);
            if (r + 1 < repeat) continue;
            std::printf("best of %d (runs interleaved): bare %.3f s, hemirad %.3f s -> ratio %.3f\n", repeat, bestBare,
                        bestHemirad, bestHemirad / bestBare);
            for (const std::string kind : {"jacobi", "gauss-seidel", "southwell", "cg", "bicgstab"}) {
                SolverOptions so;
                so.solver = kind;
                so.tolerance = 1e-6;
                so.allowUnconverged = true;
                const auto t0 = Clock::now();
                const Radiosity result = solveRadiosity(scene, run.F, so);
                const double s = seconds(t0, Clock::now());
                int iterations = 0;
                bool converged = true;
                double residual = 0;
                for (const SolveReport& rep : result.reports) {
                    iterations = std::max(iterations, rep.iterations);
                    converged = converged && rep.converged;
                    residual = std::max(residual, rep.residualOriginal);
                }
                std::printf("solve %-13s %.3f s total (%zu distinct channel solves, %d iterations, residual on I-RF %.2e%s)\n",
                            kind.c_str(), s, result.reports.size(), iterations, residual,
                            converged ? "" : ", NOT converged");
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_rays: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
