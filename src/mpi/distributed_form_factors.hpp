// Form-factor rows spread over MPI ranks: a work queue on rank 0 hands out blocks of rows (guided:
// large first, small at the end, weighed by the back end's row cost), each rank's back end pulls them
// through a RowSource, and the rows stay on the rank that computed them.
#pragma once

#include "mpi/mpi_context.hpp"
#include "preprocess/form_factor_job.hpp"

#include <map>
#include <string>
#include <vector>

namespace hemirad::mpi {

/// F spread over ranks: each rank holds the rows it computed (or loaded).
struct DistributedFormFactors {
    FormFactors local;                ///< size N; only this rank's rows are computed; hash, provenance, parameters set
    std::vector<std::int32_t> owner;  ///< per patch, on every rank: the rank holding its row, -1 for none
    // The computation, on rank 0 (summed or taken over ranks):
    RayCounts counts;
    std::map<std::string, double> stageSeconds;
    std::string device;                   ///< rank 0's FormFactorBackend::device()
    double prepareSeconds = 0;            ///< the slowest rank's acceleration structures
    double computeSeconds = 0;            ///< wall time of the rows, first row to the last rank done
    double assembleSeconds = 0;           ///< each pair from its emitting row, across the ranks
    std::vector<std::uint64_t> rowsPerRank;
    std::vector<double> busySeconds;       ///< per rank: from its first row to its worker's end
    std::size_t rowsComputed = 0;
    EmittedPairsReport emittedPairs;      ///< receiver entries taken from their emitting rows (summed)
};

/// Computes `rows` (the same list on every rank) with `settings`: every rank prepares its own back
/// end once and computes the blocks rank 0 hands it. Collective; `progress` is called on rank 0 for the
/// whole job. A failure on any rank stops the queue and throws AgreedFailure on every rank.
DistributedFormFactors computeDistributed(const Context& context, const Scene& scene, const MethodSettings& settings,
                                          const std::vector<PatchId>& rows, const ProgressCallback& progress);

/// The whole F on rank 0 (size 0 elsewhere): row lengths reduced, then each rank's entries streamed to
/// rank 0 into one CSR (rank 0 holds F once, plus one rank's entries in flight). Collective.
FormFactors gatherFormFactors(const Context& context, const DistributedFormFactors& F);

/// One F file (.hff or .mtx; not a shard manifest) spread over the ranks, each holding a contiguous
/// share of its rows: an .hff's rows are read by their rank alone (each rank streams the whole file
/// through its checksum), an .mtx is read whole by every rank, which keeps its share. With
/// `memoryCheck`, what the ranks on a node would hold together beyond 80 % of its available memory
/// is refused first (hemirad::Error naming the file, agreed). `patches`: the scene's N. Collective.
DistributedFormFactors readOwnRows(const Context& context, const std::string& path, std::size_t patches, bool memoryCheck);

/// Statistics from the ranks' rows (row sums, nonzeros; reciprocity needs pairs across ranks and is
/// left at 0), on rank 0. Collective.
FormFactorStats distributedRowStats(const Context& context, const DistributedFormFactors& F);

}  // namespace hemirad::mpi
