// Sharded F files, for an F larger than one machine's memory: one .hff file per shard (a complete
// file of N rows in which only the shard's rows are computed, with its own checksum) and, at the F
// path, a small text manifest that lists them. MPI ranks write and read their shards alone (no F
// gathered on one rank); one process reads them all into one F.
//
// Manifest (text, one record per line):
//
//   HEMIRAD-SHARDS 1
//   patches N
//   scene_hash HEX                        (Scene::geometryHash, as in the shards)
//   nonzeros NNZ                          (all shards together)
//   param KEY=VALUE                       (the shards' parameter text, provenance included; repeated)
//   shard ROWS NNZ BYTES CHECKSUM FILE    (computed rows, entries, file size, the file's stored
//                                          checksum in hex; FILE a name in the manifest's folder)
#pragma once

#include "engine/form_factors.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace hemirad {

struct FormFactorShard {
    std::string file;  ///< a file name in the manifest's folder
    std::uint64_t rows = 0, nonZeros = 0, bytes = 0, checksum = 0;
};

struct ShardManifest {
    std::uint64_t patches = 0, sceneHash = 0, nonZeros = 0;
    std::map<std::string, std::string> parameters;  ///< as the shards store them (provenance keys included)
    std::vector<FormFactorShard> shards;
};

/// Whether the file at `path` starts like a shard manifest (a missing file is not one).
bool isShardManifest(const std::string& path);
/// Reads and checks a manifest. Throws hemirad::Error naming the file, line and value.
ShardManifest readShardManifest(const std::string& path);
/// Checks a manifest's `text`, read from `path` (for messages): what one MPI rank read and sent to the
/// others, so that all work from one reading. Throws hemirad::Error as readShardManifest.
ShardManifest parseShardManifest(const std::string& text, const std::string& path);
/// Writes a manifest atomically.
void writeShardManifest(const ShardManifest& manifest, const std::string& path);
/// The manifest's header (patches, scene hash, parameters) from an F; no shards yet.
ShardManifest manifestFor(const FormFactors& F);

/// A fresh identifier for a set of shards. A new set's files never have the names of the set the
/// current manifest lists, so that set stays whole until the new manifest replaces it.
std::uint32_t newShardSetId();

/// The file name of shard `index` of `count` of set `setId` beside the manifest at `manifestPath`:
/// STEM.shard-INDEX-of-COUNT.SETID.hff.
std::string shardFileName(const std::string& manifestPath, std::size_t index, std::size_t count, std::uint32_t setId);
/// Where shard `shard` of the manifest at `manifestPath` lies.
std::string shardPath(const std::string& manifestPath, const FormFactorShard& shard);

/// Writes `F` (its computed rows are the shard's) as shard `index` of `count` of set `setId` beside
/// the manifest at `manifestPath`, atomically, and returns its record.
FormFactorShard writeShard(const FormFactors& F, const std::string& manifestPath, std::size_t index, std::size_t count,
                           std::uint32_t setId);

/// The shard files the file at `path` lists when it is a readable manifest (none otherwise; never
/// throws): read before replacing it, for removeReplacedShards.
std::vector<std::string> listedShardFiles(const std::string& path);
/// After a new manifest or F file was committed at `path`: removes the files of `previous` that the
/// file at `path` no longer lists and that are this manifest's own (named STEM.shard-..., so the
/// shards of a manifest copied under another name are left alone), then every other file beside it
/// named exactly as its shards are (shardFileName's pattern) that it does not list: the shards an
/// interrupted write left (a rank's shard renamed into place before the manifest was written, then
/// Ctrl-C). Shards that another manifest of the same stem in the folder lists (F.hff and F.mtx share
/// F.shard-...) are kept, and nothing is swept when such a manifest cannot be read. Two writes of F
/// files with one stem into one folder at the same time may remove each other's new shards: one
/// writer per stem and folder. Never throws.
void removeReplacedShards(const std::string& path, const std::vector<std::string>& previous);

/// One process: `F` as `count` shards of consecutive computed rows plus the manifest at `path`; the
/// shards a manifest at `path` listed before are removed once the new manifest is in place.
void saveShardedFormFactors(const FormFactors& F, const std::string& path, std::size_t count);

/// Loads the shards `which` (indices into manifest.shards) one at a time, each checked completely and
/// against the manifest (size, scene hash, rows, entries, checksum, parameters), and hands it to
/// `visit`. Throws hemirad::Error naming the shard file.
void visitShards(const std::string& manifestPath, const ShardManifest& manifest, const std::vector<std::size_t>& which,
                 const std::function<void(std::size_t index, FormFactors&& shard)>& visit);

/// The shards `which` as one F of N rows (rows of other shards not computed). A row in two shards is
/// an error. Peak memory: the result plus the largest shard. Throws hemirad::Error.
FormFactors loadShards(const std::string& manifestPath, const ShardManifest& manifest, const std::vector<std::size_t>& which);

/// Every shard of the manifest at `path` as one F.
FormFactors loadShardedFormFactors(const std::string& path);

}  // namespace hemirad
