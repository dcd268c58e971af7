// F whole in one process (see the header).
#include "thermal/exchange_rows.hpp"

#include "engine/error.hpp"
#include "thermal/thermal_solver.hpp"

namespace hemirad::thermal {

void ExchangeRows::requireAllRows(const std::string& whose) const {
    for (std::size_t i = 0; i < size(); ++i)
        if (!rowComputed(i))
            throw Error("thermal: row " + std::to_string(i) + " of " + (whose.empty() ? std::string("F") : whose + "F") +
                        " was not computed; thermal exchange needs every row (compute F with --all-rows)");
}

std::vector<double> LocalRows::rowProducts(const std::vector<double>& x, const std::vector<double>* start) const {
    const std::size_t n = m_F.size();
    std::vector<double> y(n, 0.0);
    const float* values = m_F.values();
    const std::uint32_t* columns = m_F.columns();
    for (std::size_t i = 0; i < n; ++i) {
        double h = start ? (*start)[i] : 0.0;
        for (std::uint64_t k = m_F.rowBegin(i); k < m_F.rowEnd(i); ++k) h += double(values[k]) * x[columns[k]];
        y[i] = h;
    }
    return y;
}

std::vector<double> LocalRows::columnSums(const std::vector<double>& w) const {
    const std::size_t n = m_F.size();
    std::vector<double> sums(n, 0.0);
    const float* values = m_F.values();
    const std::uint32_t* columns = m_F.columns();
    for (std::size_t i = 0; i < n; ++i)
        for (std::uint64_t k = m_F.rowBegin(i); k < m_F.rowEnd(i); ++k) sums[columns[k]] += w[i] * double(values[k]);
    return sums;
}

BandSolution LocalRows::solve(const Scene& scene, const std::vector<Band>& bands, const SolverOptions& options) const {
    return solveBands(scene, m_F, bands, options);
}

SolverOptions LocalRows::solverOptions(const SolverOptions& options, std::size_t patches) const {
    return thermalSolverOptions(options, patches);
}

}  // namespace hemirad::thermal
