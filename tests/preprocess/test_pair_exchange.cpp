// Each pair computed once: the exchange that hands a pair's terms from its emitting row to the
// other row, and F equal bit for bit whichever rows found their terms handed over.
#include "support.hpp"

#include "engine/subdivide.hpp"
#include "preprocess/backend_registry.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "preprocess/hemisphere/pair_exchange.hpp"

#include <doctest/doctest.h>

#include <thread>

using namespace hemirad;
using namespace hemirad::test;

TEST_CASE("Pair exchange: an emitter's entries reach rows opened after it finished, and no others") {
    PairExchange exchange(6, [](PatchId r) { return r != 5; });
    std::vector<PairExchange::Entry> entries;
    // Row 3 opens before emitter 0 finishes: nothing for it, and 0 does not count as finished.
    const std::uint64_t early = exchange.open(3, entries);
    CHECK(entries.empty());
    CHECK_FALSE(exchange.finished(0, early));
    exchange.publish(0, {{2, 0.25f}, {3, 0.0f}, {4, 0.5f}, {5, 0.75f}});  // 3 is closed, 5 is not wanted here
    CHECK(exchange.held() == 2);
    CHECK_FALSE(exchange.finished(0, early));
    const std::uint64_t later = exchange.open(4, entries);
    REQUIRE(entries.size() == 1);
    CHECK(PatchId(entries[0].patch) == 0);  // copies: doctest binds a reference, and Entry is packed
    CHECK(double(entries[0].value) == 0.5);
    CHECK(exchange.finished(0, later));
    CHECK_FALSE(exchange.finished(1, later));  // never published
    // A hidden pair (value 0) is an entry too: row 2 learns that 0 had a term for it.
    exchange.publish(1, {{2, 0.0f}});
    exchange.open(2, entries);
    REQUIRE(entries.size() == 2);
    CHECK(double(entries[0].value) == 0.25);
    CHECK(PatchId(entries[1].patch) == 1);
    CHECK(double(entries[1].value) == 0.0);
    CHECK(exchange.held() == 0);
    // Row 5 was not wanted when 0 published: 0's absence from its list says nothing.
    CHECK(exchange.open(5, entries) == 0);
    CHECK(entries.empty());
    CHECK_FALSE(exchange.finished(0, 0));
    // A row opened again (listed twice) trusts no absence either.
    CHECK(exchange.open(4, entries) == 0);
}

TEST_CASE("Pair exchange: a row the source hands out only later is not taken for one without terms") {
    // An MPI rank's queue: row 1 is pushed after row 0 finished, so row 0 kept nothing for it.
    bool pushed = false;
    PairExchange exchange(2, [&pushed](PatchId r) { return r == 0 || pushed; });
    std::vector<PairExchange::Entry> entries;
    exchange.open(0, entries);
    exchange.publish(0, {{1, 0.5f}});
    pushed = true;
    const std::uint64_t ticket = exchange.open(1, entries);
    CHECK(entries.empty());
    CHECK_FALSE(exchange.finished(0, ticket));  // row 1 recomputes the pair
}

TEST_CASE("Pair exchange: rows published and opened on several threads lose no entry") {
    const PatchId n = 400;
    PairExchange exchange(n, [](PatchId) { return true; });
    std::vector<int> seen(std::size_t(n) * n, 0);  // [receiver][emitter]: 1 handed over, 2 finished without entry
    auto work = [&](PatchId first) {
        std::vector<PairExchange::Entry> entries;
        std::vector<PairExchange::Entry> receivers;
        for (PatchId e = first; e < n; e += 2) {
            const std::uint64_t ticket = exchange.open(e, entries);
            for (const auto& entry : entries) {
                CHECK(double(entry.value) == double(entry.patch) + 0.5);
                seen[std::size_t(e) * n + entry.patch] = 1;
            }
            for (PatchId j = 0; j < e; ++j)
                if (exchange.finished(j, ticket) && !seen[std::size_t(e) * n + j]) seen[std::size_t(e) * n + j] = 2;
            receivers.clear();
            for (PatchId r = e + 1; r < n; ++r) receivers.push_back({r, float(e) + 0.5f});  // every later row
            exchange.publish(e, receivers);
        }
    };
    std::thread a(work, 0), b(work, 1);
    a.join();
    b.join();
    // An emitter that counted as finished had published to every later row: none is missing.
    int handed = 0;
    for (std::size_t k = 0; k < seen.size(); ++k) {
        CHECK(seen[k] != 2);
        handed += seen[k] == 1;
    }
    MESSAGE(handed << " of " << n * (n - 1) / 2 << " pairs handed over");
    CHECK(handed > n * (n - 1) / 4);
}

namespace {

/// F of the hemisphere back end's analytic estimator with the rows in one list (pairs handed over)
/// or one row per call (every row recomputes the pairs its row did not hand over).
FormFactors analyticRows(const Scene& scene, int threads, bool rowByRow, RayCounts& counts) {
    HemisphereOptions o;
    o.estimator = Estimator::Analytic;
    CommonOptions common;
    common.threads = threads;
    auto backend = makeBackend(MethodSettings::of(o, common));
    backend->prepare(scene);
    FormFactorBuilder builder(scene);
    std::vector<PatchId> rows(scene.size());
    for (PatchId i = 0; i < scene.size(); ++i) rows[i] = i;
    if (rowByRow) {
        for (const PatchId i : rows) backend->computeRows(std::vector<PatchId>{i}, builder);
    } else {
        backend->computeRows(rows, builder);
    }
    counts = builder.counts();
    return builder.finish();
}

}  // namespace

TEST_CASE("Each pair once: F with pairs handed between rows equals F with every pair computed by both rows, bit for bit") {
    // The closed Cornell box with its blocks (shadow rays, exact visible parts and silhouette splits
    // both ways) and the Cornell box with its mirror (image terms handed over or recomputed from the
    // emitter along the reversed chains), 1 and 2 threads.
    for (const std::string name : {"cornell_closed.obj", "cornell_mirror.obj"}) {
        CAPTURE(name);
        const Scene s = subdivide(bundledScene(name), 150.0);
        RayCounts separate, once, twoThreads;
        const FormFactors reference = analyticRows(s, 1, true, separate);
        const FormFactors F = analyticRows(s, 1, false, once);
        const FormFactors F2 = analyticRows(s, 2, false, twoThreads);
        MESSAGE(name << ", " << s.size() << " patches; shadow rays " << separate.rays << " row by row, " << once.rays
                     << " with pairs handed over (" << twoThreads.rays << " on 2 threads); exact terms "
                     << separate.shadowTerms << " / " << once.shadowTerms);
        CHECK(F.rowStarts() == reference.rowStarts());
        CHECK(F.columnVector() == reference.columnVector());
        CHECK(F.valueVector() == reference.valueVector());  // float == float: bit for bit but for -0 and NaN
        CHECK(F2.columnVector() == reference.columnVector());
        CHECK(F2.valueVector() == reference.valueVector());
        // The work the exchanges save: row by row, each pair's rays and exact terms (through the
        // mirror too) are cast by both of its rows (the corner probes for straddling pairs by both
        // rows either way: 0.73 on the closed box, 0.64 before them).
        CHECK(double(once.rays) < 0.75 * double(separate.rays));
        CHECK(once.penumbralPairs > 0);  // pairs in a penumbra, weighed alike by both rows
        CHECK(double(once.shadowTerms) < 0.7 * double(separate.shadowTerms));
    }
}

TEST_CASE("Each pair once: pairs in a penumbra (centroid and far rule) and emitters a block covers in part, bit for bit both ways") {
    // Plates of 16 x 16 patches at z = 0 (up) and z = 1 (down): their pairs are far (one point
    // each, the far rule or the centroid pass). A 4 x 4 blocker at z = 0.5 casts penumbrae on the
    // upper plate, probed from the emitters' corners; a flat block (four walls and a roof) stands
    // across some lower patches, not on their edges, so that they integrate over their free parts.
    SceneBuilder b;
    const int n = 16;
    const double h = 1.0 / n;
    for (const bool up : {true, false})
        for (int u = 0; u < n; ++u)
            for (int v = 0; v < n; ++v)
                b.rectangle(2, up ? 0 : 1, -0.5 + h * u, -0.5 + h * (u + 1), -0.5 + h * v, -0.5 + h * (v + 1), up);
    for (int u = 0; u < 4; ++u)
        for (int v = 0; v < 4; ++v)
            b.rectangle(2, 0.5, -0.25 + 0.125 * u, -0.25 + 0.125 * (u + 1), -0.25 + 0.125 * v, -0.25 + 0.125 * (v + 1), false);
    const double x0 = -0.47, x1 = -0.2, y0 = 0.1, y1 = 0.4, top = 0.05;
    b.rectangle(0, x0, y0, y1, 0, top, false);
    b.rectangle(0, x1, y0, y1, 0, top, true);
    b.rectangle(1, y0, 0, top, x0, x1, false);
    b.rectangle(1, y1, 0, top, x0, x1, true);
    b.rectangle(2, top, x0, x1, y0, y1, true);
    RayCounts separate, once, twoThreads;
    const FormFactors reference = analyticRows(b.scene, 1, true, separate);
    const FormFactors F = analyticRows(b.scene, 1, false, once);
    const FormFactors F2 = analyticRows(b.scene, 2, false, twoThreads);
    MESSAGE(b.scene.size() << " patches; penumbra computations " << separate.penumbralPairs << " row by row, "
                           << once.penumbralPairs << " handed over; covered rows " << once.coveredRows);
    CHECK(once.penumbralPairs > 0);
    CHECK(once.coveredRows > 0);
    CHECK(F.rowStarts() == reference.rowStarts());
    CHECK(F.columnVector() == reference.columnVector());
    CHECK(F.valueVector() == reference.valueVector());
    CHECK(F2.columnVector() == reference.columnVector());
    CHECK(F2.valueVector() == reference.valueVector());
}
