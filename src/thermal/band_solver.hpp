// Non-gray IR exchange (ThermalModel::bandEmissivity): the bands' linear systems on one F, coupled
// through the temperatures where fluxes or powers are given. Called by solveThermal.
#pragma once

#include "thermal/thermal_solver.hpp"

namespace hemirad::thermal::detail {

/// Also the gray model whose emissivities follow the temperatures (ThermalModel::emissivityCurves):
/// one band, each step's reflectances and emission from the emissivities at the current
/// temperatures, each unknown temperature from a balance with the emissivities at that temperature.
/// Starts from the gray solution with the reference-weighted emissivities, then iterates: the
/// bands' radiosities for the current temperatures (one solveBands call, each band's emission
/// eps_k F(lambda_k -> lambda_k+1, T) sigma T^4), then each unknown temperature from its own
/// balance given the bands' irradiances (bisection: the emitted power grows with T at every
/// wavelength), Anderson-accelerated; until no temperature moves by 1e-12 relative. Band k runs on
/// bandF[k] where given (its own specular reflectances: ThermalModel::bandSpecular), else on F; in one
/// process or across MPI ranks as F holds its rows (one group of bands sharing F: one solve call).
ThermalSolution solveBandModel(const Scene& scene, const ExchangeRows& F, const ThermalModel& model,
                               const SolverOptions& options, const std::vector<const ExchangeRows*>& bandF = {});

}  // namespace hemirad::thermal::detail
