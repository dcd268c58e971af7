// Each pair from its emitting row: receiver entries replaced, added and removed as the emitting row
// has them, rows without a computed partner left alone.
#include "allocation_failure.hpp"
#include "support.hpp"

#include "engine/emitted_pairs.hpp"

#include <doctest/doctest.h>
#include <omp.h>

using namespace hemirad;
using namespace hemirad::test;

TEST_CASE("Receiver entries take their emitting row's value (replaced, added, removed), and rows without a computed emitter keep theirs") {
    // Areas 1 < 2 < 4 < 8: patch 0 emits for all, 1 for 2 and 3, 2 for 3.
    SceneBuilder b;
    b.rectangle(2, 0, 0, 1, 0, 1, true);
    b.rectangle(2, 1, 0, 2, 0, 1, false);
    b.rectangle(0, 0, 0, 2, 0, 2, true);
    b.rectangle(0, 5, 0, 4, 0, 2, false);
    const Scene& s = b.scene;
    REQUIRE(emitsFor(s, 0, 1));
    REQUIRE(emitsFor(s, 1, 2));
    REQUIRE(!emitsFor(s, 3, 2));
    using E = FormFactors::Entry;
    std::vector<std::vector<E>> rows = {
        {{1, 0.2f}, {2, 0.1f}},             // row 0 emits: F_01, F_02 (no pair with 3)
        {{0, 0.11f}, {2, 0.05f}, {3, 0.3f}}, // row 1: F_10 disagrees (0.1 expected), emits F_12, F_13
        {{0, 0.02f}, {1, 0.025f}},          // row 2: F_20 (0.025 expected), F_21 = 0.025 as emitted
        {{0, 0.01f}},                       // row 3: F_30 has no emitted partner (row 0 lacks 3): removed
    };
    std::vector<std::uint8_t> computed = {1, 1, 1, 1};
    FormFactors F = FormFactors::fromRows(std::move(rows), computed);
    const EmittedPairsReport report = takePairsFromEmitters(F, s);
    CHECK(F.at(1, 0) == relative(0.2 * 1 / 2, 1e-7));
    CHECK(F.at(2, 0) == relative(0.1 * 1 / 4, 1e-7));
    CHECK(F.at(2, 1) == relative(0.05 * 2 / 4, 1e-7));
    CHECK(F.at(3, 1) == relative(0.3 * 2 / 8, 1e-7));  // added: row 3 lacked it
    CHECK(F.at(3, 0) == 0.0);                                         // removed: row 0 has no entry for 3
    CHECK(F.at(0, 1) == 0.2f);                                        // emitted entries stay as computed
    CHECK(F.at(1, 3) == 0.3f);
    for (PatchId i = 0; i < 4; ++i)
        for (PatchId j = 0; j < 4; ++j)
            if (i != j && F.at(i, j) > 0.0)
                CHECK(std::abs(s.patches[i].area * F.at(i, j) - s.patches[j].area * F.at(j, i)) <=
                      1.2e-7 * s.patches[i].area * F.at(i, j));
    CHECK(report.added == 1);
    CHECK(report.removed == 1);
    CHECK(report.changed == 4);  // F_10, F_20, F_31 added, F_30 removed; F_21 was right already
    CHECK(report.pairs == 5);

    // Row 0 not computed: the others keep their own entries for it.
    std::vector<std::vector<E>> again = {{}, {{0, 0.11f}}, {{0, 0.02f}}, {}};
    FormFactors G = FormFactors::fromRows(std::move(again), {0, 1, 1, 1});
    takePairsFromEmitters(G, s);
    CHECK(G.at(1, 0) == 0.11f);
    CHECK(G.at(2, 0) == 0.02f);
}

TEST_CASE("An out-of-memory while the entries a receiver lacks are collected is an exception, never std::terminate") {
    // Each thread's list of those entries grew inside an OpenMP region with no try around it: a
    // failure ended in std::terminate, which aborts this test. One thread, so that the region's only
    // thread is the calling one, whose allocations fail in turn.
    SceneBuilder b;
    b.rectangle(2, 0, 0, 1, 0, 1, true);
    b.rectangle(2, 1, 0, 2, 0, 1, false);
    const Scene& s = b.scene;
    REQUIRE(emitsFor(s, 0, 1));
    using E = FormFactors::Entry;
    const FormFactors lacking = FormFactors::fromRows(std::vector<std::vector<E>>{{{1, 0.2f}}, {}}, {1, 1});
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const FailureSweep sweep = failEachAllocation([&] {
        FormFactors F = lacking;
        takePairsFromEmitters(F, s);
    });
    omp_set_num_threads(threads);
    CHECK(sweep.failures > 0);
    CHECK(sweep.outOfMemory == sweep.failures);
    FormFactors F = lacking;
    CHECK(takePairsFromEmitters(F, s).added == 1);
    CHECK(F.at(1, 0) == relative(0.2 * 1 / 2, 1e-7));
}

TEST_CASE("A row that its emitters' values carry above the row-sum bound is scaled to it, and counted") {
    SceneBuilder b;
    b.rectangle(2, 0, 0, 1, 0, 1, true);   // area 1, emits for patch 1
    b.rectangle(2, 1, 0, 2, 0, 1, false);  // area 2
    using E = FormFactors::Entry;
    // Row 0 says F_01 = 0.9, so F_10 = 0.45; row 1 had 0.3 and 0.6 elsewhere: 1.05 after the pass.
    std::vector<std::vector<E>> rows = {{{1, 0.9f}}, {{0, 0.3f}, {1, 0.6f}}};
    FormFactors F = FormFactors::fromRows(std::move(rows), {1, 1});
    F.provenance.rowSumBound = 1.0;
    const EmittedPairsReport report = takePairsFromEmitters(F, b.scene);
    CHECK(report.rescaledRows == 1);
    CHECK(report.largestRowSum == relative(1.05, 1e-6));
    CHECK(F.rowSum(1) == relative(1.0, 1e-6));
    CHECK(F.at(1, 0) == relative(0.45 / 1.05, 1e-6));
    CHECK(F.rowSum(0) == relative(0.9, 1e-7));  // within the bound: untouched
    validateFormFactors(F, 2, "test", rowSumBound(F));           // F files accept it
}
