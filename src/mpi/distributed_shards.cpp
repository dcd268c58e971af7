// Sharded F files across MPI ranks: shards written and read by their ranks, the manifest by rank 0.
#include "mpi/distributed_shards.hpp"

#include "engine/form_factor_shards.hpp"
#include "engine/obj_loader.hpp"

#include <mpi.h>

#include <array>
#include <climits>
#include <filesystem>

namespace hemirad::mpi {

std::uint64_t writeShards(const Context& context, const DistributedFormFactors& F, const std::string& manifestPath) {
    const std::size_t ranks = std::size_t(context.size());
    // A new set beside the one a manifest at the path lists (rank 0 reads it), which stays whole
    // until the new manifest is in place.
    const std::vector<std::string> previous = context.root() ? listedShardFiles(manifestPath) : std::vector<std::string>();
    std::uint32_t setId = context.root() ? newShardSetId() : 0;
    MPI_Bcast(&setId, 1, MPI_UINT32_T, 0, MPI_COMM_WORLD);
    FormFactorShard mine;
    std::uint64_t bytes = 0;
    try {
        context.collectively(
            [&] { mine = writeShard(F.local, manifestPath, std::size_t(context.rank()), ranks, setId); });
        // The records to rank 0 (the file names follow from the ranks).
        const std::array<std::uint64_t, 4> record = {mine.rows, mine.nonZeros, mine.bytes, mine.checksum};
        std::vector<std::uint64_t> records(context.root() ? 4 * ranks : 0);
        MPI_Gather(record.data(), 4, MPI_UINT64_T, records.data(), 4, MPI_UINT64_T, 0, MPI_COMM_WORLD);
        context.collectively([&] {
            if (!context.root()) return;
            ShardManifest manifest = manifestFor(F.local);
            for (std::size_t r = 0; r < ranks; ++r) {
                FormFactorShard s;
                s.file = shardFileName(manifestPath, r, ranks, setId);
                s.rows = records[4 * r], s.nonZeros = records[4 * r + 1], s.bytes = records[4 * r + 2];
                s.checksum = records[4 * r + 3];
                manifest.nonZeros += s.nonZeros;
                bytes += s.bytes;
                manifest.shards.push_back(std::move(s));
            }
            writeShardManifest(manifest, manifestPath);
            removeReplacedShards(manifestPath, previous);
        });
    } catch (const AgreedFailure&) {
        // A rank could not write its shard, or rank 0 the manifest: none of this run's shards stays,
        // and the set the old manifest lists is untouched.
        if (!mine.file.empty()) {
            std::error_code ignored;
            std::filesystem::remove(shardPath(manifestPath, mine), ignored);
        }
        throw;
    }
    return bytes;
}

DistributedFormFactors readShards(const Context& context, const std::string& manifestPath) {
    DistributedFormFactors result;
    // Rank 0 reads the manifest for all: ranks reading it one by one could each see another file (one
    // replaced in between, or a node's stale copy) and combine two sets of shards.
    std::string text;
    context.collectively([&] {
        if (context.root()) text = readTextFile(manifestPath);
    });
    text = context.broadcastText(text);
    context.collectively([&] {
        const ShardManifest manifest = parseShardManifest(text, manifestPath);
        std::vector<std::size_t> mine;
        for (std::size_t s = std::size_t(context.rank()); s < manifest.shards.size(); s += std::size_t(context.size()))
            mine.push_back(s);
        result.local = loadShards(manifestPath, manifest, mine);
    });
    // Owners from every rank's rows; a row that two ranks hold came in two shards.
    const std::size_t n = result.local.size();
    std::vector<std::int32_t> highest(n), lowest(n);
    for (std::size_t i = 0; i < n; ++i) {
        highest[i] = result.local.rowComputed(i) ? context.rank() : -1;
        lowest[i] = result.local.rowComputed(i) ? context.rank() : INT_MAX;
    }
    result.owner.resize(n);
    MPI_Allreduce(highest.data(), result.owner.data(), int(n), MPI_INT32_T, MPI_MAX, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, lowest.data(), int(n), MPI_INT32_T, MPI_MIN, MPI_COMM_WORLD);
    context.collectively([&] {
        for (std::size_t i = 0; i < n; ++i)
            if (result.owner[i] >= 0 && lowest[i] != result.owner[i])
                throw Error(manifestPath, 0, "row " + std::to_string(i) + " is in two shards (read by ranks " +
                                                 std::to_string(lowest[i]) + " and " + std::to_string(result.owner[i]) + ")");
    });
    return result;
}

}  // namespace hemirad::mpi
