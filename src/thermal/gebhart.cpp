// Gebhart factors by columns: for a node J, C solves (I - R_d F) C = eps 1_J (one radiosity band
// whose only emitters are J's patches, each emitting eps), and X = F C holds sum_{j in J} B_ij for
// every patch i (B = F (I - R_d F)^-1 diag(eps), so B 1_J = F C). Nodes go through solveBands in
// batches, one factorisation serving a batch.
#include "thermal/gebhart.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

namespace hemirad::thermal {
namespace {

constexpr std::size_t kDenseTableNodes = 4096;

/// Calls visit(J, X) for every node J, X[i] = sum_{j in J} B_ij.
void forEachNodeColumn(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                       const std::vector<std::vector<PatchId>>& members, std::size_t batch, const SolverOptions& given,
                       SolveReport& report, const std::function<void(std::size_t, const std::vector<double>&)>& visit) {
    const SolverOptions solver = thermalSolverOptions(given, scene.size());
    checkModel(scene, model);
    const std::size_t n = scene.size();
    if (F.size() != n) throw Error("thermal: F does not belong to this scene (" + std::to_string(F.size()) + " rows)");
    for (std::size_t i = 0; i < n; ++i)
        if (!F.rowComputed(i))
            throw Error("thermal: row " + std::to_string(i) + " of F was not computed; Gebhart factors need every row "
                        "(compute F with --all-rows)");
    std::vector<double> rho(n);
    for (std::size_t i = 0; i < n; ++i) rho[i] = std::max(0.0, model.surface[i].diffuse());
    batch = std::max<std::size_t>(1, batch);
    std::vector<double> X(n);
    for (std::size_t first = 0; first < members.size(); first += batch) {
        const std::size_t last = std::min(members.size(), first + batch);
        std::vector<Band> bands(last - first);
        for (std::size_t J = first; J < last; ++J) {
            Band& band = bands[J - first];
            band.name = "node " + std::to_string(J);
            band.rho = rho;
            band.source.assign(n, 0.0);
            for (const PatchId i : members[J]) band.source[i] = model.surface[i].emissivity;
        }
        const BandSolution solved = solveBands(scene, F, bands, solver);
        if (!solved.reports.empty()) report = solved.reports.back();
        for (std::size_t J = first; J < last; ++J) {
            const std::vector<double>& C = solved.X[J - first];
#pragma omp parallel for schedule(dynamic, 256)
            for (std::int64_t i = 0; i < std::int64_t(n); ++i) {
                double x = 0.0;
                for (std::uint64_t k = F.rowBegin(std::size_t(i)); k < F.rowEnd(std::size_t(i)); ++k)
                    x += double(F.values()[k]) * C[F.columns()[k]];
                X[std::size_t(i)] = x;
            }
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

    // GR_IJ for every node J (columns), and what each node I absorbs in all: the rest escapes.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<double, double>> pairs;  // (a<b) -> (GR_ab, GR_ba)
    std::vector<double> absorbedBySurfaces(K, 0.0);
    std::vector<double>& self = out.self;
    self.assign(K, 0.0);
    std::vector<double> column(K);
    forEachNodeColumn(scene, F, model, out.members, options.batch, solver, out.report,
                      [&](std::size_t J, const std::vector<double>& X) {
                          std::fill(column.begin(), column.end(), 0.0);
                          for (std::size_t i = 0; i < n; ++i) column[nodeOf[i]] += epsArea[i] * X[i];
                          for (std::size_t I = 0; I < K; ++I) {
                              if (column[I] == 0.0) continue;
                              absorbedBySurfaces[I] += column[I];
                              if (I == J) {
                                  self[I] = column[I];
                                  continue;
                              }
                              const auto key = std::make_pair(std::uint32_t(std::min(I, J)), std::uint32_t(std::max(I, J)));
                              auto& v = pairs[key];
                              (I < J ? v.first : v.second) = column[I];
                          }
                      });

    const bool table = K <= kDenseTableNodes;
    if (table) out.B.assign(K, std::vector<double>(K + 1, 0.0));
    double largest = 0.0, worst = 0.0;
    for (const auto& [key, v] : pairs) {
        largest = std::max({largest, v.first, v.second});
        worst = std::max(worst, std::abs(v.first - v.second));
    }
    out.asymmetry = largest > 0.0 ? worst / largest : 0.0;
    auto keep = [&](std::uint32_t a, std::uint32_t b, double gr) {
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
        out.couplings.push_back({a, b, gr});
    };
    auto next = pairs.begin();
    for (std::uint32_t a = 0; a < K; ++a) {
        for (; next != pairs.end() && next->first.first == a; ++next) {
            const double gr = 0.5 * (next->second.first + next->second.second);
            if (gr > 0.0) keep(a, next->first.second, gr);
        }
        // The environment: the emission of node a that no surface absorbs (self-absorption included).
        const double escaped = out.emittingArea[a] - absorbedBySurfaces[a];
        if (out.emittingArea[a] > 0.0) out.escapeMax = std::max(out.escapeMax, escaped / out.emittingArea[a]);
        if (escaped > 1e-12 * out.emittingArea[a]) keep(a, std::uint32_t(K), escaped);
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
