// Gebhart factors by columns: for a node J, C solves (I - R_d F) C = eps 1_J (one radiosity band
// whose only emitters are J's patches, each emitting eps), and X = F C holds sum_{j in J} B_ij for
// every patch i (B = F (I - R_d F)^-1 diag(eps), so B 1_J = F C). Nodes go through solveBands in
// batches, one factorisation serving a batch.
#include "thermal/gebhart.hpp"

#include "engine/error.hpp"
#include "engine/memory.hpp"
#include "thermal/patch_conductance.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace hemirad::thermal {
namespace {

constexpr std::size_t kDenseTableNodes = 4096;

/// The column solves' solver: `auto` is LU up to 2,000 patches (one factorisation serves every
/// batch), else SOR, which sweeps a batch's columns together in one pass over F (the system has the
/// diffuse reflectances 1 - eps - s and no flux rows; thermal's own auto, BiCGSTAB, would solve them
/// one by one). A white patch (eps = s = 0) has reflectance 1; enclosed by such patches alone, the
/// system is singular and solveBands says so.
SolverOptions columnSolverOptions(const SolverOptions& given, std::size_t patches) {
    SolverOptions o = given;
    if (o.solver == "auto") o.solver = patches <= 2000 ? "lu" : "sor";
    return o;
}

void checkInputs(const Scene& scene, const FormFactors& F, const ThermalModel& model) {
    checkModel(scene, model);
    const std::size_t n = scene.size();
    if (F.size() != n) throw Error("thermal: F does not belong to this scene (" + std::to_string(F.size()) + " rows)");
    for (std::size_t i = 0; i < n; ++i)
        if (!F.rowComputed(i))
            throw Error("thermal: row " + std::to_string(i) + " of F was not computed; Gebhart factors need every row "
                        "(compute F with --all-rows)");
}

/// The route for `nodes` nodes: as asked, or under Auto the dense factorisation when it fits in the
/// memory a direct solver may use and is expected to be faster; a column solver named by the user
/// keeps the columns.
GebhartMethod gebhartMethod(const Scene& scene, const FormFactors& F, const ThermalModel& model, std::size_t nodes,
                            GebhartMethod asked, const SolverOptions& solver) {
    if (asked != GebhartMethod::Auto) return asked;
    if (solver.solver != "auto") return GebhartMethod::Columns;
    // A diffuse reflectance in (1e-12, 1e-6): W = A / rho would cost the self terms 1e-16 / rho.
    for (const SurfaceProperties& p : model.surface)
        if (p.diffuse() > 1e-12 && p.diffuse() < 1e-6) return GebhartMethod::Columns;
    const std::size_t limit = solver.memoryLimit ? solver.memoryLimit : availableMemory() / 10 * 8;
    // The factorisation, the lumped table or every pair's coupling (kept while it is alive).
    const std::size_t held = nodes < scene.size() ? nodes * nodes * sizeof(double) : nodes * (nodes + 1) / 2 * sizeof(Coupling);
    if (PatchConductance::memoryBytes(scene.size()) + held > limit) return GebhartMethod::Columns;
    return PatchConductance::pays(scene.size(), nodes, F.nonZeros()) ? GebhartMethod::Dense : GebhartMethod::Columns;
}

/// Every pair of nodes from one dense factorisation (PatchConductance): calls keep(I, J, GR_IJ) for
/// I < J with GR_IJ > 0 in (I, J) order, and rowDone(I) after node I's pairs, when what surfaces
/// absorb of its emission (absorbed[I]) is complete; fills each node's self term. Returns F's
/// reciprocity defect.
double denseCouplings(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                      const std::vector<std::vector<PatchId>>& members, const std::vector<std::uint32_t>& nodeOf,
                      std::vector<double>& self, std::vector<double>& absorbed,
                      const std::function<void(std::uint32_t, std::uint32_t, double)>& keep,
                      const std::function<void(std::uint32_t)>& rowDone) {
    checkInputs(scene, F, model);
    const std::size_t n = scene.size(), K = members.size();
    const double m2 = model.metresPerUnit * model.metresPerUnit;
    std::vector<double> area(n), eps(n), rho(n);
    for (std::size_t i = 0; i < n; ++i) {
        area[i] = scene.patches[i].area * m2;
        eps[i] = model.surface[i].emissivity;
        rho[i] = std::max(0.0, model.surface[i].diffuse());
    }
    const PatchConductance G(F, area, eps, rho);
    bool eachPatch = K == n;
    for (std::size_t I = 0; eachPatch && I < K; ++I) eachPatch = members[I].size() == 1 && members[I][0] == I;
    // Node pairs: read from G directly when every patch is a node, else summed into a K x K table.
    std::vector<double> lumped;
    if (!eachPatch) {
        lumped.assign(K * K, 0.0);
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t i = j; i < n; ++i) {
                const double g = G(i, j);
                lumped[nodeOf[i] * K + nodeOf[j]] += g;
                if (i != j) lumped[nodeOf[j] * K + nodeOf[i]] += g;
            }
    }
    auto gr = [&](std::size_t I, std::size_t J) { return eachPatch ? G(I, J) : lumped[I * K + J]; };
    for (std::size_t I = 0; I < K; ++I) {
        self[I] = gr(I, I);
        absorbed[I] += self[I];
        for (std::size_t J = I + 1; J < K; ++J) {
            const double g = gr(I, J);
            absorbed[I] += g;
            absorbed[J] += g;
            if (g > 0.0) keep(std::uint32_t(I), std::uint32_t(J), g);
        }
        rowDone(std::uint32_t(I));
    }
    return G.asymmetry();
}

/// Calls visit(J, X) for every node J, X[i] = sum_{j in J} B_ij.
void forEachNodeColumn(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                       const std::vector<std::vector<PatchId>>& members, std::size_t batch, const SolverOptions& given,
                       SolveReport& report, const std::function<void(std::size_t, const std::vector<double>&)>& visit) {
    const SolverOptions solver = columnSolverOptions(given, scene.size());
    checkInputs(scene, F, model);
    const std::size_t n = scene.size();
    std::vector<double> rho(n);
    for (std::size_t i = 0; i < n; ++i) rho[i] = std::max(0.0, model.surface[i].diffuse());
    batch = std::max<std::size_t>(1, batch);
    std::vector<double> X(n), C, FC;
    for (std::size_t first = 0; first < members.size(); first += batch) {
        const std::size_t last = std::min(members.size(), first + batch), width = last - first;
        std::vector<Band> bands(width);
        for (std::size_t J = first; J < last; ++J) {
            Band& band = bands[J - first];
            band.name = "node " + std::to_string(J);
            band.rho = rho;
            band.source.assign(n, 0.0);
            for (const PatchId i : members[J]) band.source[i] = model.surface[i].emissivity;
        }
        const BandSolution solved = solveBands(scene, F, bands, solver);
        if (!solved.reports.empty()) report = solved.reports.back();
        // F C for the batch's columns in one pass over F.
        C.resize(n * width);
        for (std::size_t b = 0; b < width; ++b)
            for (std::size_t j = 0; j < n; ++j) C[j * width + b] = solved.X[b][j];
        multiplyInterleaved(F, width, C.data(), FC);
        for (std::size_t J = first; J < last; ++J) {
            for (std::size_t i = 0; i < n; ++i) X[i] = FC[i * width + (J - first)];
            visit(J, X);
        }
    }
}

}  // namespace

void makeNodes(const Scene& scene, Lumping lumping, std::vector<std::string>& names,
               std::vector<std::vector<PatchId>>& members) {
    names.clear();
    members.clear();
    if (lumping == Lumping::Patches) {
        for (PatchId i = 0; i < scene.size(); ++i) {
            names.push_back("patch " + std::to_string(i));
            members.push_back({i});
        }
        return;
    }
    std::vector<std::vector<PatchId>> byObject(scene.objects.size());
    for (PatchId i = 0; i < scene.size(); ++i) byObject.at(scene.patches[i].object).push_back(i);
    for (std::size_t o = 0; o < byObject.size(); ++o)
        if (!byObject[o].empty()) {
            names.push_back(scene.objects[o]);
            members.push_back(std::move(byObject[o]));
        }
}

Conductors computeConductors(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                             const GebhartOptions& options, const SolverOptions& solver) {
    if (!(options.threshold >= 0.0) || !(options.threshold < 1.0))
        throw Error("thermal: the coupling threshold must be in [0, 1), got " + std::to_string(options.threshold));
    Conductors out;
    makeNodes(scene, options.lumping, out.nodes, out.members);
    const std::size_t K = out.nodes.size(), n = scene.size();
    const double m2 = model.metresPerUnit * model.metresPerUnit;
    std::vector<std::uint32_t> nodeOf(n);
    std::vector<double> epsArea(n);
    out.emittingArea.assign(K, 0.0);
    for (std::size_t I = 0; I < K; ++I)
        for (const PatchId i : out.members[I]) {
            nodeOf[i] = std::uint32_t(I);
            epsArea[i] = model.surface[i].emissivity * scene.patches[i].area * m2;
            out.emittingArea[I] += epsArea[i];
        }

    // GR_IJ for every pair of nodes, and what each node I absorbs in all: the rest escapes.
    const bool table = K <= kDenseTableNodes;
    if (table) out.B.assign(K, std::vector<double>(K + 1, 0.0));
    auto keep = [&](std::uint32_t a, std::uint32_t b, double gr, std::vector<Coupling>& kept) {
        const double Ba = out.emittingArea[a] > 0 ? gr / out.emittingArea[a] : 0.0;
        const double Bb = b < K && out.emittingArea[b] > 0 ? gr / out.emittingArea[b] : 0.0;
        if (table) {
            out.B[a][b < K ? b : K] = Ba;
            if (b < K) out.B[b][a] = Bb;
        }
        if (Ba < options.threshold && Bb < options.threshold) {
            ++out.dropped;
            out.droppedSum += gr;
            return;
        }
        kept.push_back({a, b, gr});
    };
    std::vector<double> absorbedBySurfaces(K, 0.0);
    std::vector<double>& self = out.self;
    self.assign(K, 0.0);
    // The environment: the emission of node a that no surface absorbs (self-absorption included).
    auto closeNode = [&](std::uint32_t a) {
        const double escaped = out.emittingArea[a] - absorbedBySurfaces[a];
        if (out.emittingArea[a] > 0.0) out.escapeMax = std::max(out.escapeMax, escaped / out.emittingArea[a]);
        if (escaped > 1e-12 * out.emittingArea[a]) keep(a, std::uint32_t(K), escaped, out.couplings);
    };
    out.method = gebhartMethod(scene, F, model, K, options.method, solver);
    if (out.method == GebhartMethod::Dense) {
        // In their final order, each node's environment coupling after its pairs. Every coupling is
        // kept without a threshold: reserved at once, in huge pages.
        if (options.threshold == 0.0) {
            out.couplings.reserve(K * (K + 1) / 2);
            adviseHugePages(out.couplings.data(), out.couplings.capacity() * sizeof(Coupling));
        }
        out.asymmetry = denseCouplings(
            scene, F, model, out.members, nodeOf, self, absorbedBySurfaces,
            [&](std::uint32_t a, std::uint32_t b, double gr) { keep(a, b, gr, out.couplings); }, closeNode);
    } else {
        // Column by column: a pair I < J is complete when column J arrives. GR_JI waits for it in
        // waiting[J], left there by column I, so at most the pairs of the columns still to come are held.
        std::vector<std::vector<std::pair<std::uint32_t, double>>> waiting(K);  // waiting[J]: (I < J, GR_JI)
        std::vector<Coupling> pairs;  // kept pairs between surfaces, in the order they completed
        std::vector<double> column(K), other(K, 0.0);
        double largest = 0.0, worst = 0.0;
        forEachNodeColumn(scene, F, model, out.members, options.batch, solver, out.report,
                          [&](std::size_t J, const std::vector<double>& X) {
                              std::fill(column.begin(), column.end(), 0.0);
                              for (std::size_t i = 0; i < n; ++i) column[nodeOf[i]] += epsArea[i] * X[i];
                              for (const auto& [I, gr] : waiting[J]) other[I] = gr;
                              for (std::size_t I = 0; I < K; ++I) {
                                  if (column[I] != 0.0) absorbedBySurfaces[I] += column[I];
                                  if (I == J) {
                                      self[I] = column[I];
                                  } else if (I > J) {
                                      if (column[I] != 0.0) waiting[I].push_back({std::uint32_t(J), column[I]});
                                  } else if (column[I] != 0.0 || other[I] != 0.0) {  // GR_IJ and GR_JI
                                      largest = std::max({largest, column[I], other[I]});
                                      worst = std::max(worst, std::abs(column[I] - other[I]));
                                      const double gr = 0.5 * (column[I] + other[I]);
                                      if (gr > 0.0) keep(std::uint32_t(I), std::uint32_t(J), gr, pairs);
                                  }
                              }
                              for (const auto& entry : waiting[J]) other[entry.first] = 0.0;
                              std::vector<std::pair<std::uint32_t, double>>().swap(waiting[J]);
                          });
        out.asymmetry = largest > 0.0 ? worst / largest : 0.0;
        auto before = [](const Coupling& x, const Coupling& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; };
        std::sort(pairs.begin(), pairs.end(), before);
        auto next = pairs.begin();
        out.couplings.reserve(pairs.size() + K);
        for (std::uint32_t a = 0; a < K; ++a) {
            for (; next != pairs.end() && next->a == a; ++next) out.couplings.push_back(*next);
            closeNode(a);
        }
    }
    if (table)  // the self term: what a node absorbs of its own emission (mirrors, concave objects)
        for (std::size_t I = 0; I < K; ++I)
            if (out.emittingArea[I] > 0.0) out.B[I][I] = self[I] / out.emittingArea[I];
    return out;
}

std::vector<std::vector<double>> exchangeMatrix(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                                                const ThermalSolution& solution,
                                                const std::vector<std::vector<PatchId>>& nodes, const SolverOptions& solver) {
    const std::size_t K = nodes.size(), n = scene.size();
    if (solution.T.size() != n) throw Error("thermal: the solution does not belong to this scene");
    const double sigma = kStefanBoltzmann, m2 = model.metresPerUnit * model.metresPerUnit;
    const double envT = model.environment.value_or(0.0), envT4 = envT * envT * envT * envT;
    std::vector<std::uint32_t> nodeOf(n, std::uint32_t(K));
    for (std::size_t I = 0; I < K; ++I)
        for (const PatchId i : nodes[I]) nodeOf.at(i) = std::uint32_t(I);
    std::vector<double> emitted(n), epsArea(n), absorbedAll(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const double T = std::isfinite(solution.T[i]) ? solution.T[i] : 0.0;
        epsArea[i] = model.surface[i].emissivity * scene.patches[i].area * m2;
        emitted[i] = sigma * epsArea[i] * T * T * T * T;
    }
    std::vector<std::vector<double>> gross(K + 1, std::vector<double>(K + 1, 0.0));  // gross[I][J]: I's emission absorbed by J
    SolveReport report;
    forEachNodeColumn(scene, F, model, nodes, 64, solver, report, [&](std::size_t J, const std::vector<double>& X) {
        for (std::size_t i = 0; i < n; ++i) {
            if (nodeOf[i] == K) continue;
            gross[nodeOf[i]][J] += emitted[i] * X[i];
            absorbedAll[i] += X[i];
        }
    });
    for (std::size_t i = 0; i < n; ++i) {
        if (nodeOf[i] == K) continue;
        const double escape = 1.0 - absorbedAll[i];
        gross[nodeOf[i]][K] += emitted[i] * escape;
        gross[K][nodeOf[i]] += sigma * envT4 * epsArea[i] * escape;  // reciprocity with the environment
    }
    std::vector<std::vector<double>> Q(K, std::vector<double>(K + 1, 0.0));
    for (std::size_t I = 0; I < K; ++I)
        for (std::size_t J = 0; J <= K; ++J) Q[I][J] = J == I ? 0.0 : gross[I][J] - gross[J][I];
    return Q;
}

}  // namespace hemirad::thermal
