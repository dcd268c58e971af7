// The thermal solve on F's rows where the ranks hold them (thermal/exchange_rows.hpp): row
// products and column sums from each rank's rows, summed across the ranks; the bands by PETSc
// (solveBandsDistributed). Every rank ends with the whole solution, so no rank holds F whole.
#pragma once

#include "mpi/distributed_form_factors.hpp"
#include "thermal/exchange_rows.hpp"

namespace hemirad::mpi {

class DistributedRows final : public thermal::ExchangeRows {
public:
    DistributedRows(const Context& context, const DistributedFormFactors& F) : m_context(context), m_F(F) {}
    std::size_t size() const override { return m_F.owner.size(); }
    bool rowComputed(std::size_t i) const override { return m_F.owner[i] >= 0; }  // owner: the same on every rank
    /// Each rank's rows (in their entries' order onto their start, as one process sums them), made
    /// whole by a sum across the ranks (each row has one owner: the sum adds zeros, exactly). Collective.
    std::vector<double> rowProducts(const std::vector<double>& x, const std::vector<double>* start = nullptr) const override;
    /// Each rank's rows' share, summed across the ranks. Collective.
    std::vector<double> columnSums(const std::vector<double>& w) const override;
    /// solveBandsDistributed. Collective.
    BandSolution solve(const Scene& scene, const std::vector<Band>& bands, const SolverOptions& options) const override;
    /// "auto": bicgstab (one process's auto is LU up to 2000 patches; thermal's default tolerance,
    /// 1e-10, keeps the ranks' answer within about that of it); a named solver as given.
    SolverOptions solverOptions(const SolverOptions& options, std::size_t patches) const override;

private:
    const Context& m_context;
    const DistributedFormFactors& m_F;
};

}  // namespace hemirad::mpi
