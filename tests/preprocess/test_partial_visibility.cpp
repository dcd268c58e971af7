// The analytic estimator's partial visibility end to end (default flags): blockers that hide part
// of a receiver, against closed forms and factor algebra.
#include "support.hpp"

#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

FormFactorRun analyticF(const Scene& s) {
    HemisphereOptions o;
    o.estimator = Estimator::Analytic;
    return computeFormFactors(s, MethodSettings::of(o), neededRows(s, true));
}

/// The square plates [-0.5, 0.5]^2 at z = 0 and z = 1 (n x n patches each) with a square blocker of
/// side 0.1 centred at z = 0.9; returns the plates' first patch ids.
Scene platesWithBlocker(int n, PatchId& lower, PatchId& upper) {
    SceneBuilder b;
    const double h = 1.0 / n;
    lower = PatchId(b.scene.size());
    for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) b.rectangle(2, 0, -0.5 + h * u, -0.5 + h * (u + 1), -0.5 + h * v, -0.5 + h * (v + 1), true);
    upper = PatchId(b.scene.size());
    for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) b.rectangle(2, 1, -0.5 + h * u, -0.5 + h * (u + 1), -0.5 + h * v, -0.5 + h * (v + 1), false);
    b.rectangle(2, 0.9, -0.05, 0.05, -0.05, 0.05, false);
    return b.scene;
}

/// The plates' factor past the blocker by superposition: from each point of the lower plate, the
/// upper plate's factor minus that of the blocker's shadow, the square of side 0.1 / 0.9 centred
/// at -x / 9 (inside the plate from every point), integrated by a 24 x 24 Gauss-Legendre rule (the
/// integrand is smooth).
double platesPastBlocker() {
    std::vector<double> nodes, weights;
    gaussLegendre(24, nodes, weights);
    const double s = 0.05 / 0.9;
    double sum = 0.0;
    for (std::size_t a = 0; a < nodes.size(); ++a)
        for (std::size_t b = 0; b < nodes.size(); ++b) {
            const double px = nodes[a] - 0.5, py = nodes[b] - 0.5;
            const double cx = -px / 9, cy = -py / 9;
            sum += weights[a] * weights[b] *
                   (toRectangle(px, py, -0.5, 0.5, -0.5, 0.5, 1) - toRectangle(px, py, cx - s, cx + s, cy - s, cy + s, 1));
        }
    return sum;
}

}  // namespace

TEST_CASE("Partial visibility: a partition from the emitter's edge hides the receiver's far half exactly (C-12 minus C-12 = C-11)") {
    // Emitter [0, 1]^2 at z = 0, receiver [0, 2] x [0, 1] at z = 1, a wall x = 1 between them.
    SceneBuilder b;
    const PatchId emitter = b.rectangle(2, 0, 0, 1, 0, 1, true);
    const PatchId receiver = b.rectangle(2, 1, 0, 2, 0, 1, false);
    b.rectangle(0, 1, 0, 1, 0, 1, false);
    const FormFactorRun r = analyticF(b.scene);
    // Unblocked minus the blocked part, both by C-12; the same as the directly opposed C-11 square.
    const double unblocked = parallelRectangles(0, 1, 0, 1, 0, 2, 0, 1, 1);
    const double expected = unblocked - parallelRectangles(0, 1, 0, 1, 1, 2, 0, 1, 1);
    REQUIRE(expected == doctest::Approx(c11(1, 1, 1)).epsilon(1e-12));
    CHECK(r.F.at(emitter, receiver) == doctest::Approx(expected).epsilon(1e-5));
    CHECK(r.F.at(receiver, emitter) == doctest::Approx(expected / 2).epsilon(1e-5));  // reciprocity
    CHECK(r.counts.shadowTerms > 0);
}

TEST_CASE("Partial visibility: a blocker hiding half of a receiver leaves half its factor") {
    // C-11 unit squares at distance 1; a plate just in front of the receiver covers its half x > 0.
    // By symmetry the factor is half of C-11 (the 1e-3 gap moves the shadow's edge by 1e-3 x, whose
    // first-order effect cancels over the emitter).
    SceneBuilder b;
    const PatchId emitter = b.rectangle(2, 0, -0.5, 0.5, -0.5, 0.5, true);
    const PatchId receiver = b.rectangle(2, 1, -0.5, 0.5, -0.5, 0.5, false);
    b.rectangle(2, 0.999, 0.0, 0.7, -0.7, 0.7, false);
    const FormFactorRun r = analyticF(b.scene);
    MESSAGE("half-hidden receiver: F = " << r.F.at(emitter, receiver) << ", C-11 / 2 = " << c11(1, 1, 1) / 2);
    CHECK(r.F.at(emitter, receiver) == doctest::Approx(c11(1, 1, 1) / 2).epsilon(1e-4));
    CHECK(r.F.at(receiver, emitter) == doctest::Approx(c11(1, 1, 1) / 2).epsilon(1e-4));
}

TEST_CASE("Partial visibility: plates with a small blocker between them match superposition, whole and subdivided") {
    const double expected = platesPastBlocker();
    MESSAGE("plates past the blocker: " << expected << " (unblocked " << c11(1, 1, 1) << ")");
    for (const int n : {1, 4}) {
        CAPTURE(n);
        PatchId lower, upper;
        const Scene s = platesWithBlocker(n, lower, upper);
        const FormFactorRun r = analyticF(s);
        // The lower plate's factor to the upper one, area-weighted over its patches.
        double total = 0.0;
        for (PatchId i = lower; i < upper; ++i)
            for (PatchId j = upper; j < upper + PatchId(n * n); ++j) total += r.F.at(i, j) / double(n * n);
        MESSAGE("n = " << n << ": F = " << total << ", error " << total - expected);
        CHECK(total == doctest::Approx(expected).epsilon(1e-5));
        // Every patch of the upper plate sees some of the lower one past the blocker.
        for (PatchId j = upper; j < upper + PatchId(n * n); ++j) CHECK(r.F.rowSum(j) > 0.05);
    }
}
