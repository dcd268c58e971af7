// F files: the checked binary .hff format and Matrix Market .mtx (readable by scipy.io.mmread).
#pragma once

#include "engine/form_factors.hpp"

#include <limits>
#include <optional>
#include <string>

namespace hemirad {

enum class FormFactorFormat { Hff, Mtx };

/// The format a path names by its extension (.hff or .mtx); a target without one to choose by gets
/// the text .mtx on standard output ("-") and the compact .hff on a FIFO or device (-o /dev/null to
/// time F). Throws hemirad::Error for any other extension.
FormFactorFormat formFactorFormatFor(const std::string& path);

/// Writes F atomically (AtomicFile) in `format`; a shard manifest it replaces loses its shards.
/// Throws hemirad::Error.
void saveFormFactors(const FormFactors& F, const std::string& path, FormFactorFormat format);
/// saveFormFactors in formFactorFormatFor(path).
void saveFormFactors(const FormFactors& F, const std::string& path);
/// Reads F, checking structure, checksum (.hff) and values. Throws hemirad::Error naming the file.
/// A shard manifest (form_factor_shards.hpp) at an .hff path reads every shard into one F.
/// `expectedPatches` (0: any) is the scene's patch count: a file declaring another N is refused as
/// checkFormFactorsMatch refuses it, before anything of that size is allocated.
FormFactors loadFormFactors(const std::string& path, std::size_t expectedPatches = 0);

/// Rows [first, last) of the .hff file at `path` (last clamped to its N), as loadFormFactors reads
/// them: F of the file's N in which only those rows are computed. The whole file is streamed through
/// its checksum and every row start checked; memory follows the kept rows' entries and N.
FormFactors loadHffRows(const std::string& path, std::size_t first, std::size_t last, std::size_t expectedPatches = 0);

/// Writes F as .hff atomically and returns the checksum its last 8 bytes hold (shard manifests keep it).
std::uint64_t saveHffFile(const FormFactors& F, const std::string& path);
/// Reads an .hff file as loadFormFactors does, with the checksum it holds.
FormFactors loadHffFile(const std::string& path, std::uint64_t& checksum);
/// The computed-row flags and entries per row of an .hff file, from its header and row starts alone
/// (the checksum is not verified: for planning a merge or a read whose reads verify it).
/// `expectedPatches` (0: any) as loadFormFactors takes it.
struct HffRowIndex {
    std::vector<std::uint8_t> computed;
    std::vector<std::uint64_t> lengths;
};
HffRowIndex readHffRowIndex(const std::string& path, std::size_t expectedPatches = 0);

/// Reads F from bytes in memory (tests, fuzzing); `name` names it in messages and its extension
/// (.hff or .mtx) picks the format. Same checks as loadFormFactors.
FormFactors parseFormFactors(const std::string& name, const std::string& bytes);

/// What `hemirad info` prints of an .mtx, summarised from its entries.
struct MtxRowSums {
    FormFactorProvenance provenance;
    std::size_t rowsWithEntries = 0, selfFactorRows = 0;  ///< rows with entries; rows with F_ii > 0
    double min = std::numeric_limits<double>::infinity(), max = 0.0, total = 0.0;  ///< over computed rows
};

/// An F file described without its arrays (for `hemirad info`). .hff: its header, after checking size
/// and checksum. .mtx: every entry checked as loadFormFactors checks it, and `mtxRows` set; its
/// memory follows the entries the file holds, never the N it declares (no row arrays are built).
struct FormFactorFileInfo {
    std::uint32_t version = 0;
    std::uint64_t size = 0, nonZeros = 0, sceneHash = 0, fileBytes = 0;
    std::size_t computedRows = 0;
    std::map<std::string, std::string> parameters;  ///< .mtx: without the provenance's keys
    std::optional<MtxRowSums> mtxRows;
};
FormFactorFileInfo readFormFactorInfo(const std::string& path);

/// Checks that F belongs to the scene with hash `sceneHash` and `patchCount` patches.
void checkFormFactorsMatch(const FormFactors& F, std::uint64_t sceneHash, std::size_t patchCount,
                           const std::string& path);

std::string hexHash(std::uint64_t hash);

}  // namespace hemirad
