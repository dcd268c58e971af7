// The library pipeline every front end calls: checks before work, missing rows only, the
// reciprocity and normalisation policy on a non-reciprocal F, and a mirror scene's radiosity
// against its closed-form two-patch solution.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/subdivide.hpp"
#include "engine/reciprocal_closure.hpp"
#include "engine/tone_map.hpp"
#include "pipeline/radiosity_pipeline.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// A pipeline that records what it did.
struct Recorder {
    std::vector<std::string> messages;
    int computations = 0;
    std::size_t rowsComputed = 0;
    PipelineEvents events() {
        PipelineEvents e;
        e.message = [this](const std::string& m) { messages.push_back(m); };
        e.formFactorsComputed = [this](const FormFactorRun& run, const Scene&, const MethodSettings&) {
            ++computations;
            rowsComputed += run.rowsComputed;
        };
        return e;
    }
};

/// The unit cube with a non-reciprocal F: row 0 scaled by 0.8 (every row computed).
FormFactors skewedCubeF() {
    std::vector<std::vector<FormFactors::Entry>> rows(6);
    for (std::uint32_t i = 0; i < 6; ++i)
        for (std::uint32_t j = 0; j < 6; ++j)
            if (i != j) rows[i].push_back({j, float(((i ^ 1) == j ? kCubeOpposite : kCubeAdjacent) * (i == 0 ? 0.8 : 1.0))});
    return FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(6, 1));
}

}  // namespace

TEST_CASE("The pipeline refuses --normalize-rows with mirrors before any row is computed") {
    Recorder recorder;
    FormFactorPolicy policy;
    policy.normalizeRows = true;
    const RadiosityPipeline pipeline(policy, recorder.events());
    const Scene mirrors = bundledScene("mirror_pair.obj");
    CHECK_THROWS_WITH_AS(pipeline.updateFormFactors(mirrors), doctest::Contains("the scene has mirrors"), Error);
    CHECK(recorder.computations == 0);
    CHECK_NOTHROW(pipeline.checkBeforeComputing(unitCube()));
}

TEST_CASE("The pipeline computes only the rows F lacks and keeps the others as they were") {
    Scene s = subdivide(unitCube(), 0.5);  // 24 patches
    for (PatchId i = 0; i < 4; ++i) s.patches[i].rho = Rgb::Zero();  // black: rows skipped
    Recorder recorder;
    HemisphereOptions h;
    h.estimator = Estimator::Rays;
    h.samples = 256;
    FormFactorPolicy policy;
    policy.backend = MethodSettings::of(h);
    const RadiosityPipeline pipeline(policy, recorder.events());
    FormFactorUpdate first = pipeline.updateFormFactors(s);
    CHECK(first.rowsComputed == 20);
    CHECK(first.F.computedRows() == 20);
    CHECK(pipeline.missingRows(s, &first.F).empty());
    const FormFactors before = first.F;

    s.patches[2].rho = Rgb::Constant(0.5);  // a black patch becomes reflective: its row is needed
    REQUIRE(pipeline.missingRows(s, &first.F) == std::vector<PatchId>{2});
    const FormFactorUpdate second = pipeline.updateFormFactors(s, std::move(first.F));
    CHECK(second.rowsComputed == 1);
    CHECK(recorder.computations == 2);
    CHECK(second.F.rowComputed(2));
    CHECK_FALSE(second.F.rowComputed(0));
    for (PatchId i = 4; i < s.size(); ++i)
        for (PatchId j = 0; j < s.size(); ++j) CHECK(second.F.at(i, j) == before.at(i, j));
    CHECK(second.F.parameters.at("rows_added").find("1 with hemisphere") == 0);
    // Nothing missing: nothing computed, F returned as it was.
    const FormFactorUpdate third = pipeline.updateFormFactors(s, second.F);
    CHECK(third.rowsComputed == 0);
    CHECK_FALSE(third.changed);
}

TEST_CASE("--enforce-reciprocity and --normalize-rows on a non-reciprocal F: A_i F_ij = A_j F_ji with row sums kept, then rows sum to 1") {
    const Scene s = unitCube();  // equal areas: reciprocity is symmetry
    const FormFactors skewed = skewedCubeF();
    REQUIRE(skewed.at(0, 2) != skewed.at(2, 0));

    FormFactorPolicy reciprocal;
    reciprocal.enforceReciprocity = true;
    reciprocal.statistics = true;
    std::vector<std::string> messages;
    PipelineEvents events;
    events.message = [&](const std::string& m) { messages.push_back(m); };
    const FormFactorUpdate r = RadiosityPipeline(reciprocal, events).updateFormFactors(s, skewed);
    CHECK(r.rowsComputed == 0);
    CHECK(r.changed);
    for (PatchId i = 0; i < 6; ++i)
        for (PatchId j = 0; j < 6; ++j) CHECK(r.F.at(i, j) == relative(r.F.at(j, i), 1e-7));
    REQUIRE(r.stats);
    CHECK(r.stats->reciprocityMax < 1e-6);
    // Row 0 was estimated at 0.8, 0.2 from 1: the scene is closed, but the targets are the estimates,
    // and every row keeps its sum (the pair means alone would leave row 0 at 0.9, the others at 1 - 0.02).
    CHECK(r.F.parameters.at("reciprocity") == "enforced, estimated row sums kept");
    for (PatchId i = 0; i < 6; ++i) CHECK(r.F.rowSum(i) == relative(skewed.rowSum(i), 1e-6));
    bool reported = false;
    for (const std::string& m : messages)
        reported |= m.find("rows keep their estimated sums (watertight, but some rows") != std::string::npos;
    CHECK(reported);

    FormFactorPolicy both = reciprocal;
    both.normalizeRows = true;
    const FormFactorUpdate n = RadiosityPipeline(both, {}).updateFormFactors(s, skewed);
    for (PatchId i = 0; i < 6; ++i) CHECK(n.F.rowSum(i) == relative(1.0, 1e-6));
    CHECK(n.F.parameters.at("rows") == "normalised to sum 1");
    // Normalisation alone restores closure on the skewed row and keeps the reciprocity gap.
    FormFactorPolicy normalise;
    normalise.normalizeRows = true;
    const FormFactorUpdate only = RadiosityPipeline(normalise, {}).updateFormFactors(s, skewed);
    CHECK(only.F.rowSum(0) == relative(1.0, 1e-6));
    CHECK(only.F.at(0, 2) == relative(kCubeAdjacent, 1e-6));
}

TEST_CASE("Two patches under a mirror: radiosity matches the closed-form 2 x 2 solution of the image method") {
    // P1 = [0,1]^2 and P2 = [1,2]x[0,1] on z = 0 facing +z, a mirror [0,2]x[0,1] at z = 0.5 facing -z
    // covering every path between them (s = 0.9, no diffuse part). Through the mirror each patch sees
    // its own image and its neighbour's (Sillion & Puech; docs/physics.md): F11 = F22 = s C11(1,1,1),
    // F12 = F21 = s (C11(2,1,1) - C11(1,1,1)); no direct exchange.
    const double sMirror = 0.9;
    SceneBuilder b;
    const std::uint32_t emitter = b.material("emitter", Rgb::Constant(0.6), Rgb(10, 5, 1));
    const std::uint32_t plain = b.material("plain", Rgb::Constant(0.4));
    const std::uint32_t mirror = b.material("mirror", Rgb::Zero(), Rgb::Zero(), sMirror);
    b.rectangle(2, 0, 0, 1, 0, 1, true, emitter);
    b.rectangle(2, 0, 1, 2, 0, 1, true, plain);
    b.rectangle(2, 0.5, 0, 2, 0, 1, false, mirror);
    const double self = sMirror * c11(1, 1, 1), cross = sMirror * (c11(2, 1, 1) - c11(1, 1, 1));
    // (1 - rho1 F11) B1 - rho1 F12 B2 = E1;  -rho2 F21 B1 + (1 - rho2 F22) B2 = E2 (E2 = 0).
    const double a11 = 1 - 0.6 * self, a12 = -0.6 * cross, a21 = -0.4 * cross, a22 = 1 - 0.4 * self;
    const double det = a11 * a22 - a12 * a21;

    HemisphereOptions h;
    h.estimator = Estimator::Rays;  // the mirror terms ride the rays
    h.samples = 16384;
    h.origins = 64;
    FormFactorPolicy policy;
    policy.backend = MethodSettings::of(h);
    const RadiosityPipeline pipeline(policy, {});
    const FormFactorUpdate F = pipeline.updateFormFactors(b.scene);
    CHECK(F.F.at(0, 1) == relative(cross, 1.5e-2));  // rays along the chains: 1.1 %, measured
    CHECK(F.F.at(0, 0) == relative(self, 3e-3));
    SolverOptions lu;
    lu.solver = "lu";
    const Radiosity B = pipeline.solve(b.scene, F.F, lu);
    for (int c = 0; c < 3; ++c) {
        const double E1 = b.scene.patches[0].emission[c];
        CAPTURE(c);
        CHECK(B.B[0][c] == relative(E1 * a22 / det, 1e-3));
        CHECK(B.B[1][c] == relative(-E1 * a21 / det, 1.5e-2));  // B2 follows F12
        CHECK(B.B[2][c] == 0.0);  // the mirror has no diffuse part: B = E = 0
    }
}

TEST_CASE("--drop-below keeps every pair with an emitter: a patch keeps its entry to the light and its B") {
    // issue 35 #3: at 0.01 on the Cornell box (--subdivide 150) patch 83 lost its only entry to the
    // light, kept its row sum, and its B fell 43 %.
    Warnings quiet = quietWarnings();
    const Scene s = subdivide(loadScene(sourcePath("scenes/cornell_box.obj"), quiet), 150);
    std::vector<PatchId> lights;
    for (PatchId j = 0; j < s.size(); ++j)
        if ((s.patches[j].emission > 0.0).any()) lights.push_back(j);
    REQUIRE_FALSE(lights.empty());
    const FormFactorUpdate full = RadiosityPipeline(FormFactorPolicy{}, {}).updateFormFactors(s);
    FormFactorPolicy drop;
    drop.dropBelow = 0.01;
    const RadiosityPipeline dropping(drop, {});
    const FormFactorUpdate dropped = dropping.updateFormFactors(s, full.F);
    CHECK(dropped.F.nonZeros() < full.F.nonZeros());
    REQUIRE(s.size() > 83);
    double seen = 0.0;
    for (const PatchId light : lights) seen += full.F.at(83, light);
    CHECK(seen > 0.0);
    SolverOptions lu;
    lu.solver = "lu";
    const Radiosity exact = dropping.solve(s, full.F, lu);
    const Radiosity sparse = dropping.solve(s, dropped.F, lu);
    // Where the light carries at least 1 % of a patch's B, B moves by less than 8 % (the other
    // entries' rebalancing: 4.9 % at most before the pairs across a shadow's edge were computed
    // whole, 7.0 % since, patch 79; the patches lit through a sliver of the light move up to 9 %
    // at this coarse EPS, as every patch lit only indirectly may).
    auto change = [&](PatchId i) { return std::abs(luminance(sparse.B[i]) - luminance(exact.B[i])) / luminance(exact.B[i]); };
    double worst = 0.0;
    PatchId worstPatch = 0;
    std::size_t lit = 0;
    for (PatchId i = 0; i < s.size(); ++i) {
        Rgb direct = Rgb::Zero();
        for (const PatchId light : lights)
            if (full.F.at(i, light) > 0.0) {
                CHECK(dropped.F.at(i, light) > 0.0);  // kept, pair by pair
                direct += s.patches[i].rho * full.F.at(i, light) * exact.B[light];
            }
        if ((s.patches[i].emission > 0.0).any() || luminance(direct) < 0.01 * luminance(exact.B[i])) continue;
        ++lit;
        if (change(i) > worst) worst = change(i), worstPatch = i;
    }
    MESSAGE("largest relative change of B where the light gives 1 % of it or more: " << worst << " (patch " << worstPatch
            << ", " << lit << " patches); patch 83: " << change(83));
    CHECK(lit > 100);
    CHECK(worst < 0.08);
    CHECK(change(83) < 0.03);  // 0.43 when its entry to the light was dropped
}

TEST_CASE("An F given again is post-processed only where its record lacks a step: dropped once, closed once, normalised once") {
    // issue 35 #2: a stored F dropped at EPS was dropped again on every reuse.
    const Scene s = subdivide(bundledScene("cornell_box.obj"), 150);
    const FormFactorUpdate full = RadiosityPipeline(FormFactorPolicy{}, {}).updateFormFactors(s);
    CHECK(pendingPostProcessing(FormFactorPolicy{}, full.F).any() == false);
    FormFactorPolicy drop;
    drop.dropBelow = 0.01;
    const RadiosityPipeline dropping(drop, {});
    const FormFactorUpdate dropped = dropping.updateFormFactors(s, full.F);
    CHECK(dropped.changed);
    CHECK(*sparsifiedThreshold(dropped.F) == 0.01);
    const FormFactorUpdate again = dropping.updateFormFactors(s, dropped.F);
    CHECK_FALSE(again.changed);
    CHECK(again.F.nonZeros() == dropped.F.nonZeros());
    CHECK(again.F.valueVector() == dropped.F.valueVector());
    // Another EPS drops again; reciprocity is recorded by the drop's closure; normalising is new.
    FormFactorPolicy other = drop;
    other.dropBelow = 0.02;
    CHECK(pendingPostProcessing(other, dropped.F).dropBelow == 0.02);
    FormFactorPolicy closeAndNormalise;
    closeAndNormalise.enforceReciprocity = true;
    closeAndNormalise.normalizeRows = true;
    const PostProcessing pending = pendingPostProcessing(closeAndNormalise, dropped.F);
    CHECK_FALSE(pending.enforceReciprocity);
    CHECK(pending.normalizeRows);
    FormFactors normalised = dropped.F;
    normalizeRows(normalised);
    CHECK_FALSE(pendingPostProcessing(closeAndNormalise, normalised).any());
    // A post-processed F that lacks rows cannot take new ones: it is computed again whole.
    const PatchId black = 5;
    std::vector<std::vector<FormFactors::Entry>> rows(s.size());
    std::vector<std::uint8_t> computed = full.F.computedFlags();
    for (PatchId i = 0; i < s.size(); ++i)
        if (i != black)
            for (std::uint64_t k = dropped.F.rowBegin(i); k < dropped.F.rowEnd(i); ++k)
                rows[i].push_back({dropped.F.columns()[k], dropped.F.values()[k]});
    computed[black] = 0;
    FormFactors partial = FormFactors::fromRows(std::move(rows), computed);
    partial.sceneHash = dropped.F.sceneHash;
    partial.provenance = dropped.F.provenance;
    partial.parameters = dropped.F.parameters;
    Recorder recorder;
    const FormFactorUpdate whole = RadiosityPipeline(drop, recorder.events()).updateFormFactors(s, std::move(partial));
    CHECK(whole.rowsComputed == s.size());
    CHECK(whole.F.valueVector() == dropped.F.valueVector());
    const StoredFormFactorRule rule = StoredFormFactorRule::reused(dropped.F, s.size() - 1, 1, "F.hff");
    CHECK_FALSE(rule.reuse());
    CHECK(rule.storeAfterPostProcessing());
    CHECK(rule.lines().at(0).find("computing F again whole") != std::string::npos);
}
