// Sharded F files across MPI ranks (engine/form_factor_shards.hpp): every rank writes and reads its
// own shards, so F is never gathered on one rank and no rank reads the whole F.
#pragma once

#include "mpi/distributed_form_factors.hpp"

#include <string>

namespace hemirad::mpi {

/// Each rank writes its rows as shard RANK of K of a new set beside `manifestPath`, then rank 0 writes
/// the manifest and removes the set the old manifest listed. A failure on any rank removes the shards
/// just written and throws AgreedFailure on every rank; the old manifest and its set stay whole.
/// Collective; returns the shard files' total size, on rank 0.
std::uint64_t writeShards(const Context& context, const DistributedFormFactors& F, const std::string& manifestPath);

/// Rank r reads the shards s with s mod K = r of the manifest at `manifestPath` (each checked against
/// the manifest) and keeps their rows; the owners come from every rank's shards. A row in two shards
/// is an error. Collective; throws AgreedFailure on every rank.
DistributedFormFactors readShards(const Context& context, const std::string& manifestPath);

}  // namespace hemirad::mpi
