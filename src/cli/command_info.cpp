// `hemirad info F.hff|F.mtx`: verify an F file (or a shard manifest and every shard) completely and
// describe it.
#include "cli/commands.hpp"
#include "cli/report.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/form_factor_shards.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <limits>

namespace hemirad {
namespace {

/// Row statistics of computed rows, accumulated over one F or shard by shard (every figure is row-local).
struct RowTotals {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0, sum = 0.0;
    std::size_t patches = 0, rows = 0, diagonal = 0, nonZeros = 0;

    void add(const FormFactors& F) {
        patches = F.size();
        nonZeros += F.nonZeros();
        for (std::size_t i = 0; i < F.size(); ++i) {
            if (!F.rowComputed(i)) continue;
            const double s = F.rowSum(i);
            lo = std::min(lo, s);
            hi = std::max(hi, s);
            sum += s;
            ++rows;
            if (F.at(i, i) > 0.0) ++diagonal;
        }
    }
};

double mib(double bytes) { return bytes / 1048576.0; }

void describe(const RowTotals& t, std::uint64_t sceneHash, const FormFactorProvenance& p,
              const std::map<std::string, std::string>& parameters, double fileBytes) {
    // In memory as one F: 8 bytes per row start, 12 per entry, 1 per row flag.
    const double memory = 8.0 * double(t.patches + 1) + 12.0 * double(t.nonZeros) + double(t.patches);
    std::cout << "\n  patches " << t.patches << ", computed rows " << t.rows << " (skipped " << t.patches - t.rows
              << ")\n  nonzeros " << t.nonZeros << " (" << (t.rows ? double(t.nonZeros) / double(t.rows) : 0.0)
              << " per computed row), in memory " << mib(memory) << " MiB, file " << mib(fileBytes) << " MiB\n"
              << "  scene hash "
              << (p.sceneHashKnown ? hexHash(sceneHash) : std::string("unknown (a foreign file: only the size is checked)"))
              << '\n';
    std::cout << "  method " << (p.method.empty() ? "unknown" : p.method);
    if (!p.estimator.empty()) std::cout << ", estimator " << p.estimator;
    std::cout << "; row sums bounded by " << p.rowSumBound << (p.rowSumBound > 1.0 ? " (mirror chains)" : "") << '\n';
    if (t.rows) std::cout << "  row sums min " << t.lo << " mean " << t.sum / double(t.rows) << " max " << t.hi << '\n';
    if (t.diagonal) std::cout << "  " << t.diagonal << " rows with F_ii > 0 (patches that see their mirror image)\n";
    for (const auto& [key, value] : withProvenance(p, parameters)) std::cout << "  " << key << " = " << value << '\n';
}

/// A manifest: every shard loaded and checked in turn (one shard in memory at a time).
int describeShards(const std::string& path) {
    const ShardManifest m = readShardManifest(path);
    std::vector<std::size_t> all(m.shards.size());
    for (std::size_t k = 0; k < all.size(); ++k) all[k] = k;
    RowTotals totals;
    std::vector<std::uint8_t> seen;  // allocated once a shard has confirmed the manifest's size
    double bytes = double(std::filesystem::file_size(path));
    visitShards(path, m, all, [&](std::size_t index, FormFactors&& shard) {
        seen.resize(shard.size(), 0);
        for (std::size_t i = 0; i < shard.size(); ++i) {
            if (!shard.rowComputed(i)) continue;
            if (seen[i]) throw Error(shardPath(path, m.shards[index]), 0, "row " + std::to_string(i) + " is in two shards of " + path);
            seen[i] = 1;
        }
        totals.add(shard);
        bytes += double(m.shards[index].bytes);
    });
    std::map<std::string, std::string> parameters = m.parameters;
    const FormFactorProvenance provenance = takeProvenance(parameters, path);
    std::cout << path << ": valid Hemirad form factors, a manifest of " << m.shards.size() << " shard"
              << (m.shards.size() == 1 ? "" : "s");
    describe(totals, m.sceneHash, provenance, parameters, bytes);
    for (std::size_t k = 0; k < m.shards.size(); ++k) {
        const FormFactorShard& s = m.shards[k];
        std::cout << "  shard " << k << ": " << s.file << ", " << s.rows << " rows, " << s.nonZeros << " nonzeros, "
                  << mib(double(s.bytes)) << " MiB\n";
    }
    return 0;
}

}  // namespace

int runInfo(const Options& options) {
    const std::string& path = options.inputs.at(0);
    if (isShardManifest(path)) return describeShards(path);
    const FormFactorFileInfo info = readFormFactorInfo(path);  // .hff: structure and checksum
    if (info.mtxRows) {
        // .mtx: every entry checked and summarised by readFormFactorInfo, without F's row arrays, so
        // that what info costs follows the entries and not the N the file declares (issue 35 #11).
        const MtxRowSums& rows = *info.mtxRows;
        RowTotals totals;
        totals.patches = info.size;
        totals.nonZeros = info.nonZeros;
        totals.rows = info.computedRows;
        totals.diagonal = rows.selfFactorRows;
        if (totals.rows) {
            totals.lo = rows.min;
            totals.hi = rows.max;
            totals.sum = rows.total;
        }
        std::cout << path << ": valid Hemirad form factors";
        describe(totals, info.sceneHash, rows.provenance, info.parameters, double(info.fileBytes));
        return 0;
    }
    const FormFactors F = loadFormFactors(path);  // every entry checked (an .hff's N is bounded by its size)
    RowTotals totals;
    totals.add(F);
    std::cout << path << ": valid Hemirad form factors";
    if (info.version) std::cout << ", format version " << info.version;
    describe(totals, F.sceneHash, F.provenance, F.parameters, double(info.fileBytes));
    return 0;
}

}  // namespace hemirad
