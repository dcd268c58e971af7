// Gebhart factors and radiative conductors: closure and reciprocity on exact (dyadic) extended F,
// a black enclosure gives B = F, mirrors included, and the exchange matrix sums to each node's Q.
#include "thermal/thermal_scenes.hpp"

#include "engine/subdivide.hpp"
#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"
#include "thermal/conductor_writers.hpp"
#include "thermal/gebhart.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;
using namespace hemirad::thermal;

namespace {

/// A scene and its F.
struct Enclosure {
    Scene scene;
    FormFactors F;
};

/// Three unit squares as an abstract closed enclosure (a long triangular duct's walls): F_ij = 1/2.
/// With `mirror`, patch 2 reflects s = 1/2 and sends what it reflects half to each other wall, so
/// the extended factors are F_0 = (1/8, 5/8, 1/2), F_1 = (5/8, 1/8, 1/2), F_2 = (1/2, 1/2, 0):
/// dyadic, exactly reciprocal, sum_j F_ij (1 - s_j) = 1.
Enclosure duct(bool mirror) {
    SceneBuilder b;
    b.scene.objects = {"a", "b", "c"};
    for (int k = 0; k < 3; ++k) b.rectangle(2, double(k), 0, 1, 0, 1, true);
    for (PatchId i = 0; i < 3; ++i) b.scene.patches[i].object = i;
    if (mirror) b.scene.patches[2].specular = 0.5;
    Enclosure d;
    d.scene = b.scene;
    d.F = mirror ? denseF({{0.125, 0.625, 0.5}, {0.625, 0.125, 0.5}, {0.5, 0.5, 0.0}})
                 : denseF({{0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}});
    return d;
}

/// An open cube (no ceiling) of 4 x 4 patches a face, 80 patches, and its F (every row).
Enclosure openCube() {
    Enclosure d;
    d.scene = subdivide(unitCube(), 0.25);
    std::vector<Patch> kept;
    for (const Patch& p : d.scene.patches)
        if (d.scene.parents[p.parent].sourcePatch != 1) kept.push_back(p);
    d.scene.patches = kept;
    d.F = computeFormFactors(d.scene, MethodSettings::of(HemisphereOptions{}), neededRows(d.scene, true)).F;
    return d;
}

ThermalModel modelFor(const Scene& s, std::vector<double> eps) {
    ThermalModel m;
    for (PatchId i = 0; i < s.size(); ++i) m.surface.push_back({eps[i], s.patches[i].specular});
    m.condition.assign(s.size(), Condition{Condition::Kind::Temperature, 300.0, 0});
    return m;
}

/// The same pairs in the same order (checked), and (max |GR - GR_reference|, max GR_reference).
std::pair<double, double> couplingDifference(const Conductors& c, const Conductors& reference) {
    REQUIRE(c.couplings.size() == reference.couplings.size());
    double worst = 0.0, largest = 0.0;
    for (std::size_t k = 0; k < c.couplings.size(); ++k) {
        CHECK(c.couplings[k].a == reference.couplings[k].a);
        CHECK(c.couplings[k].b == reference.couplings[k].b);
        worst = std::max(worst, std::abs(c.couplings[k].gr - reference.couplings[k].gr));
        largest = std::max(largest, reference.couplings[k].gr);
    }
    return {worst, largest};
}

double gr(const Conductors& c, std::uint32_t a, std::uint32_t b) {
    for (const Coupling& k : c.couplings)
        if (k.a == std::min(a, b) && k.b == std::max(a, b)) return k.gr;
    return 0.0;
}

}  // namespace

TEST_CASE("Gebhart factors close (sum_j B_ij = 1) and are reciprocal (eps_i A_i B_ij = eps_j A_j B_ji) to 1e-12, mirrors too") {
    for (const bool mirror : {false, true}) {
        CAPTURE(mirror);
        const Enclosure d = duct(mirror);
        const ThermalModel m = modelFor(d.scene, {0.9, 0.3, mirror ? 0.2 : 0.6});
        GebhartOptions o;
        o.lumping = Lumping::Patches;
        const Conductors c = computeConductors(d.scene, d.F, m, o, SolverOptions{});
        REQUIRE(c.B.size() == 3);
        double closure = 0, reciprocity = 0;
        for (std::size_t i = 0; i < 3; ++i) {
            double sum = 0;
            for (std::size_t j = 0; j < 3; ++j) {
                sum += c.B[i][j];
                reciprocity = std::max(reciprocity, std::abs(m.surface[i].emissivity * c.B[i][j] - m.surface[j].emissivity * c.B[j][i]));
            }
            closure = std::max(closure, std::abs(sum - 1.0));
            CHECK(c.B[i][3] <= 1e-12);  // nothing escapes a closed enclosure
        }
        MESSAGE("closure " << closure << ", reciprocity " << reciprocity << ", asymmetry " << c.asymmetry);
        CHECK(closure <= 1e-12);
        CHECK(reciprocity <= 1e-12);
        CHECK(c.asymmetry <= 1e-12);
        // Independent: B_01 from its defining equations B = F eps + F rho B, solved by iteration.
        std::vector<std::vector<double>> B(3, std::vector<double>(3, 0.0));
        for (int sweep = 0; sweep < 200; ++sweep)
            for (std::size_t i = 0; i < 3; ++i)
                for (std::size_t j = 0; j < 3; ++j) {
                    double v = d.F.at(i, j) * m.surface[j].emissivity;
                    for (std::size_t k = 0; k < 3; ++k) v += d.F.at(i, k) * m.surface[k].diffuse() * B[k][j];
                    B[i][j] = v;
                }
        for (std::size_t i = 0; i < 3; ++i)
            for (std::size_t j = 0; j < 3; ++j) CHECK(std::abs(B[i][j] - c.B[i][j]) <= 1e-12);
        // GR = eps_i A_i B_ij, symmetric.
        CHECK(std::abs(gr(c, 0, 1) - 0.9 * c.B[0][1]) <= 1e-12);
    }
}

TEST_CASE("A black enclosure's Gebhart factors are its form factors") {
    const Enclosure d = duct(false);
    const ThermalModel m = modelFor(d.scene, {1.0, 1.0, 1.0});
    GebhartOptions o;
    o.lumping = Lumping::Patches;
    const Conductors c = computeConductors(d.scene, d.F, m, o, SolverOptions{});
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j) CHECK(c.B[i][j] == relative(d.F.at(i, j), 1e-14));
}

TEST_CASE("Conductors lumped per object, with the environment, and the threshold's dropped sum") {
    // Objects floor and walls; the sky takes the rest.
    Enclosure open = openCube();
    Scene& s = open.scene;
    s.objects = {"floor", "walls"};
    for (Patch& p : s.patches) p.object = s.parents[p.parent].sourcePatch == 0 ? 0 : 1;
    const FormFactors& F = open.F;
    ThermalModel m;
    for (PatchId i = 0; i < s.size(); ++i) m.surface.push_back({s.patches[i].object == 0 ? 0.9 : 0.5, 0.0});
    m.condition.assign(s.size(), Condition{Condition::Kind::Temperature, 300.0, 0});
    const Conductors c = computeConductors(s, F, m, GebhartOptions{}, SolverOptions{});
    REQUIRE(c.nodes.size() == 2);
    CHECK(c.B[0][2] > 0.1);  // the open top
    // Black, B = F: each object's conductor to the sky is sum_i A_i (1 - sum_j F_ij) over its patches.
    ThermalModel black = m;
    for (SurfaceProperties& p : black.surface) p.emissivity = 1.0;
    const Conductors b = computeConductors(s, F, black, GebhartOptions{}, SolverOptions{});
    for (std::uint32_t I = 0; I < 2; ++I) {
        double sky = 0;
        for (PatchId i = 0; i < s.size(); ++i)
            if (s.patches[i].object == I) sky += s.patches[i].area * (1.0 - F.rowSum(i));
        CHECK(gr(b, I, 2) == relative(sky, 1e-9));
        CHECK(b.B[I][I] + b.B[I][1 - I] + b.B[I][2] == relative(1.0, 1e-9));
    }
    MESSAGE("floor-walls GR " << gr(c, 0, 1) << " m^2, asymmetry " << c.asymmetry);
    CHECK(c.asymmetry <= 1e-5);  // the solve to its tolerance

    GebhartOptions coarse;
    coarse.threshold = 0.99;
    const Conductors dropped = computeConductors(s, F, m, coarse, SolverOptions{});
    CHECK(dropped.couplings.empty());
    CHECK(dropped.dropped == 3);
    CHECK(std::abs(dropped.droppedSum - (gr(c, 0, 1) + gr(c, 0, 2) + gr(c, 1, 2))) <= 1e-12 * dropped.droppedSum);
}

TEST_CASE("Per-patch conductors: the same couplings from LU and from SOR's batched column sweeps, whatever the batch") {
    // The open cube of the previous case, each of its 80 patches a node: 3,160 pairs, completed as
    // their second column arrives, across batches that split the columns unevenly.
    const Enclosure open = openCube();
    const Scene& s = open.scene;
    const FormFactors& F = open.F;
    ThermalModel m;
    for (PatchId i = 0; i < s.size(); ++i) m.surface.push_back({0.3 + 0.6 * double(i % 5) / 4.0, 0.0});
    m.condition.assign(s.size(), Condition{Condition::Kind::Temperature, 300.0, 0});
    GebhartOptions o;
    o.lumping = Lumping::Patches;
    SolverOptions lu;
    lu.solver = "lu";
    const Conductors reference = computeConductors(s, F, m, o, lu);
    REQUIRE(reference.nodes.size() == 80);
    for (const std::size_t batch : {std::size_t(7), std::size_t(64)}) {
        CAPTURE(batch);
        o.batch = batch;
        SolverOptions sor;
        sor.solver = "sor";
        sor.tolerance = 1e-12;
        const Conductors c = computeConductors(s, F, m, o, sor);
        CHECK(c.report.solver == "sor");
        const auto [worst, largest] = couplingDifference(c, reference);
        CHECK(worst <= 1e-10 * largest);
        CHECK(std::abs(c.asymmetry - reference.asymmetry) <= 1e-8);
        for (std::size_t I = 0; I < 80; ++I) CHECK(c.self[I] == relative(reference.self[I], 1e-9));
    }
    // Every pair once, in (a, b) order, each node's environment coupling after its pairs.
    for (std::size_t k = 1; k < reference.couplings.size(); ++k) {
        const Coupling& p = reference.couplings[k - 1];
        const Coupling& q = reference.couplings[k];
        CHECK((p.a < q.a || (p.a == q.a && p.b < q.b)));
    }
    std::size_t pairs = 0;
    for (const Coupling& k : reference.couplings) pairs += k.b < 80;
    CHECK(pairs <= 80 * 79 / 2);
    CHECK(pairs > 80 * 79 / 4);  // most patches of the open cube see each other through reflections
}

TEST_CASE("One dense factorisation gives the column solves' conductors: diffuse, black and purely specular patches, per patch and per object") {
    // The open cube with every kind of row: diffuse gray (P), black (eps = 1) and mirrors that
    // reflect all they do not absorb (eps + s = 1): the last two have rho_d = 0 (Q), which the
    // dense route treats by its own blocks.
    Enclosure open = openCube();
    Scene& s = open.scene;
    auto mirror = [&](PatchId i) { return s.parents[s.patches[i].parent].sourcePatch == 2; };  // one wall
    for (PatchId i = 0; i < s.size(); ++i)
        if (mirror(i)) s.patches[i].specular = 0.85;
    const FormFactors F = computeFormFactors(s, MethodSettings::of(HemisphereOptions{}), neededRows(s, true)).F;
    ThermalModel m;
    for (PatchId i = 0; i < s.size(); ++i) {
        m.surface.push_back(mirror(i)     ? SurfaceProperties{0.15, 0.85}
                            : i % 3 == 0 ? SurfaceProperties{1.0, 0.0}
                                         : SurfaceProperties{0.2 + 0.7 * double(i % 7) / 6.0, 0.0});
    }
    m.condition.assign(s.size(), Condition{Condition::Kind::Temperature, 300.0, 0});
    s.objects = {"floor", "walls", "odd"};
    for (Patch& p : s.patches) p.object = s.parents[p.parent].sourcePatch == 0 ? 0 : 1;
    s.patches[5].object = s.patches[77].object = 2;  // an object of two patches far apart
    SolverOptions lu;
    lu.solver = "lu";
    for (const Lumping lumping : {Lumping::Patches, Lumping::Objects}) {
        CAPTURE(int(lumping));
        GebhartOptions o;
        o.lumping = lumping;
        o.method = GebhartMethod::Columns;
        const Conductors reference = computeConductors(s, F, m, o, lu);
        o.method = GebhartMethod::Dense;
        const Conductors c = computeConductors(s, F, m, o, SolverOptions{});
        CHECK(reference.method == GebhartMethod::Columns);
        CHECK(c.method == GebhartMethod::Dense);
        const auto [worst, largest] = couplingDifference(c, reference);
        MESSAGE("dense against columns: " << worst / largest << " of the largest of " << c.couplings.size()
                                          << " couplings; F's asymmetry " << c.asymmetry);
        // Equal patches and one computation per pair: F is reciprocal to the last bit, so the dense
        // route (which symmetrises S before solving) and the columns (GR after) agree to rounding.
        CHECK(c.asymmetry <= 1e-12);
        CHECK(worst <= 1e-12 * largest);
        for (std::size_t I = 0; I < c.self.size(); ++I) CHECK(std::abs(c.self[I] - reference.self[I]) <= 1e-12 * largest);
        CHECK(std::abs(c.escapeMax - reference.escapeMax) <= 1e-12);
    }
}

TEST_CASE("The dense route on an exactly reciprocal F: closure and reciprocity to 1e-12 with black and mirror rows, and a white enclosure refused") {
    // The duct's extended factors are exact; the mirror (patch 2) reflects s = 1/2 and absorbs the
    // rest (rho_d = 0), patch 1 is black: only patch 0 reflects diffusely.
    const Enclosure d = duct(true);
    const ThermalModel m = modelFor(d.scene, {0.4, 1.0, 0.5});
    GebhartOptions o;
    o.lumping = Lumping::Patches;
    o.method = GebhartMethod::Dense;
    const Conductors c = computeConductors(d.scene, d.F, m, o, SolverOptions{});
    // By hand: B_i1 = F_i1 + F_i0 rho_0 B_01, B_01 = F_01 / (1 - rho_0 F_00), rho_0 = 0.6.
    const double B01 = 0.625 / (1.0 - 0.6 * 0.125);
    CHECK(c.B[0][1] == relative(B01, 1e-14));
    CHECK(c.B[2][1] == relative(0.5 + 0.5 * 0.6 * B01, 1e-14));
    for (std::size_t i = 0; i < 3; ++i) {
        double sum = 0.0;
        for (std::size_t j = 0; j < 3; ++j) {
            sum += c.B[i][j];
            CHECK(std::abs(m.surface[i].emissivity * c.B[i][j] - m.surface[j].emissivity * c.B[j][i]) <= 1e-12);
        }
        CHECK(sum == relative(1.0, 1e-12));
    }
    // A mirror of s = 0.3 and eps = 0.7: rho = 1 - eps - s is a rounding leftover (5.6e-17), not a
    // diffuse reflector with W = A / rho = 1.8e16 A, whose self term would cancel to nonsense. The
    // columns (LU) are the reference on the same F (F_00 = s/4, F_01 = 1/2 + s/4: the duct's mirror
    // sends half of what it reflects to each other wall).
    Enclosure leftover = duct(false);
    leftover.scene.patches[2].specular = 0.3;
    leftover.F = denseF({{0.075, 0.575, 0.5}, {0.575, 0.075, 0.5}, {0.5, 0.5, 0.0}});
    const ThermalModel hair = modelFor(leftover.scene, {0.4, 1.0, 0.7});
    REQUIRE(hair.surface[2].diffuse() > 0.0);
    REQUIRE(hair.surface[2].diffuse() < 1e-15);
    const Conductors h = computeConductors(leftover.scene, leftover.F, hair, o, SolverOptions{});
    GebhartOptions byColumns = o;
    byColumns.method = GebhartMethod::Columns;
    SolverOptions lu;
    lu.solver = "lu";
    const Conductors hc = computeConductors(leftover.scene, leftover.F, hair, byColumns, lu);
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(h.B[i][0] + h.B[i][1] + h.B[i][2] == relative(1.0, 1e-9));
        for (std::size_t j = 0; j < 4; ++j) CHECK(std::abs(h.B[i][j] - hc.B[i][j]) <= 1e-12);
    }
    // White walls (eps = s = 0) alone: every ray reflects forever; no conductor exists.
    const Enclosure plain = duct(false);
    const ThermalModel white = modelFor(plain.scene, {0.0, 0.0, 0.0});
    CHECK_THROWS_WITH_AS(computeConductors(plain.scene, plain.F, white, o, SolverOptions{}),
                         doctest::Contains("singular"), Error);
}

TEST_CASE("The exchange matrix between objects sums to each object's net power") {
    const Enclosure d = duct(true);
    ThermalModel m = modelFor(d.scene, {0.9, 0.3, 0.2});
    m.condition[0].value = 500;
    m.condition[1] = Condition{Condition::Kind::Flux, 100.0, 0};
    const ThermalSolution sol = solveThermal(d.scene, d.F, m, SolverOptions{});
    std::vector<std::string> names;
    std::vector<std::vector<PatchId>> nodes;
    makeNodes(d.scene, Lumping::Objects, names, nodes);
    const auto Q = exchangeMatrix(d.scene, d.F, m, sol, nodes, SolverOptions{});
    for (std::size_t I = 0; I < 3; ++I) {
        double total = 0;
        for (const double q : Q[I]) total += q;
        CHECK(std::abs(total - sol.Q[I]) <= 1e-9 * 100.0);
        for (std::size_t J = 0; J < 3; ++J) CHECK(Q[I][J] == relative(-Q[J][I], 1e-12));
    }
}

TEST_CASE("Conductor files: ESATAN GR lines, a SINDA conductor block, Matrix Market and CSV name the same couplings") {
    const Enclosure d = duct(false);
    const ThermalModel m = modelFor(d.scene, {0.9, 0.3, 0.6});
    const Conductors c = computeConductors(d.scene, d.F, m, GebhartOptions{}, SolverOptions{});
    const auto dir = tempDir("conductors");
    for (const std::string& format : conductorFormats()) writeConductors((dir / ("gr." + format)).string(), format, c);
    const std::string esatan = readText(dir / "gr.esatan"), sinda = readText(dir / "gr.sinda");
    const std::string mtx = readText(dir / "gr.mtx"), csv = readText(dir / "gr.csv");
    // Each GR in the shortest text that reads back to the same double.
    const auto after = [](const std::string& text, const std::string& key) {
        const std::size_t at = text.find(key);
        REQUIRE(at != std::string::npos);
        return std::stod(text.substr(at + key.size()));
    };
    CHECK(after(esatan, "GR(1, 2) = ") == gr(c, 0, 1));
    CHECK(esatan.find("GR(1, 2) = " + std::to_string(gr(c, 0, 1)).substr(0, 6)) != std::string::npos);
    CHECK(sinda.find("HEADER CONDUCTOR DATA") != std::string::npos);
    CHECK(after(sinda, "-1, 1, 2, ") == gr(c, 0, 1));
    CHECK(mtx.find("%%MatrixMarket matrix coordinate real symmetric") == 0);
    CHECK(mtx.find("\n4 4 3\n") != std::string::npos);
    CHECK(csv.find("node_a,node_b,GR (m^2)\na,b,") == 0);
    CHECK(conductorFormatFor("model.ESATAN") == "esatan");
    CHECK(conductorFormatFor("radk.inp") == "sinda");
    CHECK(conductorFormatFor("gr.txt").empty());
}
