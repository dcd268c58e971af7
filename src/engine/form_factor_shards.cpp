// Sharded F files: the manifest, shard files written and read alone, and the merge into one F.
#include "engine/form_factor_shards.hpp"

#include "engine/atomic_file.hpp"
#include "engine/error.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/obj_loader.hpp"
#include "engine/text_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

namespace hemirad {
namespace {

constexpr char kManifestMagic[] = "HEMIRAD-SHARDS";
constexpr long kManifestVersion = 1;
constexpr std::uint64_t kMaxPatches = 1ULL << 28;  // as for an .hff file

std::uint64_t parseHex(const TextReader& r, std::size_t k, const char* what) {
    const std::string text(r.tokens()[k]);
    char* end = nullptr;
    errno = 0;
    const unsigned long long value = std::strtoull(text.c_str(), &end, 16);
    if (text.empty() || *end != '\0' || errno == ERANGE || text.size() > 16)
        r.fail(std::string("bad ") + what + " " + quote(text) + " (expected up to 16 hexadecimal digits)");
    return value;
}

std::uint64_t count(const TextReader& r, std::size_t k, const char* what) {
    const long value = r.integer(k, what);
    if (value < 0) r.fail(std::string(what) + " " + quote(r.tokens()[k]) + " is negative");
    return static_cast<std::uint64_t>(value);
}

/// The line's text from token k on, spaces kept (file names and parameter values may hold spaces).
std::string restVerbatim(const TextReader& r, std::size_t k) {
    const std::string_view line = r.text();
    return std::string(line.substr(static_cast<std::size_t>(r.tokens()[k].data() - line.data())));
}

/// The start of every shard file name of the manifest at `path`: STEM.shard-
std::string shardStem(const std::string& path) { return std::filesystem::path(path).stem().string() + ".shard-"; }

/// Whether `name` is exactly what shardFileName gives for a manifest of this `stem` (shardStem's
/// text): STEM.shard-INDEX-of-COUNT.SETID.hff, INDEX < COUNT in decimal without leading zeros,
/// SETID 8 lower-case hexadecimal digits.
bool isShardFileName(const std::string& name, const std::string& stem) {
    if (name.compare(0, stem.size(), stem) != 0) return false;
    std::size_t k = stem.size();
    auto digit = [&](std::size_t at) { return at < name.size() && name[at] >= '0' && name[at] <= '9'; };
    auto number = [&](std::uint64_t& value) {  // up to 19 digits: no overflow
        const std::size_t first = k;
        for (value = 0; digit(k) && k - first < 19; ++k) value = 10 * value + std::uint64_t(name[k] - '0');
        return k > first && !(name[first] == '0' && k - first > 1);
    };
    auto literal = [&](const char* text) {
        const std::size_t length = std::strlen(text);
        if (name.compare(k, length, text) != 0) return false;
        k += length;
        return true;
    };
    std::uint64_t index = 0, count = 0;
    if (!number(index) || !literal("-of-") || !number(count) || index >= count || !literal(".")) return false;
    for (int d = 0; d < 8; ++d, ++k)
        if (!digit(k) && !(k < name.size() && name[k] >= 'a' && name[k] <= 'f')) return false;
    return literal(".hff") && k == name.size();
}

/// The shard file names the manifest at `path` lists, into `names`; false when it is a manifest
/// that cannot be read (then nothing it may list is known). A file that is not a manifest lists none.
bool listedShardNames(const std::string& path, std::vector<std::string>& names) {
    try {
        if (!isShardManifest(path)) return true;
        for (const FormFactorShard& s : readShardManifest(path).shards) names.push_back(s.file);
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

/// Removes the files beside the F at `path` named as its shards (isShardFileName) that neither it
/// nor another manifest of its stem in that folder (F.hff and F.mtx share "F.shard-") lists. Nothing
/// is removed when one of those manifests cannot be read. Never throws.
void removeUnlistedShards(const std::string& path) {
    try {
        const std::filesystem::path target(path), folder = target.parent_path().empty() ? "." : target.parent_path();
        const std::string own = shardStem(path), stem = target.stem().string();
        std::vector<std::string> listed;
        if (!listedShardNames(path, listed)) return;
        std::vector<std::string> orphans;
        std::error_code ec;
        for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string name = it->path().filename().string();
            if (name == target.filename().string()) continue;
            if (isShardFileName(name, own)) orphans.push_back(name);
            else if (it->path().stem().string() == stem && !listedShardNames(it->path().string(), listed)) return;
        }
        if (ec) return;
        for (const std::string& name : orphans) {
            if (std::find(listed.begin(), listed.end(), name) != listed.end()) continue;
            const std::string file = (folder / name).string();
            if (!std::filesystem::is_regular_file(file, ec) || isShardManifest(file)) continue;
            std::filesystem::remove(file, ec);
        }
    } catch (const std::exception&) {
        // a folder that cannot be listed keeps what it has: the new F is in place either way
    }
}

}  // namespace

bool isShardManifest(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;  // never opens a FIFO or a device
    std::ifstream in(path, std::ios::binary);
    char start[sizeof kManifestMagic - 1] = {};
    in.read(start, sizeof start);
    return in && std::memcmp(start, kManifestMagic, sizeof start) == 0;
}

ShardManifest readShardManifest(const std::string& path) { return parseShardManifest(readTextFile(path), path); }

ShardManifest parseShardManifest(const std::string& text, const std::string& path) {
    TextReader r(path, text);
    if (!r.next() || r.tokens().size() != 2 || r.tokens()[0] != kManifestMagic)
        throw Error(path, 1, "not a Hemirad shard manifest (expected 'HEMIRAD-SHARDS 1')");
    if (r.integer(1, "manifest version") != kManifestVersion)
        r.fail("unsupported manifest version " + quote(r.tokens()[1]) + " (this build reads version 1)");
    ShardManifest m;
    bool havePatches = false, haveHash = false, haveNonZeros = false;
    std::uint64_t rows = 0, nonZeros = 0;
    while (r.next()) {
        const auto& t = r.tokens();
        if (t.empty()) continue;
        if (t[0] == "patches" && t.size() == 2) {
            m.patches = count(r, 1, "patch count");
            if (m.patches == 0 || m.patches > kMaxPatches)
                r.fail("patch count " + quote(r.tokens()[1]) + " is out of range (1 to " + std::to_string(kMaxPatches) + ")");
            havePatches = true;
        } else if (t[0] == "scene_hash" && t.size() == 2) {
            m.sceneHash = parseHex(r, 1, "scene hash");
            haveHash = true;
        } else if (t[0] == "nonzeros" && t.size() == 2) {
            m.nonZeros = count(r, 1, "nonzero count");
            haveNonZeros = true;
        } else if (t[0] == "param" && t.size() >= 2) {
            const std::string entry = restVerbatim(r, 1);
            const std::size_t eq = entry.find('=');
            if (eq == std::string::npos || eq == 0) r.fail("parameter " + quote(entry) + " is not KEY=VALUE");
            m.parameters[entry.substr(0, eq)] = entry.substr(eq + 1);
        } else if (t[0] == "shard" && t.size() >= 6) {
            FormFactorShard s;
            s.rows = count(r, 1, "shard row count");
            s.nonZeros = count(r, 2, "shard nonzero count");
            s.bytes = count(r, 3, "shard file size");
            s.checksum = parseHex(r, 4, "shard checksum");
            s.file = restVerbatim(r, 5);
            if (s.file == "." || s.file == ".." || s.file.find('/') != std::string::npos)
                r.fail("shard file " + quote(s.file) + " is not a file name beside the manifest");
            rows += s.rows;
            nonZeros += s.nonZeros;
            m.shards.push_back(std::move(s));
        } else {
            r.fail("unknown manifest record " + quote(r.text()) +
                   " (expected patches, scene_hash, nonzeros, param or shard)");
        }
    }
    if (!havePatches || !haveHash || !haveNonZeros)
        throw Error(path, 0, std::string("manifest lacks its '") +
                                 (!havePatches ? "patches" : !haveHash ? "scene_hash" : "nonzeros") + "' record");
    if (m.shards.empty()) throw Error(path, 0, "manifest lists no shard");
    if (rows > m.patches)
        throw Error(path, 0, "the shards hold " + std::to_string(rows) + " rows, more than the " +
                                 std::to_string(m.patches) + " patches");
    if (nonZeros != m.nonZeros)
        throw Error(path, 0, "the shards hold " + std::to_string(nonZeros) + " nonzeros, the manifest announces " +
                                 std::to_string(m.nonZeros));
    return m;
}

void writeShardManifest(const ShardManifest& m, const std::string& path) {
    checkParameters(m.parameters, path);
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    out << kManifestMagic << ' ' << kManifestVersion << "\npatches " << m.patches << "\nscene_hash "
        << hexHash(m.sceneHash) << "\nnonzeros " << m.nonZeros << '\n';
    for (const auto& [key, value] : m.parameters) out << "param " << key << '=' << value << '\n';
    for (const FormFactorShard& s : m.shards)
        out << "shard " << s.rows << ' ' << s.nonZeros << ' ' << s.bytes << ' ' << hexHash(s.checksum) << ' '
            << s.file << '\n';
    file.commit();
}

ShardManifest manifestFor(const FormFactors& F) {
    ShardManifest m;
    m.patches = F.size();
    m.sceneHash = F.sceneHash;
    m.parameters = withProvenance(F.provenance, F.parameters);
    return m;
}

std::uint32_t newShardSetId() {
    std::random_device device;
    const auto now = std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count());
    return std::uint32_t(device()) ^ std::uint32_t(now) ^ std::uint32_t(now >> 32) ^ std::uint32_t(::getpid());
}

std::string shardFileName(const std::string& manifestPath, std::size_t index, std::size_t count, std::uint32_t setId) {
    char id[9];
    std::snprintf(id, sizeof id, "%08x", setId);
    return shardStem(manifestPath) + std::to_string(index) + "-of-" + std::to_string(count) + "." + id + ".hff";
}

std::vector<std::string> listedShardFiles(const std::string& path) {
    std::vector<std::string> files;
    try {
        if (!isShardManifest(path)) return files;
        for (const FormFactorShard& s : readShardManifest(path).shards) files.push_back(shardPath(path, s));
    } catch (const std::exception&) {
        files.clear();  // not a manifest one can trust: nothing of it is removed
    }
    return files;
}

void removeReplacedShards(const std::string& path, const std::vector<std::string>& previous) {
    const std::vector<std::string> current = listedShardFiles(path);
    const std::string own = shardStem(path);
    for (const std::string& file : previous) {
        if (std::find(current.begin(), current.end(), file) != current.end()) continue;
        if (std::filesystem::path(file).filename().string().rfind(own, 0) != 0) continue;
        std::error_code ignored;
        std::filesystem::remove(file, ignored);
    }
    removeUnlistedShards(path);
}

std::string shardPath(const std::string& manifestPath, const FormFactorShard& shard) {
    return (std::filesystem::path(manifestPath).parent_path() / shard.file).string();
}

FormFactorShard writeShard(const FormFactors& F, const std::string& manifestPath, std::size_t index, std::size_t count,
                           std::uint32_t setId) {
    FormFactorShard s;
    s.file = shardFileName(manifestPath, index, count, setId);
    const std::string path = shardPath(manifestPath, s);
    s.checksum = saveHffFile(F, path);
    s.rows = F.computedRows();
    s.nonZeros = F.nonZeros();
    s.bytes = std::filesystem::file_size(path);
    return s;
}

void saveShardedFormFactors(const FormFactors& F, const std::string& path, std::size_t count) {
    if (count == 0) throw Error(path, 0, "no shards asked for");
    checkParameters(withProvenance(F.provenance, F.parameters), path);  // before any shard is written
    const std::vector<std::string> previous = listedShardFiles(path);
    const std::uint32_t setId = newShardSetId();
    ShardManifest m = manifestFor(F);
    const std::size_t n = F.size(), rows = F.computedRows();
    std::size_t i = 0, done = 0;
    for (std::size_t k = 0; k < count; ++k) {
        // Shard k: the next rows up to its share of the computed rows (consecutive rows).
        const std::size_t target = rows * (k + 1) / count;
        const std::size_t first = i;
        while (i < n && (done < target || (k + 1 == count))) done += F.rowComputed(i++) ? 1 : 0;
        std::vector<std::uint64_t> rowStart(n + 1, 0);
        std::vector<std::uint8_t> computed(n, 0);
        const std::uint64_t base = F.rowBegin(first);
        for (std::size_t j = first; j < i; ++j) {
            computed[j] = F.computedFlags()[j];
            rowStart[j + 1] = F.rowEnd(j) - base;
        }
        for (std::size_t j = i; j < n; ++j) rowStart[j + 1] = rowStart[j];
        const std::uint64_t end = base + rowStart[n];
        FormFactors shard = FormFactors::fromCsr(
            std::move(rowStart), std::vector<std::uint32_t>(F.columns() + base, F.columns() + end),
            std::vector<double>(F.values() + base, F.values() + end), std::move(computed));
        shard.sceneHash = F.sceneHash;
        shard.provenance = F.provenance;
        shard.parameters = F.parameters;
        try {
            m.shards.push_back(writeShard(shard, path, k, count, setId));
        } catch (...) {
            for (const FormFactorShard& written : m.shards) {  // the old set stays whole
                std::error_code ignored;
                std::filesystem::remove(shardPath(path, written), ignored);
            }
            throw;
        }
        m.nonZeros += m.shards.back().nonZeros;
    }
    writeShardManifest(m, path);
    removeReplacedShards(path, previous);
}

void visitShards(const std::string& manifestPath, const ShardManifest& m, const std::vector<std::size_t>& which,
                 const std::function<void(std::size_t, FormFactors&&)>& visit) {
    for (std::size_t index : which) {
        const FormFactorShard& s = m.shards.at(index);
        const std::string path = shardPath(manifestPath, s);
        std::uint64_t checksum = 0;
        FormFactors F = loadHffFile(path, checksum);
        auto mismatch = [&](const std::string& what) {
            throw Error(path, 0, "does not match its manifest " + manifestPath + ": " + what +
                                     " (a shard of another run? recompute F)");
        };
        if (checksum != s.checksum) mismatch("checksum " + hexHash(checksum) + ", listed " + hexHash(s.checksum));
        std::error_code ec;
        const std::uint64_t bytes = std::filesystem::file_size(path, ec);
        if (!ec && bytes != s.bytes) mismatch(std::to_string(bytes) + " bytes, listed " + std::to_string(s.bytes));
        if (F.size() != m.patches)
            mismatch(std::to_string(F.size()) + " patches, listed " + std::to_string(m.patches));
        if (F.sceneHash != m.sceneHash) mismatch("scene hash " + hexHash(F.sceneHash) + ", listed " + hexHash(m.sceneHash));
        if (F.computedRows() != s.rows || F.nonZeros() != s.nonZeros)
            mismatch(std::to_string(F.computedRows()) + " rows and " + std::to_string(F.nonZeros()) + " nonzeros, listed " +
                     std::to_string(s.rows) + " and " + std::to_string(s.nonZeros));
        if (withProvenance(F.provenance, F.parameters) != m.parameters) mismatch("computed with other parameters");
        visit(index, std::move(F));
    }
}

FormFactors loadShards(const std::string& manifestPath, const ShardManifest& m, const std::vector<std::size_t>& which) {
    const std::size_t n = m.patches;
    // Pass 1: each shard's rows and entries per row, to place every row once. Nothing of size N is
    // allocated before a shard has confirmed the manifest's N.
    std::vector<std::uint64_t> rowStart;
    std::vector<std::uint8_t> held;
    for (std::size_t index : which) {
        const std::string path = shardPath(manifestPath, m.shards.at(index));
        const HffRowIndex rows = readHffRowIndex(path);
        if (rows.lengths.size() != n)
            throw Error(path, 0, "has " + std::to_string(rows.lengths.size()) + " patches; its manifest " + manifestPath +
                                     " lists " + std::to_string(n));
        rowStart.resize(n + 1, 0);
        held.resize(n, 0);
        for (std::size_t i = 0; i < n; ++i) {
            if (!rows.computed[i]) continue;
            if (held[i]) throw Error(path, 0, "row " + std::to_string(i) + " is in two shards of " + manifestPath);
            held[i] = 1;
            rowStart[i + 1] = rows.lengths[i];
        }
    }
    std::vector<std::uint8_t>().swap(held);
    rowStart.resize(n + 1, 0);  // no shard of this rank's: every row empty
    for (std::size_t i = 0; i < n; ++i) rowStart[i + 1] += rowStart[i];
    // Pass 2: each shard read, checked and scattered into place.
    std::vector<std::uint32_t> columns(rowStart[n]);
    std::vector<double> values(rowStart[n]);
    std::vector<std::uint8_t> computed(n, 0);
    visitShards(manifestPath, m, which, [&](std::size_t index, FormFactors&& shard) {
        const std::string path = shardPath(manifestPath, m.shards[index]);
        for (std::size_t i = 0; i < n; ++i) {
            if (!shard.rowComputed(i)) continue;
            if (computed[i])
                throw Error(path, 0, "row " + std::to_string(i) + " is in two shards of " + manifestPath);
            const std::uint64_t begin = shard.rowBegin(i), length = shard.rowEnd(i) - begin;
            if (length != rowStart[i + 1] - rowStart[i])
                throw Error(path, 0, "changed while it was read (row " + std::to_string(i) + ")");
            std::copy_n(shard.columns() + begin, length, columns.begin() + std::ptrdiff_t(rowStart[i]));
            std::copy_n(shard.values() + begin, length, values.begin() + std::ptrdiff_t(rowStart[i]));
            computed[i] = 1;
        }
    });
    for (std::size_t i = 0; i < n; ++i)
        if (!computed[i] && rowStart[i + 1] != rowStart[i])
            throw Error(manifestPath, 0, "a shard changed while it was read (row " + std::to_string(i) + ")");
    FormFactors F = FormFactors::fromCsr(std::move(rowStart), std::move(columns), std::move(values), std::move(computed));
    F.sceneHash = m.sceneHash;
    F.parameters = m.parameters;
    F.provenance = takeProvenance(F.parameters, manifestPath);
    return F;
}

FormFactors loadShardedFormFactors(const std::string& path) {
    const ShardManifest m = readShardManifest(path);
    std::vector<std::size_t> all(m.shards.size());
    for (std::size_t k = 0; k < all.size(); ++k) all[k] = k;
    return loadShards(path, m, all);
}

}  // namespace hemirad
