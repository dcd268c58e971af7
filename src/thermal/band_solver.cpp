// Non-gray (banded) IR exchange by a fixed point on the unknown temperatures, Anderson-accelerated
// (Walker & Ni 2011), each step one linear radiosity solve per band (Siegel & Howell, the band
// energy approximation: within a band every property is gray).
#include "thermal/band_solver.hpp"

#include "engine/error.hpp"
#include "thermal/blackbody.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace hemirad::thermal::detail {
namespace {

constexpr int kMaxIterations = 300;
constexpr double kTolerance = 1e-12;
constexpr std::size_t kHistory = 6;

/// The T >= 0 at which g crosses 0 upwards, by bisection (g increases with constant emissivities);
/// NaN where g stays above 0 (the surface would have to absorb more than it receives).
template <class G>
double temperatureWhere(G g) {
    double a = 0.0;
    if (g(0.0) > 0.0) {
        // With emissivities against temperature the absorbed eps(T) H can grow faster than the
        // emitted eps(T) sigma T^4 (a surface giving off less than it receives): look for a
        // temperature below the balance before giving up.
        for (double T = 1.0; T < 1e6 && !(a > 0.0); T *= 1.05)
            if (g(T) <= 0.0) a = T;
        if (!(a > 0.0)) return std::nan("");
    }
    double b = a > 0.0 ? 2.0 * a : 300.0;
    while (g(b) < 0.0) {
        a = b;
        b *= 2.0;
        if (b > 1e9) throw Error("thermal: no temperature below 1e9 K gives the power a surface must emit");
    }
    for (int step = 0; step < 200 && b - a > 1e-15 * b; ++step) {
        const double m = 0.5 * (a + b);
        (g(m) < 0.0 ? a : b) = m;
    }
    return 0.5 * (a + b);
}

}  // namespace

ThermalSolution solveBandModel(const Scene& scene, const ExchangeRows& F, const ThermalModel& model,
                               const SolverOptions& given, const std::vector<const ExchangeRows*>& bandF) {
    const SolverOptions options = F.solverOptions(given, scene.size());
    // Bands with limits, or one gray band whose emissivities follow the temperatures (curves).
    const bool curves = model.bandEmissivity.empty();
    const std::size_t n = scene.size(), K = curves ? 1 : model.bandEmissivity.size(), nodes = model.isothermal.size();
    std::vector<double> lo(K), hi(K);
    for (std::size_t k = 0; k < K; ++k) {
        lo[k] = k ? model.bandLimitsUm[k - 1] : 0.0;
        hi[k] = k < model.bandLimitsUm.size() ? model.bandLimitsUm[k] : std::numeric_limits<double>::infinity();
    }
    auto eps = [&](std::size_t k, std::size_t i, double T) {
        return curves ? emissivityAt(model, i, T) : model.bandEmissivity[k][i];
    };
    // Whether patch i emits at some temperature.
    auto emits = [&](std::size_t i) {
        if (!curves) {
            double any = 0.0;
            for (std::size_t k = 0; k < K; ++k) any += model.bandEmissivity[k][i];
            return any > 0.0;
        }
        const std::int32_t c = model.curveOf.empty() ? -1 : model.curveOf[i];
        if (c < 0) return model.surface[i].emissivity > 0.0;
        const std::vector<double>& e = model.emissivityCurves[std::size_t(c)].emissivity;
        return *std::max_element(e.begin(), e.end()) > 0.0;
    };
    auto external = [&](std::size_t i) { return model.absorbedExternal.empty() ? 0.0 : model.absorbedExternal[i]; };
    const double m2 = model.metresPerUnit * model.metresPerUnit;
    const double envT = model.environment.value_or(0.0), sigma = kStefanBoltzmann;

    // The gray start (also the check of the conditions: closed enclosures of fluxes, and so on).
    ThermalModel gray = model;
    gray.bandEmissivity.clear();
    gray.bandLimitsUm.clear();
    gray.bandSpecular.clear();
    gray.curveOf.clear();
    // A curve's value at the known temperature, else at the reference one, or the curve's largest
    // where it is 0 there (a surface that emits at other temperatures needs a defined start).
    for (std::size_t i = 0; i < n && curves; ++i) {
        const bool known = model.condition[i].kind == Condition::Kind::Temperature;
        double& e = gray.surface[i].emissivity;
        e = emissivityAt(model, i, known ? model.condition[i].value : model.referenceTemperature);
        if (!known && !(e > 0.0) && emits(i)) {
            const std::vector<double>& values = model.emissivityCurves[std::size_t(model.curveOf[i])].emissivity;
            e = *std::max_element(values.begin(), values.end());
        }
    }
    ThermalSolution out = solveGrayThermal(scene, F, gray, options);

    // Each band's F (its own where its specular reflectances differ from the scene's) and what of
    // each patch's view escapes to the environment in that band.
    std::vector<const ExchangeRows*> Fk(K, &F);
    std::vector<std::vector<double>> specular(K, std::vector<double>(n)), escape(K);
    for (std::size_t k = 0; k < K; ++k) {
        if (k < bandF.size() && bandF[k]) Fk[k] = bandF[k];
        if (Fk[k] == &F && !curves && bandNeedsOwnFormFactors(scene, model, k))
            throw Error("thermal: IR band " + std::to_string(k + 1) + "'s specular reflectances differ from the scene's, "
                        "which F was computed with: the band needs its own F");
        if (Fk[k]->size() != n)
            throw Error("thermal: IR band " + std::to_string(k + 1) + "'s F has " + std::to_string(Fk[k]->size()) +
                        " rows for " + std::to_string(n) + " patches");
        for (std::size_t i = 0; i < n; ++i) {
            if (!Fk[k]->rowComputed(i))
                throw Error("thermal: row " + std::to_string(i) + " of IR band " + std::to_string(k + 1) + "'s F was not computed");
            specular[k][i] = curves ? model.surface[i].specular : specularIn(model, k, i);
        }
        escape[k] = escapeFractions(*Fk[k], specular[k]);
    }

    // The unknowns: flux patches' and nodes' temperatures, x = (T_free..., T_node...).
    std::vector<std::size_t> free;
    for (std::size_t i = 0; i < n; ++i)
        if (model.condition[i].kind == Condition::Kind::Flux && emits(i)) free.push_back(i);
    const std::size_t m = free.size() + nodes;
    auto temperatureOf = [&](const Eigen::VectorXd& x, std::size_t i) {
        const Condition& c = model.condition[i];
        if (c.kind == Condition::Kind::Temperature) return c.value;
        if (c.kind == Condition::Kind::Isothermal) return x[Eigen::Index(free.size() + c.node)];
        const auto at = std::lower_bound(free.begin(), free.end(), i);
        return at != free.end() && *at == i ? x[at - free.begin()] : 0.0;
    };
    Eigen::VectorXd x = Eigen::VectorXd::Zero(Eigen::Index(m));
    for (std::size_t f = 0; f < free.size(); ++f)
        x[Eigen::Index(f)] = std::isfinite(out.T[free[f]]) ? out.T[free[f]] : model.referenceTemperature;
    for (std::size_t k = 0; k < nodes; ++k) x[Eigen::Index(free.size() + k)] = out.isothermalT[k];

    std::vector<Band> bands(K);
    std::vector<std::vector<double>> J(K, std::vector<double>(n, 0.0)), H(K, std::vector<double>(n, 0.0));
    for (std::size_t k = 0; k < K; ++k) {
        bands[k].name = curves ? std::string("ir") : "ir band " + std::to_string(k + 1);
        bands[k].rho.resize(n);
        bands[k].source.resize(n);
    }
    const double envT4 = sigma * envT * envT * envT * envT;
    std::vector<double> envShare(K);
    for (std::size_t k = 0; k < K; ++k) envShare[k] = bandFraction(lo[k], hi[k], envT) * envT4;

    // One step of the fixed point: the bands for the temperatures x, then the temperatures.
    SolveReport report;
    auto step = [&](const Eigen::VectorXd& xs) {
        for (std::size_t k = 0; k < K; ++k) {
            for (std::size_t i = 0; i < n; ++i) {
                const double T = temperatureOf(xs, i), e = eps(k, i, T);
                bands[k].rho[i] = std::max(0.0, 1.0 - e - specular[k][i]);
                bands[k].source[i] = e * bandFraction(lo[k], hi[k], T) * sigma * T * T * T * T +
                                     bands[k].rho[i] * envShare[k] * escape[k][i];
            }
            bands[k].initial = &J[k];
        }
        // The bands that share an F in one solveBands call (all of them, without their own F).
        std::vector<bool> done(K, false);
        bool first = true;
        for (std::size_t k0 = 0; k0 < K; ++k0) {
            if (done[k0]) continue;
            std::vector<std::size_t> group;
            std::vector<Band> shared;
            for (std::size_t k = k0; k < K; ++k)
                if (Fk[k] == Fk[k0]) group.push_back(k), shared.push_back(std::move(bands[k])), done[k] = true;
            BandSolution solved = Fk[k0]->solve(scene, shared, options);
            for (std::size_t g = 0; g < group.size(); ++g) {
                bands[group[g]] = std::move(shared[g]);
                J[group[g]] = std::move(solved.X[g]);
            }
            if (first) report = solved.reports.front(), first = false;
            for (const SolveReport& r : solved.reports) report.residualOriginal = std::max(report.residualOriginal, r.residualOriginal);
        }
        for (std::size_t k = 0; k < K; ++k) {
            std::vector<double> start(n);
            for (std::size_t i = 0; i < n; ++i) start[i] = envShare[k] * escape[k][i];
            H[k] = Fk[k]->rowProducts(J[k], &start);
        }
        // Each unknown temperature from its own balance: the IR it gives off less what it absorbs
        // (both with the emissivities at that temperature) equals its net flux or power.
        Eigen::VectorXd next = Eigen::VectorXd::Zero(Eigen::Index(m));
        auto netLeaving = [&](std::size_t i, double T) {
            double net = 0.0;
            for (std::size_t k = 0; k < K; ++k)
                net += eps(k, i, T) * (bandFraction(lo[k], hi[k], T) * sigma * T * T * T * T - H[k][i]);
            return net;
        };
        for (std::size_t f = 0; f < free.size(); ++f) {
            const std::size_t i = free[f];
            const double target = model.condition[i].value + external(i);
            const double T = temperatureWhere([&](double t) { return netLeaving(i, t) - target; });
            if (std::isnan(T)) {
                std::ostringstream msg;
                msg << "thermal: patch " << i << " has a net flux of " << model.condition[i].value
                    << " W/m^2 but would have to absorb more than it receives (no temperature solves it)";
                throw Error(msg.str());
            }
            next[Eigen::Index(f)] = T;
        }
        for (std::size_t node = 0; node < nodes; ++node) {
            std::vector<std::size_t> members;
            double target = model.isothermal[node].power;
            for (std::size_t i = 0; i < n; ++i) {
                const Condition& cond = model.condition[i];
                if (cond.kind != Condition::Kind::Isothermal || cond.node != node) continue;
                members.push_back(i);
                target += scene.patches[i].area * m2 * external(i);
            }
            const double T = temperatureWhere([&](double t) {
                double net = -target;
                for (const std::size_t i : members) net += scene.patches[i].area * m2 * netLeaving(i, t);
                return net;
            });
            if (std::isnan(T))
                throw Error("thermal: isothermal node '" + model.isothermal[node].name +
                            "' would have to absorb more than it receives (no temperature solves it)");
            next[Eigen::Index(free.size() + node)] = T;
        }
        return next;
    };

    // Anderson acceleration of x <- step(x) (type II, the last kHistory differences).
    std::vector<Eigen::VectorXd> dx, dr;
    Eigen::VectorXd previousX, previousR;
    int iteration = 0;
    bool converged = m == 0;
    for (; iteration < kMaxIterations; ++iteration) {
        const Eigen::VectorXd g = step(x);
        if (m == 0) break;
        const Eigen::VectorXd r = g - x;
        double change = 0.0;
        for (Eigen::Index f = 0; f < r.size(); ++f) change = std::max(change, std::abs(r[f]) / std::max(x[f], 1.0));
        if (change <= kTolerance) {
            x = g;
            converged = true;
            step(x);  // the bands for the final temperatures
            break;
        }
        if (iteration > 0) {
            dx.push_back(x - previousX);
            dr.push_back(r - previousR);
            if (dx.size() > kHistory) {
                dx.erase(dx.begin());
                dr.erase(dr.begin());
            }
        }
        previousX = x;
        previousR = r;
        Eigen::VectorXd nextX = g;
        if (!dr.empty()) {
            Eigen::MatrixXd D(r.size(), Eigen::Index(dr.size())), X(r.size(), Eigen::Index(dx.size()));
            for (std::size_t h = 0; h < dr.size(); ++h) {
                D.col(Eigen::Index(h)) = dr[h];
                X.col(Eigen::Index(h)) = dx[h];
            }
            const Eigen::VectorXd gamma = D.colPivHouseholderQr().solve(r);
            nextX = g - (X + D) * gamma;
        }
        for (Eigen::Index f = 0; f < nextX.size(); ++f) x[f] = nextX[f] > 0.0 ? nextX[f] : 0.5 * g[f];  // stay physical
    }
    if (!converged && !options.allowUnconverged) {
        std::ostringstream msg;
        msg << "thermal: the band model's temperatures did not settle in " << kMaxIterations
            << " iterations (to 1e-12); pass --allow-unconverged to take them";
        throw Error(msg.str());
    }

    // The results from the bands.
    out.report = report;
    out.report.iterations = iteration + 1;
    out.report.note = (curves ? std::string("emissivity against temperature: ") : "band model: " + std::to_string(K) + " bands, ") +
                      std::to_string(iteration + 1) + " iterations";
    out.isothermalT.assign(nodes, 0.0);
    for (std::size_t k = 0; k < nodes; ++k) out.isothermalT[k] = x[Eigen::Index(free.size() + k)];
    double largest = 0.0, sumQ = 0.0, environment = 0.0;
    std::vector<std::vector<double>> absorbedFrom(K);  // per band: F's columns
    for (std::size_t k = 0; k < K; ++k) {
        std::vector<double> w(n);
        for (std::size_t i = 0; i < n; ++i) w[i] = out.areaM2[i] * (1.0 - specular[k][i]);
        absorbedFrom[k] = Fk[k]->columnSums(w);
    }
    for (std::size_t i = 0; i < n; ++i) {
        const Condition& c = model.condition[i];
        double Ji = 0.0, Hi = 0.0, net = 0.0;
        const double T = c.kind == Condition::Kind::Flux && !std::binary_search(free.begin(), free.end(), i)
                             ? std::nan("")
                             : temperatureOf(x, i);
        for (std::size_t k = 0; k < K; ++k) {
            Ji += J[k][i];
            Hi += H[k][i];
            const double Tk = std::isnan(T) ? 0.0 : T;
            net += eps(k, i, Tk) * (bandFraction(lo[k], hi[k], Tk) * sigma * Tk * Tk * Tk * Tk - H[k][i]);
            environment += out.areaM2[i] * (1.0 - specular[k][i]) * envShare[k] * escape[k][i] -
                           J[k][i] * (out.areaM2[i] - absorbedFrom[k][i]);
        }
        out.T[i] = T;
        out.J[i] = Ji;
        out.H[i] = Hi;
        out.q[i] = c.kind == Condition::Kind::Flux ? c.value : net - external(i);
        out.Q[i] = out.q[i] * out.areaM2[i];
        largest = std::max(largest, std::abs(out.Q[i]));
        sumQ += out.Q[i];
        environment += out.areaM2[i] * external(i);
    }
    out.environmentPower = environment;
    out.balance = std::abs(sumQ + environment) / (largest > 0.0 ? largest : 1.0);
    out.reciprocityImbalance = 0.0;
    return out;
}

}  // namespace hemirad::thermal::detail
