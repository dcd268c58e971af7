// The thermal solve on the ranks' rows (see the header).
#include "mpi/distributed_thermal.hpp"

#include "mpi/petsc_solve.hpp"

#include <mpi.h>

namespace hemirad::mpi {
namespace {

/// Element-wise sum over the ranks, in place. Collective.
void sumAcrossRanks(std::vector<double>& v) {
    if (!v.empty()) MPI_Allreduce(MPI_IN_PLACE, v.data(), int(v.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
}

}  // namespace

std::vector<double> DistributedRows::rowProducts(const std::vector<double>& x, const std::vector<double>* start) const {
    std::vector<double> y = thermal::heldRowProducts(m_F.local, [&](std::size_t i) { return m_F.owner[i] == m_context.rank(); },
                                                     x, start);
    sumAcrossRanks(y);
    return y;
}

std::vector<double> DistributedRows::columnSums(const std::vector<double>& w) const {
    std::vector<double> sums =
        thermal::heldColumnSums(m_F.local, [&](std::size_t i) { return m_F.owner[i] == m_context.rank(); }, w);
    sumAcrossRanks(sums);
    return sums;
}

BandSolution DistributedRows::solve(const Scene& scene, const std::vector<Band>& bands, const SolverOptions& options) const {
    return solveBandsDistributed(m_context, scene, m_F, bands, options);
}

SolverOptions DistributedRows::solverOptions(const SolverOptions& options, std::size_t) const {
    SolverOptions o = options;
    if (o.solver == "auto") o.solver = "bicgstab";
    return o;
}

}  // namespace hemirad::mpi
