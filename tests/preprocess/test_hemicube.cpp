// Hemicube back end on Mesa's software OpenGL: delta form factors, closed forms, agreement with the
// hemisphere back end, parent-polygon vs per-patch drawing, CPU vs GPU reduction, context errors.
// These tests need a GL 4.5 context and fail (never skip) without one.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "engine/subdivide.hpp"
#include "gl/gl_api.hpp"
#include "gl/gl_context.hpp"
#include "preprocess/backend_registry.hpp"
#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "preprocess/hemicube/hemicube_options.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"

#include <doctest/doctest.h>

#include <cstdlib>
#include <sys/wait.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

FormFactorRun hemicube(const Scene& s, std::uint32_t resolution, Reduction reduce = Reduction::Cpu,
                       bool parents = true) {
    HemicubeOptions o;
    o.resolution = resolution;
    o.reduce = reduce;
    o.parentPolygons = parents;
    return computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
}

/// Mean over rows of sum_j |A_ij - B_ij|.
double meanRowL1(const FormFactors& A, const FormFactors& B) {
    double total = 0.0;
    for (std::size_t i = 0; i < A.size(); ++i) {
        double row = 0.0;
        for (std::uint64_t k = A.rowBegin(i); k < A.rowEnd(i); ++k)
            row += std::abs(A.values()[k] - B.at(i, A.columns()[k]));
        for (std::uint64_t k = B.rowBegin(i); k < B.rowEnd(i); ++k)
            if (A.at(i, B.columns()[k]) == 0.0) row += B.values()[k];
        total += row;
    }
    return total / double(A.size());
}

}  // namespace

TEST_CASE("Delta form factors: the shares of physics.md and the midpoint overshoot") {
    for (std::uint32_t R : {64u, 256u}) {
        const HemicubeLayout layout(R);
        CHECK(layout.width() == 3 * R);
        // The overshoot is ~1e-4: compare it as a ratio (Approx's default scale of 1 would accept anything).
        CHECK((layout.rawSum() - 1.0) * double(R) * R == doctest::Approx(0.54).epsilon(0.05));
        double sum = 0.0;
        for (float w : layout.weights()) sum += w;
        CHECK(sum == doctest::Approx(1.0).epsilon(1e-6));
        CHECK(layout.faceShare(HemicubeLayout::Top) == doctest::Approx(0.55412642).epsilon(1e-3));
        for (int f = 1; f < 5; ++f) CHECK(layout.faceShare(f) == doctest::Approx(0.11146839).epsilon(1e-3));
    }
    CHECK_THROWS_WITH_AS(HemicubeLayout(127), doctest::Contains("must be an even number"), Error);
}

TEST_CASE("A headless GL 4.5 core context exists (EGL on Mesa here)") {
    auto context = createHeadlessContext(GlApiKind::Egl);
    context->makeCurrent();
    GLint major = 0, minor = 0;
    gl::GetIntegerv(GL_MAJOR_VERSION, &major);
    gl::GetIntegerv(GL_MINOR_VERSION, &minor);
    CHECK(major * 10 + minor >= 45);
    CHECK(gl::describeContext().find("Core Profile") != std::string::npos);
    context->release();
}

TEST_CASE("Parallel plates from the centroid: the point-to-area factor 4 B3(1/2, 1/2, 1)") {
    // The hemicube sits at the centroid: it measures the factor of that point (physics.md §1 note).
    const double A = 0.5, B = 0.5, a = A / std::sqrt(1 + A * A), b = B / std::sqrt(1 + B * B);
    const double point = 4.0 / (2 * kPi) * (a * std::atan(B / std::sqrt(1 + A * A)) + b * std::atan(A / std::sqrt(1 + B * B)));
    const FormFactorRun r = hemicube(bundledScene("parallel_plates.obj"), 256);
    CHECK(r.F.at(0, 1) == doctest::Approx(point).epsilon(2e-3));
    CHECK(r.F.at(1, 0) == doctest::Approx(point).epsilon(2e-3));
}

TEST_CASE("Subdivided closed cube: rows sum to 1 and face-to-face factors match the closed forms") {
    const Scene s = subdivide(unitCube(), 0.125);  // 8 x 8 patches per face
    const FormFactorRun r = hemicube(s, 128);
    CHECK(r.counts.misses == 0);
    CHECK(r.stats.rowSumMin == doctest::Approx(1.0).epsilon(1e-5));
    CHECK(r.stats.rowSumMax == doctest::Approx(1.0).epsilon(1e-5));
    // Area-weighted sums over each face's patches give the face-to-face factors.
    const std::size_t per = s.size() / 6;
    for (std::size_t a = 0; a < 6; ++a)
        for (std::size_t b = 0; b < 6; ++b) {
            if (a == b) continue;
            double sum = 0.0;
            for (std::size_t i = a * per; i < (a + 1) * per; ++i)
                for (std::size_t j = b * per; j < (b + 1) * per; ++j) sum += r.F.at(i, j);
            const double expected = (a ^ 1) == b ? kCubeOpposite : kCubeAdjacent;
            CHECK(sum / double(per) == doctest::Approx(expected).epsilon(5e-3));
        }
}

TEST_CASE("Hemicube and hemisphere converge to the same F on the Cornell box") {
    const Scene s = subdivide(bundledScene("cornell_box.obj"), 100.0);
    const FormFactorRun cube = hemicube(s, 128);
    HemisphereOptions o;
    o.estimator = Estimator::Rays;  // centroid estimates like the hemicube's (analytic integrates near pairs over the emitter)
    o.samples = 3072;
    const FormFactorRun coarse = computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
    o.samples = 49152;  // about the hemicube's pixel count
    const FormFactorRun fine = computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
    const double coarseL1 = meanRowL1(cube.F, coarse.F), fineL1 = meanRowL1(cube.F, fine.F);
    MESSAGE("mean per-row sum |F_hemicube - F_hemisphere|: 3072 rays ", coarseL1, ", 49152 rays ", fineL1);
    // Both estimate the centroid-to-patch factors; the gap is the hemisphere's sampling noise
    // (~1/sqrt(rays)) plus the hemicube's pixel aliasing.
    CHECK(fineL1 < 0.04);
    CHECK(fineL1 < 0.5 * coarseL1);
    for (PatchId i = 0; i < s.size(); ++i) CHECK(cube.F.rowSum(i) == doctest::Approx(fine.F.rowSum(i)).epsilon(3e-3));
}

TEST_CASE("Drawing subdivided parents whole gives the F of drawing every patch") {
    const Scene s = subdivide(bundledScene("cornell_box.obj"), 60.0);
    const FormFactorRun whole = hemicube(s, 128, Reduction::Cpu, true);
    const FormFactorRun each = hemicube(s, 128, Reduction::Cpu, false);
    // Only pixels whose centres lie exactly on an edge may differ: between sibling patches (which
    // one gets it), and on outer edges (a big triangle's edge and a row of small ones rasterise the
    // same line, but ties on it can fall either way).
    CHECK(meanRowL1(whole.F, each.F) < 1e-3);
    for (PatchId i = 0; i < s.size(); ++i) CHECK(whole.F.rowSum(i) == doctest::Approx(each.F.rowSum(i)).epsilon(2e-4));
    CHECK(whole.F.parameters.at("parent_polygons") == "yes");
    CHECK(each.F.parameters.at("parent_polygons") == "no");
}

TEST_CASE("Triangle and general-quad parents find their patches too") {
    SceneBuilder b;
    b.rectangle(2, 0, 0, 2, 0, 2, true);  // floor, emitter side
    b.polygon({Vec3(0, 0, 1), Vec3(0, 2, 1), Vec3(2, 0, 1)});                   // triangle ceiling, facing down
    b.polygon({Vec3(2.5, 0, 0), Vec3(2.5, 0, 1), Vec3(2.5, 3, 1.5), Vec3(2.5, 2, 0)});  // trapezoid wall facing -x
    const Scene s = subdivide(b.scene, 0.3);
    const FormFactorRun whole = hemicube(s, 128, Reduction::Cpu, true);
    const FormFactorRun each = hemicube(s, 128, Reduction::Cpu, false);
    CHECK(meanRowL1(whole.F, each.F) < 2e-3);
}

TEST_CASE("CPU and GPU reduction give the same F") {
    const Scene s = subdivide(bundledScene("cornell_box.obj"), 100.0);
    const FormFactorRun cpu = hemicube(s, 64, Reduction::Cpu);
    const FormFactorRun gpu = hemicube(s, 64, Reduction::Gpu);
    // The GPU sums in 2^-31 fixed point: a row differs by at most one unit per pixel.
    CHECK(meanRowL1(cpu.F, gpu.F) < 1e-5);
    CHECK(gpu.counts.misses == cpu.counts.misses);
}

TEST_CASE("GPU reduction counts pixels below one fixed-point unit as lost power instead of dropping them") {
    // The GPU adds pixels in units of 2^-31 of a row. At R = 4096 the lowest rows of the side faces
    // carry less than half a unit each; in the closed cube nothing is missed, so all that is lost is
    // exactly their weight.
    const std::uint32_t R = 4096;
    const HemicubeLayout layout(R);
    double below = 0.0;
    for (float w : layout.weights())
        if (double(w) * 2147483648.0 < 0.5) below += w;
    REQUIRE(below > 1e-6);
    HemicubeOptions o;
    o.resolution = R;
    o.reduce = Reduction::Gpu;
    CommonOptions one;
    one.threads = 1;
    const FormFactorRun r = computeFormFactors(unitCube(), MethodSettings::of(o, one), {0});
    CHECK(r.counts.misses == 0);
    CHECK(r.counts.backfaces == 0);
    CHECK(r.counts.lostWeight == doctest::Approx(below).epsilon(1e-3));
}

TEST_CASE("A failing GL context is a clear error, and auto falls back to OSMesa") {
    const std::string scene = sourcePath("scenes/unit_cube.obj");
    const auto dir = tempDir("gl-context");
    const std::string run = std::string(HEMIRAD_BINARY) + " formfactors " + scene + " -o " + (dir / "F.hff").string() +
                            " --method hemicube --resolution 16 --quiet";
    const std::string log = (dir / "run.log").string();
    auto status = [&](const std::string& env, const std::string& gl) {
        const int s = std::system((env + " " + run + " --gl " + gl + " > " + log + " 2>&1").c_str());
        return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
    };
    auto output = [&] {
        std::ifstream in(log);
        return std::string((std::istreambuf_iterator<char>(in)), {});
    };
    CHECK(status("__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json", "egl") == 1);
    CHECK(output().find("EGL: no surfaceless Mesa display") != std::string::npos);
    CHECK(status("MESA_GL_VERSION_OVERRIDE=3.3", "egl") == 1);
    CHECK(output().find("cannot create an OpenGL 4.5 core context") != std::string::npos);
    CHECK(status("__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json", "auto") == 0);
    MethodSettings cube = defaultSettings("hemicube");
    CHECK_THROWS_WITH_AS(setBackendOption(cube, "--gl", "vulkan"), doctest::Contains("--gl expects auto, egl or osmesa, got 'vulkan'"),
                         Error);
}

TEST_CASE("Hemicube mirror portals give the image-method factor of physics.md") {
    const Scene s = subdivide(bundledScene("mirror_pair.obj"), 0.125);  // P1, P2 and the mirror: 64 patches each
    HemicubeOptions o;
    o.resolution = 128;
    const FormFactorRun r = computeFormFactors(s, MethodSettings::of(o), neededRows(s, false));
    double viaMirror = 0.0;
    for (PatchId i = 0; i < 64; ++i)
        for (PatchId j = 64; j < 128; ++j) viaMirror += r.F.at(i, j) / 64.0;
    CHECK(viaMirror == doctest::Approx(0.9 * (c11(2, 1, 1) - c11(1, 1, 1))).epsilon(2e-3));
    CHECK(r.counts.bounces > 0);  // portal passes ran
    CHECK(r.F.parameters.at("mirrors") == "portals");
}

TEST_CASE("Facing mirrors: portals, ray-traced mirror pixels and the hemisphere agree, depth limit included") {
    SceneBuilder b;
    const std::uint32_t mirror = b.material("mirror", Rgb::Constant(0.05), Rgb::Zero(), 0.9);
    b.rectangle(2, 0, -3, 3, -3, 3, true, mirror);
    b.rectangle(2, 1, -3, 3, -3, 3, false, mirror);
    b.rectangle(2, 0.5, -0.3, 0.3, -0.3, 0.3, false);
    HemicubeOptions o;
    o.resolution = 256;
    CommonOptions depth4;
    depth4.maxDepth = 4;
    const FormFactorRun portals = computeFormFactors(b.scene, MethodSettings::of(o, depth4), neededRows(b.scene, true));
    o.mirrors = HemicubeMirrors::Rays;
    const FormFactorRun rays = computeFormFactors(b.scene, MethodSettings::of(o, depth4), neededRows(b.scene, true));
    HemisphereOptions h;
    h.estimator = Estimator::Rays;
    h.samples = 65536;
    const FormFactorRun sphere = computeFormFactors(b.scene, MethodSettings::of(h, depth4), neededRows(b.scene, true));
    for (PatchId i = 0; i < 3; ++i)
        for (PatchId j = 0; j < 3; ++j) {
            CAPTURE(i);
            CAPTURE(j);
            CHECK(portals.F.at(i, j) == doctest::Approx(rays.F.at(i, j)).epsilon(1e-5));
            CHECK(portals.F.at(i, j) == doctest::Approx(sphere.F.at(i, j)).epsilon(0.02));
        }
    CHECK(portals.counts.cutoffWeight == doctest::Approx(sphere.counts.cutoffWeight).epsilon(0.02));
    CHECK(portals.F.rowSum(0) > 1.0);  // deposits along the chain: extended rows exceed 1
}

TEST_CASE("Without a visible mirror no portal pass runs") {
    const FormFactorRun r = hemicube(subdivide(unitCube(), 0.5), 32);
    CHECK(r.counts.bounces == 0);
    CHECK(r.counts.cutoffWeight == 0.0);
}

TEST_CASE("Each back end takes only its own options: --estimator is refused for the hemicube, unknown values are errors") {
    MethodSettings cube = defaultSettings("hemicube");
    CHECK_THROWS_WITH_AS(setBackendOption(cube, "--estimator", "analytic"),
                         doctest::Contains("option '--estimator' does not apply to --method hemicube (it takes --resolution"),
                         Error);
    MethodSettings sphere = defaultSettings("hemisphere");
    CHECK_THROWS_WITH_AS(setBackendOption(sphere, "--estimator", "exact"),
                         doctest::Contains("--estimator expects auto, rays or analytic, got 'exact'"), Error);
    CHECK_THROWS_WITH_AS(setBackendOption(sphere, "--resolution", "64"),
                         doctest::Contains("option '--resolution' does not apply to --method hemisphere"), Error);
    CHECK_THROWS_WITH_AS(setBackendOption(sphere, "--frobnicate", "1"), doctest::Contains("unknown option '--frobnicate'"),
                         Error);
    // The typed options behind the flags: the wrong type is an internal error, never a silent default.
    CHECK_THROWS_AS(cube.as<HemisphereOptions>(), Error);
}
