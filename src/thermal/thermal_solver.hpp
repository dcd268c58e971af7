// Gray radiative exchange by the net-radiation (radiosity) method on the extended form factors:
// unknown diffuse radiosity J per patch, temperatures where fluxes are given, the environment node,
// and the energy balance. One IR band through the solver registry (solve/solver.hpp).
#pragma once

#include "engine/form_factors.hpp"
#include "solve/solver.hpp"
#include "thermal/exchange_rows.hpp"
#include "thermal/thermal_model.hpp"

#include <vector>

namespace hemirad::thermal {

/// Per patch (SI units) and the balance.
struct ThermalSolution {
    std::vector<double> T;  ///< K (NaN where eps = 0 and the flux is given: no temperature is defined)
    std::vector<double> J;  ///< diffuse radiosity, W/m^2
    std::vector<double> H;  ///< irradiance (from the scene and the environment), W/m^2
    std::vector<double> q;  ///< net heat flux leaving, W/m^2 (IR leaving minus the absorbed external heat)
    std::vector<double> Q;  ///< net power leaving, W
    std::vector<double> areaM2;  ///< patch areas, m^2
    std::vector<double> isothermalT;  ///< K, per isothermal node of the model
    /// 1 - sum_j F_ij (1 - s_j): the part of patch i's hemisphere through which the environment is
    /// seen (directly or through mirrors), from F's rows.
    std::vector<double> escape;
    /// Q_env: net power the environment gives the scene, W (its IR exchange, plus the absorbed
    /// external heat: the sun is part of the environment).
    double environmentPower = 0.0;
    /// |sum_i Q_i + Q_env| / max_i |Q_i|: the solve's residual as an energy balance. The environment's
    /// emission side is counted from F's columns (what the surfaces absorb of each patch's emission),
    /// so the balance is exact up to the solve, whatever F's reciprocity.
    double balance = 0.0;
    /// The same environment exchange counted from F's rows (what each patch sees escape): differs by
    /// F's reciprocity defect; |difference| / max |Q_i| is reported as this.
    double reciprocityImbalance = 0.0;
    SolveReport report;
};

/// Solves the model on `F` (the extended factors of `scene`, all rows computed). `options.solver`
/// picks the solver ("auto": LU up to 2000 patches). Throws hemirad::Error for an invalid model
/// (checkModel), a missing row, an enclosure whose temperatures are not determined (every patch
/// given a flux, closed, no environment), a flux that asks a surface to absorb more than it receives
/// (T^4 < 0), or an unconverged solve. `bandF`: with per-band specular reflectances
/// (ThermalModel::bandSpecular), each band's extended F (not owned; nullptr or absent: `F`, which
/// must then serve that band's reflectances).
ThermalSolution solveThermal(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                             const SolverOptions& options, const std::vector<const FormFactors*>& bandF = {});
/// The same on F as `F` holds it (one process, or rows across MPI ranks); bandF[k] likewise.
ThermalSolution solveThermal(const Scene& scene, const ExchangeRows& F, const ThermalModel& model,
                             const SolverOptions& options, const std::vector<const ExchangeRows*>& bandF = {});

/// The gray model (no bands, no emissivity curves: else hemirad::Error) on F as `F` holds it: in one
/// process (LocalRows) or across MPI ranks. solveThermal's errors.
ThermalSolution solveGrayThermal(const Scene& scene, const ExchangeRows& F, const ThermalModel& model,
                                 const SolverOptions& options);

/// The solver options thermal solves use: "auto" is lu up to 2000 patches, else bicgstab (conditions
/// of flux make rows of reflectance 1 - s, often 1, where stationary sweeps crawl; measured in
/// bench/thermal.sh); a named solver is kept.
SolverOptions thermalSolverOptions(const SolverOptions& options, std::size_t patches);

/// Per patch: 1 - sum_j F_ij (1 - s_j) (s from the model).
std::vector<double> escapeFractions(const FormFactors& F, const ThermalModel& model);
/// The same with the specular reflectances given per patch.
std::vector<double> escapeFractions(const FormFactors& F, const std::vector<double>& specular);
std::vector<double> escapeFractions(const ExchangeRows& F, const std::vector<double>& specular);

}  // namespace hemirad::thermal
