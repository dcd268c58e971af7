// Adding a back end is its own code plus one registration: a test-only back end (the closed unit
// cube's exact factors from Howell's closed forms) is registered here and then used, unchanged,
// by hemirad's option parsing and usage text, the pipeline, the memory check and the report.
#include "support.hpp"

#include "cli/options.hpp"
#include "engine/error.hpp"
#include "pipeline/radiosity_pipeline.hpp"
#include "preprocess/backend_registry.hpp"

#include "preprocess/hemisphere/hemisphere_options.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

/// The test back end's own options.
struct ClosedCubeOptions {
    static constexpr const char* kMethod = "closed-cube";
    int percent = 100;  ///< every factor scaled to this percent (to see the option arrive)
};

/// Rows of the closed unit cube (patches in unitCube()'s order: opposite faces pair up as (0,1),
/// (2,3), (4,5)), from the closed forms instead of sampling.
class ClosedCubeBackend final : public FormFactorBackend {
public:
    explicit ClosedCubeBackend(const ClosedCubeOptions& options) : m_options(options) {}
    std::string_view name() const override { return ClosedCubeOptions::kMethod; }
    void prepare(const Scene& scene) override {
        if (scene.size() != 6) throw Error("closed-cube: the scene must be the 6-patch unit cube");
    }
    void computeRows(RowSource& rows, FormFactorBuilder& builder) override {
        const double scale = m_options.percent / 100.0;
        for (PatchId i = 0; rows.next(i);) {
            std::vector<FormFactors::Entry> row;
            for (std::uint32_t j = 0; j < 6; ++j)
                if (j != i) row.push_back({j, float(scale * ((i ^ 1) == j ? kCubeOpposite : kCubeAdjacent))});
            builder.setRow(i, std::move(row), 1.0 - scale);  // what the scaled row leaves out
        }
    }
    FormFactorProvenance provenance() const override {
        FormFactorProvenance p;
        p.method = ClosedCubeOptions::kMethod;
        return p;
    }
    std::map<std::string, std::string> parameters() const override {
        return {{"percent", std::to_string(m_options.percent)}};
    }

private:
    ClosedCubeOptions m_options;
};

const BackendDescriptor& closedCubeDescriptor() {
    static const BackendDescriptor d = [] {
        BackendDescriptor b;
        b.name = ClosedCubeOptions::kMethod;
        b.summary = "exact factors of the closed unit cube (test back end)";
        b.workUnit = "rows";
        b.options = {integerOption<ClosedCubeOptions>("--percent", "Percent", "P", "scale every factor to P percent",
                                                      &ClosedCubeOptions::percent, 1, 100)};
        b.defaults = [] { return std::any(ClosedCubeOptions{}); };
        b.create = [](const MethodSettings& s) -> std::unique_ptr<FormFactorBackend> {
            return std::make_unique<ClosedCubeBackend>(s.as<ClosedCubeOptions>());
        };
        b.workPerRow = [](const Scene&, const MethodSettings&) { return 1.0; };
        b.describe = [](const Scene&, const MethodSettings& s) {
            RunDescription r;
            r.settings = "closed forms at " + std::to_string(s.as<ClosedCubeOptions>().percent) + "%";
            r.record = {{"percent", std::to_string(s.as<ClosedCubeOptions>().percent)}};
            return r;
        };
        return b;
    }();
    return d;
}

/// The test back end is registered for one test case only: other cases in the same process (a
/// direct run of hemirad_tests) see the built-in registry.
struct ScopedRegistration {
    ScopedRegistration() { registerFormFactorBackend(closedCubeDescriptor()); }
    ~ScopedRegistration() { unregisterFormFactorBackend(ClosedCubeOptions::kMethod); }
};

}  // namespace

TEST_CASE("A back end registered from outside the library works through hemirad's options, the pipeline and the solve") {
    const ScopedRegistration registered;
    // The CLI parses its flags, refuses other back ends' flags for it and its flag for others.
    const char* argv[] = {"hemirad", "solve", "cube.obj", "-o", "B.csv", "--method", "closed-cube", "--percent", "100"};
    const Options o = parseOptions(9, argv);
    CHECK(o.formFactors.method == "closed-cube");
    CHECK(o.formFactors.as<ClosedCubeOptions>().percent == 100);
    const char* wrong[] = {"hemirad", "solve", "cube.obj", "-o", "B.csv", "--method", "closed-cube", "--samples", "96"};
    CHECK_THROWS_WITH_AS(parseOptions(9, wrong), doctest::Contains("'--samples' does not apply to --method closed-cube (it takes --percent)"),
                         UsageError);
    const char* other[] = {"hemirad", "solve", "cube.obj", "-o", "B.csv", "--percent", "50"};
    CHECK_THROWS_WITH_AS(parseOptions(7, other), doctest::Contains("'--percent' does not apply to --method hemisphere"), UsageError);
    CHECK(usageText().find("closed-cube (--method closed-cube): exact factors of the closed unit cube") != std::string::npos);

    // The pipeline computes F with it and the solve reproduces the unit-cube table of docs/physics.md.
    Scene s = unitCube();
    for (Patch& p : s.patches) p.rho = Rgb::Constant(0.5), p.emission = Rgb::Zero();
    s.patches[0].emission = Rgb::Constant(1.0);
    std::vector<std::string> lines;
    FormFactorPolicy policy;
    policy.backend = o.formFactors;
    PipelineEvents events;
    events.formFactorsComputed = [&](const FormFactorRun& run, const Scene& scene, const MethodSettings& m) {
        lines.push_back(findBackend(m.method).describe(scene, m).settings + ", " + std::to_string(run.rowsComputed) + " rows");
    };
    const RadiosityPipeline pipeline(policy, events);
    const FormFactorUpdate F = pipeline.updateFormFactors(s);
    CHECK(lines == std::vector<std::string>{"closed forms at 100%, 6 rows"});
    CHECK(F.F.provenance.method == "closed-cube");
    CHECK(F.F.parameters.at("percent") == "100");
    const Radiosity B = pipeline.solve(s, F.F, {});
    CHECK(B.B[0][0] == doctest::Approx(1.0909090981).epsilon(1e-6));
    CHECK(B.B[1][0] == doctest::Approx(0.1817458261).epsilon(1e-6));

    // Its name is taken now; a second registration is an error.
    CHECK_THROWS_WITH_AS(registerFormFactorBackend(closedCubeDescriptor()), doctest::Contains("registered already"), Error);
}

TEST_CASE("An unregistered back end is gone from the registry, and the built-in default stays") {
    {
        const ScopedRegistration registered;
        CHECK(formFactorBackends().size() == 3);
    }
    CHECK(formFactorBackends().size() == 2);
    CHECK_THROWS_WITH_AS(defaultSettings("closed-cube"), doctest::Contains("unknown --method 'closed-cube'"), Error);
    CHECK_THROWS_WITH_AS(unregisterFormFactorBackend("hemisphere"), doctest::Contains("cannot be removed"), Error);
}

TEST_CASE("Form-factor settings as F records them: one line, compared by the GUI's rule, differences named") {
    MethodSettings a = defaultSettings(defaultBackend().name);
    MethodSettings b = a;
    b.common.threads = 7;  // how fast, not which F
    CHECK(sameFormFactorSettings(a, b));
    CHECK(formFactorSettingsDifference(formFactorSettingsText(a), b).empty());
    const std::string text = formFactorSettingsText(a);
    CHECK(text.rfind("--method=" + a.method + " --max-depth=8 min_weight=1e-04", 0) == 0);
    b.common.maxDepth = 2;
    CHECK_FALSE(sameFormFactorSettings(a, b));
    CHECK(formFactorSettingsDifference(text, b) == "--max-depth 8 (the file) against 2 (this run)");
    // Another back end: named alone; an unrecorded option is said to be so.
    CHECK(formFactorSettingsDifference("--method=closed-cube", a) ==
          "--method closed-cube (the file) against " + a.method + " (this run)");
    CHECK(formFactorSettingsDifference("--method=" + a.method, a).find("--max-depth (not recorded) (the file) against 8") == 0);
}

TEST_CASE("A back-end option that F's settings do not record counts as its default (files from before the option)") {
    MethodSettings a = MethodSettings::of(HemisphereOptions{});
    std::string older = formFactorSettingsText(a);
    const std::size_t at = older.find(" --pairs=rules");
    REQUIRE(at != std::string::npos);
    older.erase(at, std::string(" --pairs=rules").size());
    CHECK(formFactorSettingsDifference(older, a).empty());
    a.as<HemisphereOptions>().pairs = PairMethod::Whole;
    CHECK(formFactorSettingsDifference(older, a) == "--pairs (not recorded) (the file) against whole (this run)");
}
