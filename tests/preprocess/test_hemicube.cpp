// Hemicube back end on Mesa's software OpenGL: delta form factors, closed forms, parent-polygon vs
// per-patch drawing, CPU vs GPU reduction, mirror portals, context errors (the comparisons with the
// hemisphere back end are in test_hemicube_hemisphere.cpp).
// These tests need a GL 4.5 context and fail (never skip) without one.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "engine/subdivide.hpp"
#include "gl/gl_api.hpp"
#include "gl/gl_context.hpp"
#include "preprocess/backend_registry.hpp"
#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemicube/hemicube_backend.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "preprocess/hemicube/hemicube_options.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <future>
#include <mutex>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

using namespace hemirad;
using namespace hemirad::test;

namespace {

FormFactorRun hemicube(const Scene& s, std::uint32_t resolution, Reduction reduce = Reduction::Cpu,
                       bool parents = true, std::uint32_t origins = 1) {
    HemicubeOptions o;
    o.resolution = resolution;
    o.reduce = reduce;
    o.parentPolygons = parents;
    o.origins = origins;
    return computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
}

}  // namespace

TEST_CASE("Delta form factors: the shares of physics.md and the midpoint overshoot") {
    for (std::uint32_t R : {64u, 256u}) {
        const HemicubeLayout layout(R);
        CHECK(layout.width() == 3 * R);
        // The overshoot is ~1e-4: compare it as a ratio (Approx's default scale of 1 would accept anything).
        CHECK((layout.rawSum() - 1.0) * double(R) * R == relative(0.54, 0.05));
        double sum = 0.0;
        for (float w : layout.weights()) sum += w;
        CHECK(sum == relative(1.0, 1e-6));
        CHECK(layout.faceShare(HemicubeLayout::Top) == relative(0.55412642, 1e-3));
        for (int f = 1; f < 5; ++f) CHECK(layout.faceShare(f) == relative(0.11146839, 1e-3));
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
    CHECK(r.F.at(0, 1) == relative(point, 2e-3));
    CHECK(r.F.at(1, 0) == relative(point, 2e-3));
}

TEST_CASE("--origins 16 at R = 256: area-sampled hemicubes meet C-11 and C-14 within 1e-3 (the centroid misses by 0.04)") {
    const Scene parallel = bundledScene("parallel_plates.obj"), perpendicular = bundledScene("perpendicular_plates.obj");
    for (const Reduction reduce : {Reduction::Cpu, Reduction::Gpu}) {
        CAPTURE(int(reduce));
        const FormFactorRun p = hemicube(parallel, 256, reduce, true, 16);
        CHECK(std::abs(p.F.at(0, 1) - c11(1, 1, 1)) < 1e-3);  // measured -9.4e-5
        CHECK(std::abs(p.F.at(1, 0) - c11(1, 1, 1)) < 1e-3);
        const FormFactorRun q = hemicube(perpendicular, 256, reduce, true, 16);
        CHECK(std::abs(q.F.at(0, 1) - c14(1, 2, 1)) < 1e-3);  // measured 2.3e-4
        CHECK(std::abs(q.F.at(1, 0) - c14(2, 1, 1)) < 1e-3);  // measured -3.2e-4
        CHECK(p.F.parameters.at("origins") == "16");
    }
    // The centroid's point factor is what the area rule corrects.
    CHECK(std::abs(hemicube(parallel, 256).F.at(0, 1) - c11(1, 1, 1)) > 0.02);
    CHECK(std::abs(hemicube(perpendicular, 256).F.at(1, 0) - c14(2, 1, 1)) > 0.02);
    // K is rounded up to a square: 5 origins take the 3 x 3 rule.
    CHECK(hemicube(parallel, 16, Reduction::Cpu, true, 5).F.parameters.at("origins") == "9");
}

TEST_CASE("The worker count follows the renderer: one context per core on llvmpipe (taking turns at the driver), one on a GPU, --threads wins") {
    CHECK(isSoftwareRenderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
    CHECK(isSoftwareRenderer("softpipe"));
    CHECK(!isSoftwareRenderer("NVIDIA H100 80GB HBM3/PCIe/SSE2"));
    CHECK(!isSoftwareRenderer("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6, DRM 3.54)"));
    CHECK(hemicubeWorkers("llvmpipe (LLVM 15.0.6, 256 bits)", 0, 16) == 16);
    CHECK(hemicubeWorkers("NVIDIA H100 80GB HBM3/PCIe/SSE2", 0, 16) == 1);
    CHECK(hemicubeWorkers("NVIDIA H100 80GB HBM3/PCIe/SSE2", 3, 16) == 3);
    CHECK(hemicubeWorkers("llvmpipe (LLVM 15.0.6, 256 bits)", 2, 16) == 2);
    CHECK(hemicubeWorkers("llvmpipe", 0, 0) == 1);
    // The run says which renderer it used and why it chose its contexts.
    CommonOptions one;
    one.threads = 1;
    HemicubeOptions o;
    o.resolution = 16;
    const FormFactorRun r = computeFormFactors(unitCube(), MethodSettings::of(o, one), {0});
    CHECK(r.device.find("1 GL context (--threads)") != std::string::npos);
    CHECK(r.device.find("llvmpipe") != std::string::npos);
    CHECK(r.F.parameters.at("gl_renderer").find("llvmpipe") != std::string::npos);
    // llvmpipe's contexts take turns at the driver (Mesa 22.3 crashed now and then with two drawing
    // at once); a GPU's do not, and one context has nobody to take turns with.
    CHECK(hemicubeSerializesContexts("llvmpipe (LLVM 15.0.6, 256 bits)"));
    CHECK(!hemicubeSerializesContexts("NVIDIA H100 80GB HBM3/PCIe/SSE2"));
    CHECK(r.device.find("taking turns") == std::string::npos);
    CommonOptions two;
    two.threads = 2;
    const FormFactorRun r2 = computeFormFactors(unitCube(), MethodSettings::of(o, two), {0, 1});
    CHECK(r2.device.find("2 GL contexts (--threads) taking turns at the driver") != std::string::npos);
    CHECK(r2.F.at(0, 1) == r.F.at(0, 1));  // the same pixels whichever context drew them
}

TEST_CASE("On llvmpipe the turns at the driver are the process's: a computation waits while another holds the driver") {
    // Two computations at once in one process (two Python threads, say) share llvmpipe's screen as one
    // computation's workers do, so they take turns under one lock, not one lock per computation.
    HemicubeOptions o;
    o.resolution = 16;
    CommonOptions two;
    two.threads = 2;
    const FormFactorRun alone = computeFormFactors(unitCube(), MethodSettings::of(o, two), {0, 1});
    REQUIRE(alone.device.find("taking turns at the driver") != std::string::npos);
    std::future<FormFactorRun> waiting;  // declared first: destroyed after the lock is let go
    std::unique_lock<std::mutex> held(sharedDriverMutex());
    waiting = std::async(std::launch::async, [&] {
        return computeFormFactors(unitCube(), MethodSettings::of(o, two), {0, 1});
    });
    // Alone it takes milliseconds; while the driver is held it cannot draw a pixel.
    CHECK(waiting.wait_for(std::chrono::seconds(2)) == std::future_status::timeout);
    held.unlock();
    const FormFactorRun after = waiting.get();
    for (PatchId i : {0u, 1u})
        for (PatchId j = 0; j < 6; ++j) CHECK(after.F.at(i, j) == alone.F.at(i, j));
}

TEST_CASE("Batched hemicubes (one instanced draw into B atlas layers) give the row-by-row F entry by entry") {
    const Scene s = subdivide(bundledScene("cornell_box.obj"), 100.0);  // parents of all kinds of the box
    auto run = [&](Reduction reduce, std::uint32_t batch, std::uint32_t origins) {
        HemicubeOptions o;
        o.resolution = 64;
        o.reduce = reduce;
        o.batch = batch;
        o.origins = origins;
        return computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
    };
    auto maxEntryDifference = [&](const FormFactors& a, const FormFactors& b) {
        double worst = 0.0;
        for (PatchId i = 0; i < s.size(); ++i)
            for (PatchId j = 0; j < s.size(); ++j) worst = std::max(worst, std::abs(a.at(i, j) - b.at(i, j)));
        return worst;
    };
    auto maxRowDifference = [&](const FormFactors& a, const FormFactors& b) {
        double worst = 0.0;
        for (PatchId i = 0; i < s.size(); ++i) {
            double sum = 0.0;
            for (PatchId j = 0; j < s.size(); ++j) sum += std::abs(a.at(i, j) - b.at(i, j));
            worst = std::max(worst, sum);
        }
        return worst;
    };
    // 8 rows per pass; and 4 origins per row in passes of 10 layers (two rows, two layers unused).
    for (const auto& [batch, origins] : {std::pair<std::uint32_t, std::uint32_t>{8, 1}, {10, 4}}) {
        CAPTURE(batch);
        const FormFactorRun rowByRow = run(Reduction::Cpu, 1, origins);
        const FormFactorRun cpu = run(Reduction::Cpu, batch, origins);
        const FormFactorRun gpu = run(Reduction::Gpu, batch, origins);
        const FormFactorRun gpuRowByRow = run(Reduction::Gpu, 1, origins);
        CHECK(cpu.F.parameters.at("batch") == std::to_string(batch));
        CHECK(rowByRow.F.parameters.at("batch") == "1");
        CHECK(maxEntryDifference(rowByRow.F, cpu.F) < 1e-7);
        CHECK(maxEntryDifference(gpuRowByRow.F, gpu.F) < 1e-7);
        // The GPU sums in 2^-31 fixed point: a row differs by at most one unit per pixel.
        CHECK(maxRowDifference(cpu.F, gpu.F) < 1e-6);
        CHECK(cpu.counts.misses == rowByRow.counts.misses);
        CHECK(gpu.counts.misses == rowByRow.counts.misses);
        CHECK(gpu.counts.lostWeight == relative(rowByRow.counts.lostWeight, 1e-6));
        // Each row's loss reaches its row, however rows share a pass: 1 - its row sum (no mirrors), by area.
        double lost = 0.0, area = 0.0;
        for (PatchId i = 0; i < s.size(); ++i) lost += s.patches[i].area * (1.0 - rowByRow.F.rowSum(i)), area += s.patches[i].area;
        CHECK(rowByRow.counts.lostFraction() == relative(lost / area, 1e-4));
        CHECK(cpu.counts.lostFraction() == relative(lost / area, 1e-4));
        CHECK(gpu.counts.lostFraction() == relative(lost / area, 1e-4));
    }
}

TEST_CASE("Hemicubes per pass: by renderer, within the driver's layers and the memory budget, a row's points at least") {
    const char* llvmpipe = "llvmpipe (LLVM 15.0.6, 256 bits)";
    const char* gpu = "NVIDIA H100 80GB HBM3/PCIe/SSE2";
    CHECK(hemicubeLayers(llvmpipe, 0, 128, 13000, false, 1, 2048) == 1);  // measured: batches are slower there
    CHECK(hemicubeLayers(gpu, 0, 128, 13000, false, 1, 2048) == 256);
    CHECK(hemicubeLayers(gpu, 0, 128, 13000, true, 1, 2048) == 256);
    CHECK(hemicubeLayers(gpu, 0, 128, 13000, false, 1, 100) == 100);     // GL_MAX_ARRAY_TEXTURE_LAYERS
    CHECK(hemicubeLayers(gpu, 0, 1024, 13000, false, 1, 2048) == 7);     // 37.7 MB per layer in 256 MiB
    CHECK(hemicubeLayers(gpu, 0, 1024, 13000, false, 16, 2048) == 16);   // but a row's 16 hemicubes fit a pass
    CHECK(hemicubeLayers(gpu, 0, 128, 10000000, true, 1, 2048) == 6);    // the GPU's dense rows for 10M patches
    CHECK(hemicubeLayers(llvmpipe, 8, 128, 13000, false, 1, 2048) == 8); // --batch
    CHECK(hemicubeLayers(gpu, 1, 128, 13000, false, 16, 2048) == 1);     // --batch 1: row by row
    // Three passes in flight keep three read-back copies (CPU reduction) or three pair buffers.
    CHECK(hemicubeLayers(gpu, 0, 1024, 13000, false, 1, 2048, 3) == 4);  // 20 bytes a pixel: 62.9 MB per layer
    CHECK(hemicubeLayers(gpu, 0, 1024, 13000, false, 1, 2048, 3, true) == 3);  // a mirror scene's stencil: 24 bytes
    // The GPU reduction's buffers within the driver's largest storage block (here 128 MiB):
    // 10M patches' dense rows are 40 MB a layer.
    CHECK(hemicubeLayers(gpu, 0, 128, 10000000, true, 1, 2048, 1, false, 134217728.0) == 3);
    CHECK(hemicubeLayers(gpu, 0, 128, 13000, true, 64, 2048, 1, false, 134217728.0) == 256);
    CHECK(hemicubeLayers(gpu, 0, 128, 10000000, true, 16, 2048, 1, false, 134217728.0) == 3);  // points go one by one
    // In a scene with mirrors the rows that may see one go row by row whatever --batch says, and
    // the run says how many: mirror_pair's two plates face the mirror, the mirror sees neither's front.
    HemicubeOptions o;
    o.resolution = 16;
    o.batch = 8;
    const Scene mirrors = bundledScene("mirror_pair.obj");
    CHECK(computeFormFactors(mirrors, MethodSettings::of(o), {0}).F.parameters.at("batch") ==
          "8 (2 of 3 rows may see a mirror: row by row)");
}

TEST_CASE("By renderer: the CPU reduction with one pass in flight and no row threads on llvmpipe and the GPU reduction with three and the spare cores on a GPU") {
    const char* llvmpipe = "llvmpipe (LLVM 15.0.6, 256 bits)";
    const char* gpu = "NVIDIA H100 80GB HBM3/PCIe/SSE2";
    CHECK(hemicubeReduction(llvmpipe, Reduction::Auto) == Reduction::Cpu);
    CHECK(hemicubeReduction(gpu, Reduction::Auto) == Reduction::Gpu);
    CHECK(hemicubeReduction(gpu, Reduction::Cpu) == Reduction::Cpu);
    CHECK(hemicubeReduction(llvmpipe, Reduction::Gpu) == Reduction::Gpu);
    CHECK(hemicubeInFlight(llvmpipe, 0) == 1);
    CHECK(hemicubeInFlight(gpu, 0) == 3);
    CHECK(hemicubeInFlight(gpu, 1) == 1);
    CHECK(hemicubeInFlight(llvmpipe, 2) == 2);
    // Row threads: none beside llvmpipe's context per core; on a GPU the cores its context leaves.
    CHECK(hemicubeRowThreads(llvmpipe, -1, 16, 16) == 0);
    CHECK(hemicubeRowThreads(gpu, -1, 16, 1) == 15);
    CHECK(hemicubeRowThreads(gpu, -1, 1, 1) == 0);
    CHECK(hemicubeRowThreads(gpu, 0, 16, 1) == 0);
    CHECK(hemicubeRowThreads(llvmpipe, 3, 16, 16) == 3);
    CHECK(hemicubeRowThreads(gpu, -1, 16, 3) == 4);  // --threads 3: the 13 spare cores shared
    // The run reports the resolved choices.
    HemicubeOptions o;
    o.resolution = 16;
    const FormFactorRun r = computeFormFactors(unitCube(), MethodSettings::of(o), {0});
    CHECK(r.F.parameters.at("reduce") == "cpu (by renderer)");
    CHECK(r.F.parameters.at("in_flight") == "1");
    CHECK(r.device.find("1 in flight, reduction on the CPU") != std::string::npos);
    o.reduce = Reduction::Gpu;
    o.inFlight = 2;
    const FormFactorRun g = computeFormFactors(unitCube(), MethodSettings::of(o), {0});
    CHECK(g.F.parameters.at("reduce") == "gpu");
    CHECK(g.F.parameters.at("in_flight") == "2");
}

TEST_CASE("Passes in flight and row threads (rows summed beside the GL thread) give the F of one pass at a time, bit for bit") {
    const Scene s = subdivide(bundledScene("cornell_box.obj"), 100.0);
    auto run = [&](Reduction reduce, std::uint32_t batch, std::uint32_t inFlight, int rowThreads) {
        HemicubeOptions o;
        o.resolution = 32;
        o.reduce = reduce;
        o.batch = batch;
        o.inFlight = inFlight;
        o.rowThreads = rowThreads;
        CommonOptions one;
        one.threads = 1;  // one GL context: the GPU's arrangement
        return computeFormFactors(s, MethodSettings::of(o, one), neededRows(s, true));
    };
    for (const Reduction reduce : {Reduction::Cpu, Reduction::Gpu})
        for (const std::uint32_t batch : {1u, 7u}) {
            CAPTURE(int(reduce));
            CAPTURE(batch);
            const FormFactorRun one = run(reduce, batch, 1, 0);
            for (const auto& [inFlight, rowThreads] : {std::pair<std::uint32_t, int>{3, 0}, {3, 2}, {1, 3}}) {
                CAPTURE(inFlight);
                CAPTURE(rowThreads);
                const FormFactorRun other = run(reduce, batch, inFlight, rowThreads);
                CHECK(other.F.parameters.at("in_flight") == std::to_string(inFlight));
                CHECK(other.F.parameters.at("row_threads") == std::to_string(rowThreads));
                std::size_t differing = 0;
                for (PatchId i = 0; i < s.size(); ++i)
                    for (PatchId j = 0; j < s.size(); ++j) differing += one.F.at(i, j) != other.F.at(i, j);
                CHECK(differing == 0);
                CHECK(other.counts.misses == one.counts.misses);
                CHECK(other.counts.lostWeight == relative(one.counts.lostWeight, 1e-12));
                CHECK(other.counts.lostFraction() == relative(one.counts.lostFraction(), 1e-9));  // per row
                CHECK(other.counts.rays == one.counts.rays);
            }
        }
}

TEST_CASE("In a mirror scene, rows that cannot see a mirror are batched and give the row-by-row F, and rows that can keep their portals") {
    // The mirror Cornell box: the mirror's own wall, the back of its blocks and the like cannot see it.
    const Scene s = subdivide(bundledScene("cornell_mirror.obj"), 120.0);
    const std::vector<bool> maySee = rowsThatMaySeeMirrors(s, HemicubeGeometry::build(s, true).extent);
    const auto batched = std::size_t(std::count(maySee.begin(), maySee.end(), false));
    CHECK(batched > 0);
    CHECK(batched < s.size());
    for (const Reduction reduce : {Reduction::Cpu, Reduction::Gpu}) {
        CAPTURE(int(reduce));
        HemicubeOptions o;
        o.resolution = 32;
        o.reduce = reduce;
        o.batch = 1;
        o.inFlight = 1;
        const FormFactorRun rowByRow = computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
        o.batch = 16;
        o.inFlight = 2;
        o.rowThreads = 2;
        const FormFactorRun mixed = computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
        CHECK(mixed.F.parameters.at("batch").rfind("16 (", 0) == 0);
        double worst = 0.0;
        for (PatchId i = 0; i < s.size(); ++i)
            for (PatchId j = 0; j < s.size(); ++j) worst = std::max(worst, std::abs(rowByRow.F.at(i, j) - mixed.F.at(i, j)));
        CHECK(worst < 1e-7);
        CHECK(mixed.counts.bounces == rowByRow.counts.bounces);  // the same portal passes
        CHECK(mixed.counts.bounces > 0);
    }
    // The conservative test itself: a patch that can see a mirror is never batched. Every pixel
    // that lands on a mirror in the row-by-row run belongs to a row marked as maybe seeing one.
    HemicubeOptions o;
    o.resolution = 32;
    o.batch = 1;
    const FormFactorRun r = computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
    std::size_t unmarked = 0;
    for (PatchId i = 0; i < s.size(); ++i)
        for (PatchId j = 0; j < s.size(); ++j)
            if (s.patches[j].specular > 0.0 && r.F.at(i, j) > 0.0 && !maySee[i]) ++unmarked;
    CHECK(unmarked == 0);
}

TEST_CASE("Subdivided closed cube: rows sum to 1 and face-to-face factors match the closed forms") {
    const Scene s = subdivide(unitCube(), 0.125);  // 8 x 8 patches per face
    const FormFactorRun r = hemicube(s, 128);
    CHECK(r.counts.misses == 0);
    CHECK(r.stats.rowSumMin == relative(1.0, 1e-5));
    CHECK(r.stats.rowSumMax == relative(1.0, 1e-5));
    // Area-weighted sums over each face's patches give the face-to-face factors.
    const std::size_t per = s.size() / 6;
    for (std::size_t a = 0; a < 6; ++a)
        for (std::size_t b = 0; b < 6; ++b) {
            if (a == b) continue;
            double sum = 0.0;
            for (std::size_t i = a * per; i < (a + 1) * per; ++i)
                for (std::size_t j = b * per; j < (b + 1) * per; ++j) sum += r.F.at(i, j);
            const double expected = (a ^ 1) == b ? kCubeOpposite : kCubeAdjacent;
            CHECK(sum / double(per) == relative(expected, 5e-3));
        }
}

TEST_CASE("Drawing subdivided parents whole gives the F of drawing every patch") {
    const Scene s = subdivide(bundledScene("cornell_box.obj"), 60.0);
    const FormFactorRun whole = hemicube(s, 128, Reduction::Cpu, true);
    const FormFactorRun each = hemicube(s, 128, Reduction::Cpu, false);
    // Only pixels whose centres lie exactly on an edge may differ: between sibling patches (which
    // one gets it), and on outer edges (a big triangle's edge and a row of small ones rasterise the
    // same line, but ties on it can fall either way).
    CHECK(meanRowL1(whole.F, each.F) < 1e-3);
    for (PatchId i = 0; i < s.size(); ++i) CHECK(whole.F.rowSum(i) == relative(each.F.rowSum(i), 2e-4));
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
    CHECK(r.counts.lostWeight == relative(below, 1e-3));
}

TEST_CASE("A failing GL context is a clear error, auto falls back to OSMesa, and OSMesa is loaded only when needed") {
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
    CHECK(status("", "osmesa") == 0);
    // libOSMesa is loaded at run time, only when asked for: the binary does not need it, EGL runs
    // without it, and its absence is a clear error naming the way out.
    CHECK(runCommand("ldd " + std::string(HEMIRAD_BINARY)).output.find("libOSMesa") == std::string::npos);
    CHECK(status("HEMIRAD_OSMESA_LIBRARY=/nonexistent/libOSMesa.so.8", "egl") == 0);
    CHECK(status("HEMIRAD_OSMESA_LIBRARY=/nonexistent/libOSMesa.so.8", "osmesa") == 1);
    CHECK(output().find("OSMesa: cannot load libOSMesa (/nonexistent/libOSMesa.so.8") != std::string::npos);
    CHECK(output().find("--gl egl") != std::string::npos);
    CHECK(status("HEMIRAD_OSMESA_LIBRARY=/nonexistent/libOSMesa.so.8 __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json", "auto") == 1);
    CHECK(output().find("EGL: no surfaceless Mesa display") != std::string::npos);
    CHECK(output().find("cannot load libOSMesa") != std::string::npos);
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
    CHECK(viaMirror == relative(0.9 * (c11(2, 1, 1) - c11(1, 1, 1)), 2e-3));
    CHECK(r.counts.bounces > 0);  // portal passes ran
    CHECK(r.F.parameters.at("mirrors") == "portals");
}

TEST_CASE("Area-sampled hemicubes through a mirror portal: the two unsubdivided patches of mirror_pair get the image-method factor") {
    // One patch each: from the centroid the factor through the mirror is 1.8 % low; 16 hemicubes
    // per patch, each weighted by its point's weight (portals included), close the gap.
    const Scene s = bundledScene("mirror_pair.obj");
    const double exact = 0.9 * (c11(2, 1, 1) - c11(1, 1, 1));
    HemicubeOptions o;
    o.resolution = 256;
    o.origins = 16;
    const FormFactorRun r = computeFormFactors(s, MethodSettings::of(o), neededRows(s, false));
    CHECK(std::abs(r.F.at(0, 1) - exact) < 2e-4);  // measured -9e-6
    CHECK(std::abs(r.F.at(1, 0) - exact) < 2e-4);
    o.origins = 1;
    CHECK(std::abs(computeFormFactors(s, MethodSettings::of(o), neededRows(s, false)).F.at(0, 1) - exact) > 1e-3);
}

TEST_CASE("Computing F leaves the process environment alone: no setenv while worker threads run") {
    // The hemicube once set LP_NUM_THREADS from prepare(), while other threads may read the
    // environment (a data race in getenv/setenv); configureProcessThreads() in main() does it now.
    const char* previous = std::getenv("LP_NUM_THREADS");
    const std::string kept = previous ? previous : "";
    ::unsetenv("LP_NUM_THREADS");
    std::vector<std::string> before;
    for (char** e = environ; *e; ++e) before.emplace_back(*e);
    HemicubeOptions o;
    o.resolution = 16;
    CommonOptions twoWorkers;
    twoWorkers.threads = 2;
    const Scene s = subdivide(unitCube(), 0.5);
    const FormFactorRun r = computeFormFactors(s, MethodSettings::of(o, twoWorkers), neededRows(s, true));
    std::vector<std::string> after;
    for (char** e = environ; *e; ++e) after.emplace_back(*e);
    if (previous) ::setenv("LP_NUM_THREADS", kept.c_str(), 1);
    CHECK(r.F.rowSum(0) == relative(1.0, 1e-3));
    CHECK(after == before);
}

TEST_CASE("Without a visible mirror no portal pass runs") {
    const FormFactorRun r = hemicube(subdivide(unitCube(), 0.5), 32);
    CHECK(r.counts.bounces == 0);
    CHECK(r.counts.cutoffWeight == 0.0);
}

