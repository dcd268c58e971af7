// F whole in one process (see the header).
#include "thermal/exchange_rows.hpp"

#include "engine/error.hpp"
#include "thermal/thermal_solver.hpp"

#include <string>

namespace hemirad::thermal {

void ExchangeRows::requireAllRows() const {
    for (std::size_t i = 0; i < size(); ++i)
        if (!rowComputed(i))
            throw Error("thermal: row " + std::to_string(i) +
                        " of F was not computed; thermal exchange needs every row (compute F with --all-rows)");
}

std::vector<double> LocalRows::rowProducts(const std::vector<double>& x, const std::vector<double>* start) const {
    return heldRowProducts(m_F, [](std::size_t) { return true; }, x, start);
}

std::vector<double> LocalRows::columnSums(const std::vector<double>& w) const {
    return heldColumnSums(m_F, [](std::size_t) { return true; }, w);
}

BandSolution LocalRows::solve(const Scene& scene, const std::vector<Band>& bands, const SolverOptions& options) const {
    return solveBands(scene, m_F, bands, options);
}

SolverOptions LocalRows::solverOptions(const SolverOptions& options, std::size_t patches) const {
    return thermalSolverOptions(options, patches);
}

}  // namespace hemirad::thermal
