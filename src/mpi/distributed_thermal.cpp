// The gray thermal solve on the ranks' rows (see the header).
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
    const FormFactors& F = m_F.local;
    std::vector<double> y(size(), 0.0);
    const float* values = F.values();
    const std::uint32_t* columns = F.columns();
    for (std::size_t i = 0; i < y.size(); ++i) {
        if (m_F.owner[i] != m_context.rank()) continue;
        double h = start ? (*start)[i] : 0.0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) h += double(values[k]) * x[columns[k]];
        y[i] = h;
    }
    sumAcrossRanks(y);
    return y;
}

std::vector<double> DistributedRows::columnSums(const std::vector<double>& w) const {
    const FormFactors& F = m_F.local;
    std::vector<double> sums(size(), 0.0);
    const float* values = F.values();
    const std::uint32_t* columns = F.columns();
    for (std::size_t i = 0; i < sums.size(); ++i) {
        if (m_F.owner[i] != m_context.rank()) continue;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) sums[columns[k]] += w[i] * double(values[k]);
    }
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
