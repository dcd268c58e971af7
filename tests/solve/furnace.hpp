// Test support: the closed-box furnace, B = E / (1 - rho) for E = 1 and one rho everywhere.
#pragma once

#include "solve/solver.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace hemirad::test {

/// max |B_i (1 - rho) - 1| (red channel) of `s` (E = 1, rho everywhere) solved by `solver` to 1e-12.
inline double furnaceError(const Scene& s, const FormFactors& F, const std::string& solver, double rho) {
    SolverOptions o;
    o.solver = solver;
    o.tolerance = 1e-12;
    o.maxIterations = 100000;
    const Radiosity r = solveRadiosity(s, F, o);
    double worst = 0.0;
    for (const Rgb& b : r.B) worst = std::max(worst, std::abs(b[0] * (1 - rho) - 1.0));
    return worst;
}

}  // namespace hemirad::test
