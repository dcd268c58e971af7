// What the gray thermal solve and the solar band need of F: products with its rows, sums down its
// columns, and the bands' linear solves. One process holds F whole (LocalRows); under mpirun each
// rank holds its own rows (mpi/distributed_thermal.hpp), and every result comes back whole on every
// rank, so the solves' bookkeeping (temperatures, the environment, the balance) runs unchanged.
#pragma once

#include "engine/form_factors.hpp"
#include "solve/solver.hpp"

#include <cstdint>
#include <vector>

namespace hemirad::thermal {

class ExchangeRows {
public:
    virtual ~ExchangeRows() = default;
    /// N, the scene's patches.
    virtual std::size_t size() const = 0;
    /// Whether row i of F was computed (on some rank).
    virtual bool rowComputed(std::size_t i) const = 0;
    /// Throws hemirad::Error naming the first row of F not computed.
    void requireAllRows() const;
    /// start_i + (F x)_i for every row i, each row summed in its entries' order onto start_i (no
    /// start: 0).
    virtual std::vector<double> rowProducts(const std::vector<double>& x, const std::vector<double>* start = nullptr) const = 0;
    /// sum_i w_i F_ij for every column j.
    virtual std::vector<double> columnSums(const std::vector<double>& w) const = 0;
    /// solveBands' contract on this F: X whole, one report per distinct band.
    virtual BandSolution solve(const Scene& scene, const std::vector<Band>& bands, const SolverOptions& options) const = 0;
    /// `options` as this F's solves take them (thermalSolverOptions in one process).
    virtual SolverOptions solverOptions(const SolverOptions& options, std::size_t patches) const = 0;
};

/// start_i + (F x)_i on the rows this process holds (held(i)), 0 on the others; each row summed in
/// its entries' order onto start_i (no start: 0).
template <class Held>
std::vector<double> heldRowProducts(const FormFactors& F, Held held, const std::vector<double>& x,
                                    const std::vector<double>* start) {
    std::vector<double> y(F.size(), 0.0);
    const double* values = F.values();
    const std::uint32_t* columns = F.columns();
    for (std::size_t i = 0; i < y.size(); ++i) {
        if (!held(i)) continue;
        double h = start ? (*start)[i] : 0.0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) h += double(values[k]) * x[columns[k]];
        y[i] = h;
    }
    return y;
}

/// sum_i w_i F_ij over the rows this process holds (held(i)), for every column j.
template <class Held>
std::vector<double> heldColumnSums(const FormFactors& F, Held held, const std::vector<double>& w) {
    std::vector<double> sums(F.size(), 0.0);
    const double* values = F.values();
    const std::uint32_t* columns = F.columns();
    for (std::size_t i = 0; i < sums.size(); ++i) {
        if (!held(i)) continue;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) sums[columns[k]] += w[i] * double(values[k]);
    }
    return sums;
}

/// F whole in this process: solveBands and plain loops.
class LocalRows final : public ExchangeRows {
public:
    explicit LocalRows(const FormFactors& F) : m_F(F) {}
    std::size_t size() const override { return m_F.size(); }
    bool rowComputed(std::size_t i) const override { return m_F.rowComputed(i); }
    std::vector<double> rowProducts(const std::vector<double>& x, const std::vector<double>* start = nullptr) const override;
    std::vector<double> columnSums(const std::vector<double>& w) const override;
    BandSolution solve(const Scene& scene, const std::vector<Band>& bands, const SolverOptions& options) const override;
    SolverOptions solverOptions(const SolverOptions& options, std::size_t patches) const override;

private:
    const FormFactors& m_F;
};

}  // namespace hemirad::thermal
