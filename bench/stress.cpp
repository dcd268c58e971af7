// Numerical stress benchmarks (issue #4): high-albedo closed boxes for every solver, closure error
// amplification with and without reciprocity enforcement and row normalisation, a hall of mirrors
// against the depth limit, extreme scales, and float against double accumulation.
#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "engine/reciprocal_closure.hpp"
#include "solve/solver.hpp"
#include "solve/solver_registry.hpp"
#include "engine/subdivide.hpp"
#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

using namespace hemirad;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

Scene box(double maxEdge) {
    Warnings w(nullptr);
    return subdivide(loadObj("scenes/unit_cube.obj", w), maxEdge);
}

void furnace(Scene& s, double rho) {
    for (Patch& p : s.patches) {
        p.rho = Rgb::Constant(rho);
        p.emission = Rgb::Constant(1.0);
    }
}

/// Max relative error of B against the furnace answer E / (1 - rho).
double furnaceError(const Radiosity& r, double rho) {
    double worst = 0.0;
    for (const Rgb& b : r.B) worst = std::max(worst, std::abs(b[0] * (1.0 - rho) - 1.0));
    return worst;
}

FormFactors hemisphereF(const Scene& s, std::uint32_t samples, std::uint32_t origins = 1) {
    HemisphereOptions o;
    o.estimator = Estimator::Rays;  // the ray estimator: closed rows sum to 1 exactly
    o.samples = samples;
    o.origins = origins;
    return computeFormFactors(s, MethodSettings::of(o), neededRows(s, true)).F;
}

void solvers() {
    std::printf("\n## Closed box furnace: every solver at high albedo\n\n");
    std::printf("Unit cube, 8 x 8 patches per face (384), hemisphere F (768 directions, rows sum to 1 exactly),\n"
                "E = 1 everywhere: B = E / (1 - rho). Tolerance 1e-9; `error` = max |B (1 - rho) - 1|.\n"
                "Cholesky and CG solve the symmetric form diag(A / rho) - diag(A) F, exact only for a reciprocal F:\n"
                "`--enforce-reciprocity` (symmetric scaling to the row targets, here 1: a closed box) makes it so.\n\n");
    std::printf("| rho | F | solver | converged | iterations | seconds | error |\n|---|---|---|---|---|---|---|\n");
    Scene s = box(0.125);
    const FormFactors raw = hemisphereF(s, 768);
    FormFactors enforced = raw;
    enforceReciprocity(enforced, s);
    for (double rho : {0.9, 0.99, 0.999}) {
        furnace(s, rho);
        for (const FormFactors* F : {&raw, static_cast<const FormFactors*>(&enforced)})
            for (const SolverDescriptor* solver : solverRegistry()) {
                const std::string& kind = solver->name;
                SolverOptions o;
                o.solver = kind;
                o.tolerance = 1e-9;
                o.allowUnconverged = true;
                o.maxIterations = 200000;
                const auto t0 = Clock::now();
                const Radiosity r = solveRadiosity(s, *F, o);
                std::printf("| %.3f | %s | %s | %s | %d | %.3f | %.2e |\n", rho, F == &raw ? "as estimated" : "enforced",
                            kind.c_str(), r.reports[0].converged ? "yes" : "NO", r.reports[0].iterations, since(t0),
                            furnaceError(r, rho));
            }
    }
}

void closure() {
    std::printf("\n## Closure error amplification\n\n");
    std::printf("Same box, hemisphere F with 96 directions x 4 origins. The old `--enforce-reciprocity` averaged\n"
                "A_i F_ij and A_j F_ji, which broke the rows' closure (the furnace error grows as rho delta / (1 - rho),\n"
                "physics.md); the pair mean scaled symmetrically to the row targets keeps both. Gauss-Seidel to 1e-10.\n\n");
    Scene s = box(0.125);
    const FormFactors raw = hemisphereF(s, 96, 4);
    // The pair means alone (the old --enforce-reciprocity): both rows of a pair computed.
    FormFactors averaged = raw;
    {
        const TransposedFormFactors Ft = transpose(raw);
        std::vector<std::vector<FormFactors::Entry>> rows(raw.size());
        for (std::size_t i = 0; i < raw.size(); ++i)
            mergeRowAndColumn(raw, Ft, i, [&](std::uint32_t j, double fij, double fji) {
                const double v = j == i ? fij : 0.5 * (s.patches[i].area * fij + s.patches[j].area * fji) / s.patches[i].area;
                if (v > 0.0) rows[i].push_back({j, float(v)});
            });
        averaged = FormFactors::fromRows(std::move(rows), raw.computedFlags());
    }
    FormFactors enforced = raw;
    const ReciprocityReport report = enforceReciprocity(enforced, s);
    std::printf("(`--enforce-reciprocity`: %s)\n\n", describe(report).c_str());
    std::printf("| rho | F | max row-sum error | reciprocity max | furnace error |\n|---|---|---|---|---|\n");
    struct Variant {
        const char* name;
        const FormFactors* F;
    };
    const Variant variants[] = {{"as estimated", &raw}, {"pair means (the old enforcement)", &averaged},
                                {"--enforce-reciprocity", &enforced}};
    for (double rho : {0.9, 0.99, 0.999}) {
        furnace(s, rho);
        for (const Variant& v : variants) {
            double delta = 0.0;
            for (std::size_t i = 0; i < v.F->size(); ++i) delta = std::max(delta, std::abs(v.F->rowSum(i) - 1.0));
            const double reciprocity = computeStats(*v.F, s).reciprocityMax;
            SolverOptions o;
            o.solver = "gauss-seidel";
            o.tolerance = 1e-10;
            o.maxIterations = 200000;
            try {
                const Radiosity r = solveRadiosity(s, *v.F, o);
                std::printf("| %.3f | %s | %.2e | %.2e | %.2e |\n", rho, v.name, delta, reciprocity, furnaceError(r, rho));
            } catch (const Error& e) {
                std::printf("| %.3f | %s | %.2e | %.2e | no solution: %s |\n", rho, v.name, delta, reciprocity, e.what());
            }
        }
    }
}

void mirrors() {
    std::printf("\n## Hall of mirrors: the depth limit\n\n");
    std::printf("Two facing mirrors (6 x 6 m, 1 m apart, s = 0.99) and a 0.6 m diffuse patch between them\n"
                "facing one mirror; hemisphere, 4096 directions. F(patch -> itself) through the mirrors and\n"
                "the power still travelling when chains are cut (reported by every run).\n\n");
    std::printf("| max depth | F(patch -> patch) | F(patch -> mirror 1) | cut off (%% of emitted) | bounces | seconds |\n"
                "|---|---|---|---|---|---|\n");
    Scene s;
    s.materials.push_back(Material{});
    s.materials[0].name = "white";
    Material m;
    m.name = "mirror";
    m.rho = Rgb::Zero();
    m.specular = 0.99;
    s.materials.push_back(m);
    s.objects.push_back("default");
    auto quad = [&](double z, double h, bool up, std::uint32_t material) {
        const std::uint32_t b = std::uint32_t(s.vertices.size());
        s.vertices.push_back(Vec3(-h, -h, z));
        s.vertices.push_back(Vec3(h, -h, z));
        s.vertices.push_back(Vec3(h, h, z));
        s.vertices.push_back(Vec3(-h, h, z));
        if (up) s.addPatch({b, b + 1, b + 2, b + 3}, material, 0);
        else s.addPatch({b, b + 3, b + 2, b + 1}, material, 0);
    };
    quad(0.0, 3.0, true, 1);
    quad(1.0, 3.0, false, 1);
    quad(0.5, 0.3, false, 0);
    for (std::uint32_t depth : {1u, 2u, 4u, 8u, 16u, 64u, 256u, 1000u}) {
        HemisphereOptions o;
        o.estimator = Estimator::Rays;
        o.samples = 4096;
        CommonOptions chain;
        chain.maxDepth = depth;
        chain.minWeight = 1e-6;
        const auto t0 = Clock::now();
        const FormFactorRun r = computeFormFactors(s, MethodSettings::of(o, chain), {2});
        std::printf("| %u | %.5f | %.5f | %.4f | %llu | %.3f |\n", depth, r.F.at(2, 2), r.F.at(2, 0),
                    100.0 * r.counts.cutoffWeight, static_cast<unsigned long long>(r.counts.bounces), since(t0));
    }
}

void scales() {
    std::printf("\n## Extreme scales\n\n");
    std::printf("| case | quantity | value | expected |\n|---|---|---|---|\n");
    // Area ratio 1e6: a 1 mm square facing a 1 m square 0.5 m away; reciprocity A_i F_ij = A_j F_ji.
    {
        Scene s;
        s.materials.push_back(Material{});
        s.objects.push_back("default");
        auto square = [&](double h, double z, bool up) {
            const std::uint32_t b = std::uint32_t(s.vertices.size());
            for (Vec3 v : {Vec3(-h, -h, z), Vec3(h, -h, z), Vec3(h, h, z), Vec3(-h, h, z)}) s.vertices.push_back(v);
            if (up) s.addPatch({b, b + 1, b + 2, b + 3}, 0, 0);
            else s.addPatch({b, b + 3, b + 2, b + 1}, 0, 0);
        };
        square(0.0005, 0.0, true);
        square(0.5, 0.5, false);
        const FormFactors F = hemisphereF(s, 3072, 64);
        const double small = s.patches[0].area * F.at(0, 1), large = s.patches[1].area * F.at(1, 0);
        const double expectedHits = 3072.0 * 64 * small / s.patches[1].area;
        std::printf("| area ratio 1e6 | F_small->large (196,608 rays) | %.4f | 0.5541 (4 B-3, a = b = c) |\n", F.at(0, 1));
        std::printf("| area ratio 1e6 | A_small F_sl / (A_large F_ls) | %.3g | 1 with ~%.2f expected hits on the "
                    "small patch from the large one: its row cannot resolve F_ls; A_small F_sl is the estimate to trust |\n",
                    small / large, expectedHits);
    }
    // Nearly touching: unit squares 1e-4 apart (C-11 with c = 1e-4: F = 0.99990).
    {
        Scene s;
        s.materials.push_back(Material{});
        s.objects.push_back("default");
        for (Vec3 v : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0, 0, 1e-4), Vec3(1, 0, 1e-4),
                       Vec3(1, 1, 1e-4), Vec3(0, 1, 1e-4)})
            s.vertices.push_back(v);
        s.addPatch({0, 1, 2, 3}, 0, 0);
        s.addPatch({4, 7, 6, 5}, 0, 0);
        const FormFactors F = hemisphereF(s, 3072, 16);
        std::printf("| plates 1e-4 apart | F_12 | %.5f | 0.99990 |\n", F.at(0, 1));
    }
    // Large coordinates: the subdivided cube moved by 1e5 and scaled by 1000 still loses nothing.
    {
        Scene s = box(0.25);
        for (Vec3& v : s.vertices) v = 1000.0 * v + Vec3(1e5, 1e5, 1e5);
        s.updateMeasures();
        HemisphereOptions o;
        o.estimator = Estimator::Rays;
        o.samples = 768;
        const FormFactorRun r = computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
        std::printf("| cube offset 1e5, scale 1e3 | lost fraction | %.2e | 0 |\n", r.counts.lostWeight / double(s.size()));
        std::printf("| cube offset 1e5, scale 1e3 | min row sum | %.6f | 1 |\n", r.stats.rowSumMin);
    }
}

void accumulation() {
    std::printf("\n## Float against double accumulation\n\n");
    std::printf("Summing the 3 R^2 delta form factors of one hemicube (they total exactly 1) pixel by pixel,\n"
                "as a patch seen by the whole hemicube would: the error of a float accumulator grows with R.\n\n");
    std::printf("| R | pixels | float sum - 1 | double sum - 1 |\n|---|---|---|---|\n");
    for (int R : {64, 256, 1024, 2048}) {
        const double step = 2.0 / R, dA = step * step;
        std::vector<double> w;
        double total = 0;
        for (int face = 0; face < 5; ++face)
            for (int py = 0; py < (face ? R / 2 : R); ++py)
                for (int px = 0; px < R; ++px) {
                    const double x = -1 + (px + 0.5) * step;
                    const double y = face ? (py + 0.5) * step : -1 + (py + 0.5) * step;
                    const double d = x * x + y * y + 1;
                    w.push_back((face ? y : 1.0) * dA / (3.14159265358979 * d * d));
                    total += w.back();
                }
        float f = 0;
        double g = 0;
        for (double v : w) {
            f += static_cast<float>(v / total);
            g += static_cast<float>(v / total);
        }
        std::printf("| %d | %zu | %.2e | %.2e |\n", R, w.size(), double(f) - 1.0, g - 1.0);
    }
}

}  // namespace

int main() {
    try {
        std::printf("# Numerical stress benchmarks\n");
        solvers();
        closure();
        mirrors();
        scales();
        accumulation();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_stress: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
