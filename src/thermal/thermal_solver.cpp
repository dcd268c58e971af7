// Net-radiation method (Siegel & Howell, "Thermal Radiation Heat Transfer", ch. 6; with specular
// surfaces through extended factors, Sillion & Puech 1989):
//   H_i = sum_j F_ij J_j + H_env,i,     H_env,i = sigma T_env^4 escape_i
//   known T:  J_i - rho_d,i sum_j F_ij J_j = eps_i sigma T_i^4 + rho_d,i H_env,i
//   known q:  J_i - (1 - s_i) sum_j F_ij J_j = q_i + (1 - s_i) H_env,i   (eps sigma T^4 = q + eps H)
// then q_i = eps_i (sigma T_i^4 - H_i) where T is known, T_i = ((q_i + eps_i H_i) / (eps_i sigma))^1/4
// where q is. Both are one linear system (I - R F) J = S: one band of solveBands.
#include "thermal/thermal_solver.hpp"

#include "engine/error.hpp"
#include "thermal/band_solver.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hemirad::thermal {

std::vector<double> escapeFractions(const ExchangeRows& F, const std::vector<double>& specular) {
    std::vector<double> absorbing(specular.size());
    for (std::size_t j = 0; j < specular.size(); ++j) absorbing[j] = 1.0 - specular[j];
    std::vector<double> escape = F.rowProducts(absorbing);
    for (double& e : escape) e = std::max(0.0, 1.0 - e);
    return escape;
}

std::vector<double> escapeFractions(const FormFactors& F, const std::vector<double>& specular) {
    return escapeFractions(LocalRows(F), specular);
}

namespace {

std::vector<double> specularOf(const ThermalModel& model) {
    std::vector<double> specular(model.surface.size());
    for (std::size_t i = 0; i < specular.size(); ++i) specular[i] = model.surface[i].specular;
    return specular;
}

}  // namespace

std::vector<double> escapeFractions(const FormFactors& F, const ThermalModel& model) {
    return escapeFractions(F, specularOf(model));
}

SolverOptions thermalSolverOptions(const SolverOptions& options, std::size_t patches) {
    SolverOptions o = options;
    if (o.solver == "auto") o.solver = patches <= 2000 ? "lu" : "bicgstab";
    return o;
}

ThermalSolution solveThermal(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                             const SolverOptions& given, const std::vector<const FormFactors*>& bandF) {
    std::vector<LocalRows> own;
    own.reserve(bandF.size());
    std::vector<const ExchangeRows*> bandRows;
    for (const FormFactors* f : bandF) {
        if (f) own.emplace_back(*f);
        bandRows.push_back(f ? &own.back() : nullptr);
    }
    return solveThermal(scene, LocalRows(F), model, given, bandRows);
}

ThermalSolution solveThermal(const Scene& scene, const ExchangeRows& F, const ThermalModel& model,
                             const SolverOptions& given, const std::vector<const ExchangeRows*>& bandF) {
    checkModel(scene, model);
    if (!model.bandEmissivity.empty() || hasEmissivityCurves(model)) return detail::solveBandModel(scene, F, model, given, bandF);
    return solveGrayThermal(scene, F, model, given);
}

ThermalSolution solveGrayThermal(const Scene& scene, const ExchangeRows& F, const ThermalModel& model,
                                 const SolverOptions& given) {
    checkModel(scene, model);
    if (!model.bandEmissivity.empty() || hasEmissivityCurves(model))
        throw Error("thermal: a band model or emissivities against temperature need F whole in one process");
    const SolverOptions options = F.solverOptions(given, scene.size());
    const std::size_t n = scene.size();
    if (F.size() != n)
        throw Error("thermal: F has " + std::to_string(F.size()) + " rows but the scene has " + std::to_string(n) + " patches");
    F.requireAllRows();

    ThermalSolution out;
    out.escape = escapeFractions(F, specularOf(model));
    const double sigma = kStefanBoltzmann;
    const double envT = model.environment.value_or(0.0);
    const double envExitance = sigma * envT * envT * envT * envT;
    const double m2 = model.metresPerUnit * model.metresPerUnit;
    auto external = [&](std::size_t i) { return model.absorbedExternal.empty() ? 0.0 : model.absorbedExternal[i]; };
    std::vector<double> environmentIrradiance(n);  // sigma T_env^4 escape_i, where each row's sum starts
    for (std::size_t i = 0; i < n; ++i) environmentIrradiance[i] = envExitance * out.escape[i];

    // Band 0: the known temperatures and fluxes, isothermal nodes at 0 K. Band 1 + k: node k's
    // patches emitting eps sigma T_ref^4, nothing else (the response to node k's temperature). The
    // system is linear in the nodes' T^4, so their net powers are affine in it: Q = Q0 + M t, and
    // M t = P - Q0 gives t = T^4 / T_ref^4. One factorisation serves every band.
    constexpr double kReferenceT4 = 300.0 * 300.0 * 300.0 * 300.0;
    const std::size_t nodes = model.isothermal.size();
    std::vector<Band> bands(1 + nodes);
    for (std::size_t b = 0; b < bands.size(); ++b) {
        bands[b].name = b == 0 ? "ir" : "ir node " + model.isothermal[b - 1].name;
        bands[b].rho.resize(n);
        bands[b].source.assign(n, 0.0);
    }
    bool anyTemperature = false;
    for (std::size_t i = 0; i < n; ++i) {
        const SurfaceProperties& sp = model.surface[i];
        const Condition& c = model.condition[i];
        const double Henv = envExitance * out.escape[i];
        double rho = std::max(0.0, sp.diffuse()), source = 0.0;
        if (c.kind == Condition::Kind::Temperature) {
            anyTemperature = true;
            const double T2 = c.value * c.value;
            source = sp.emissivity * sigma * T2 * T2 + rho * Henv;
        } else if (c.kind == Condition::Kind::Flux) {
            rho = 1.0 - sp.specular;
            source = c.value + external(i) + rho * Henv;  // the IR flux leaving carries the absorbed sun too
        } else {
            source = rho * Henv;
            bands[1 + c.node].source[i] = sp.emissivity * sigma * kReferenceT4;
        }
        for (Band& band : bands) band.rho[i] = rho;
        bands[0].source[i] = source;
    }
    // Without a temperature a closed enclosure (nothing seen of the environment, whether there is one
    // or not) fixes no temperature level: refused here on every process alike, before the solve
    // (where one process's LU finds the system singular, an iterative solve across ranks would not).
    if (!anyTemperature) {
        double open = 0.0;
        for (const double e : out.escape) open = std::max(open, e);
        if (open < 1e-6)
            throw Error(std::string("thermal: every surface has a heat-flux or power condition in a closed enclosure ") +
                        (model.environment ? "that sees nothing of the environment" : "and there is no environment") +
                        ": the temperatures are not determined (and exist only if the fluxes sum to 0); "
                        "give at least one object a temperature");
    }
    BandSolution solved;
    try {
        solved = F.solve(scene, bands, options);
    } catch (const Error& e) {
        const std::string what = e.what();
        if (what.find("singular") == std::string::npos) throw;
        throw Error("thermal: the radiosity system has no unique solution (" + what +
                    "); with only heat-flux conditions a closed enclosure needs one temperature or an environment");
    }
    out.report = solved.reports.at(0);
    for (const SolveReport& r : solved.reports)
        if (r.residualOriginal > out.report.residualOriginal) out.report.residualOriginal = r.residualOriginal;
    out.J = std::move(solved.X.at(0));
    out.isothermalT.assign(nodes, 0.0);
    if (nodes) {
        // Net power of each node per band: sum over its patches of A (J - (1 - s) H).
        auto nodePowers = [&](const std::vector<double>& J, bool withEnvironment) {
            const std::vector<double> FJ = F.rowProducts(J, withEnvironment ? &environmentIrradiance : nullptr);
            std::vector<double> Q(nodes, 0.0);
            for (std::size_t i = 0; i < n; ++i) {
                const Condition& c = model.condition[i];
                if (c.kind != Condition::Kind::Isothermal) continue;
                const double h = FJ[i];
                Q[c.node] += scene.patches[i].area * m2 * (J[i] - (1.0 - model.surface[i].specular) * h);
            }
            return Q;
        };
        const std::vector<double> Q0 = nodePowers(out.J, true);
        std::vector<double> absorbedByNode(nodes, 0.0);
        for (std::size_t i = 0; i < n; ++i)
            if (model.condition[i].kind == Condition::Kind::Isothermal)
                absorbedByNode[model.condition[i].node] += scene.patches[i].area * m2 * external(i);
        Eigen::MatrixXd M(nodes, nodes);
        Eigen::VectorXd rhs(nodes);
        for (std::size_t k = 0; k < nodes; ++k) {
            const std::vector<double> Qk = nodePowers(solved.X[1 + k], false);
            for (std::size_t I = 0; I < nodes; ++I) M(Eigen::Index(I), Eigen::Index(k)) = Qk[I];
            rhs[Eigen::Index(k)] = model.isothermal[k].power + absorbedByNode[k] - Q0[k];
        }
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
        if (lu.rank() < Eigen::Index(nodes))
            throw Error("thermal: the isothermal nodes' temperatures are not determined (their power balance is singular: "
                        "a closed enclosure of power conditions only); give at least one object a temperature");
        const Eigen::VectorXd t = lu.solve(rhs);
        for (std::size_t k = 0; k < nodes; ++k) {
            if (!(t[Eigen::Index(k)] >= 0.0)) {
                std::ostringstream msg;
                msg << "thermal: isothermal node '" << model.isothermal[k].name << "' would need T^4 < 0 to give off "
                    << model.isothermal[k].power << " W: it cannot absorb that much (no temperature solves it)";
                throw Error(msg.str());
            }
            out.isothermalT[k] = std::sqrt(std::sqrt(t[Eigen::Index(k)] * kReferenceT4));
            for (std::size_t i = 0; i < n; ++i) out.J[i] += t[Eigen::Index(k)] * solved.X[1 + k][i];
        }
    }

    // H from the solution, then q, T and Q per patch.
    out.H.assign(n, 0.0);
    out.T.assign(n, 0.0);
    out.q.assign(n, 0.0);
    out.Q.assign(n, 0.0);
    out.areaM2.assign(n, 0.0);
    double largest = 0.0;
    const std::vector<double> FJ = F.rowProducts(out.J, &environmentIrradiance);
    for (std::size_t i = 0; i < n; ++i) {
        const double h = FJ[i];
        out.H[i] = h;
        const SurfaceProperties& sp = model.surface[i];
        const Condition& c = model.condition[i];
        if (c.kind == Condition::Kind::Temperature || c.kind == Condition::Kind::Isothermal) {
            const double T = c.kind == Condition::Kind::Temperature ? c.value : out.isothermalT[c.node];
            out.T[i] = T;
            out.q[i] = sp.emissivity * (sigma * T * T * T * T - h) - external(i);
        } else {
            out.q[i] = c.value;
            if (sp.emissivity > 0.0) {
                const double T4 = (c.value + external(i) + sp.emissivity * h) / (sp.emissivity * sigma);
                if (T4 < 0.0) {
                    std::ostringstream msg;
                    msg << "thermal: patch " << i;
                    if (scene.patches[i].object < scene.objects.size())
                        msg << " (object '" << scene.objects[scene.patches[i].object] << "')";
                    msg << " has a net flux of " << c.value << " W/m^2 but receives only " << h
                        << " W/m^2: it would have to absorb more than it receives (no temperature solves it)";
                    throw Error(msg.str());
                }
                out.T[i] = std::sqrt(std::sqrt(T4));
            } else {
                out.T[i] = std::nan("");
            }
        }
        out.areaM2[i] = scene.patches[i].area * m2;
        out.Q[i] = out.q[i] * out.areaM2[i];
        largest = std::max(largest, std::abs(out.Q[i]));
    }

    // The environment: absorbs the part of each patch's emission that no surface absorbs (counted
    // from F's columns) and gives each patch sigma T_env^4 escape_i of irradiance.
    std::vector<double> absorbing(n);
    for (std::size_t i = 0; i < n; ++i) absorbing[i] = out.areaM2[i] * (1.0 - model.surface[i].specular);
    const std::vector<double> absorbedFrom = F.columnSums(absorbing);  // sum_i A_i F_ij (1 - s_i), per column j
    double toEnvironmentColumns = 0.0, toEnvironmentRows = 0.0, fromEnvironment = 0.0, sumQ = 0.0, fromOutside = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
        toEnvironmentColumns += out.J[j] * (out.areaM2[j] - absorbedFrom[j]);
        toEnvironmentRows += out.J[j] * out.areaM2[j] * out.escape[j];
        fromEnvironment += out.areaM2[j] * (1.0 - model.surface[j].specular) * envExitance * out.escape[j];
        sumQ += out.Q[j];
        fromOutside += out.areaM2[j] * external(j);
    }
    out.environmentPower = fromEnvironment - toEnvironmentColumns + fromOutside;
    const double scale = largest > 0.0 ? largest : 1.0;
    out.balance = std::abs(sumQ + out.environmentPower) / scale;
    out.reciprocityImbalance = std::abs(toEnvironmentColumns - toEnvironmentRows) / scale;
    return out;
}

}  // namespace hemirad::thermal
