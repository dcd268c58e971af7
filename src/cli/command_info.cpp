// `hemirad info F.hff|F.mtx`: verify an F file completely and describe it.
#include "cli/commands.hpp"
#include "cli/report.hpp"
#include "engine/form_factor_file.hpp"

#include <algorithm>
#include <iostream>
#include <limits>

namespace hemirad {

int runInfo(const Options& options) {
    const std::string& path = options.inputs.at(0);
    const FormFactorFileInfo info = readFormFactorInfo(path);  // structure and checksum
    const FormFactors F = loadFormFactors(path);               // every entry checked
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0, sum = 0.0;
    std::size_t rows = 0, diagonal = 0;
    for (std::size_t i = 0; i < F.size(); ++i) {
        if (!F.rowComputed(i)) continue;
        const double s = F.rowSum(i);
        lo = std::min(lo, s);
        hi = std::max(hi, s);
        sum += s;
        ++rows;
        if (F.at(i, i) > 0.0) ++diagonal;
    }
    std::cout << path << ": valid Hemirad form factors";
    if (info.version) std::cout << ", format version " << info.version;
    std::cout << "\n  patches " << F.size() << ", computed rows " << F.computedRows() << " (skipped "
              << F.size() - F.computedRows() << ")\n  nonzeros " << F.nonZeros() << " ("
              << (rows ? double(F.nonZeros()) / rows : 0.0) << " per computed row), in memory "
              << F.memoryBytes() / 1048576.0 << " MiB, file " << info.fileBytes / 1048576.0 << " MiB\n"
              << "  scene hash " << (F.provenance.sceneHashKnown ? hexHash(F.sceneHash) : std::string("unknown (a foreign file: only the size is checked)")) << '\n';
    const FormFactorProvenance& p = F.provenance;
    std::cout << "  method " << (p.method.empty() ? "unknown" : p.method);
    if (!p.estimator.empty()) std::cout << ", estimator " << p.estimator;
    std::cout << "; row sums bounded by " << p.rowSumBound << (p.rowSumBound > 1.0 ? " (mirror chains)" : "") << '\n';
    if (rows) std::cout << "  row sums min " << lo << " mean " << sum / rows << " max " << hi << '\n';
    if (diagonal) std::cout << "  " << diagonal << " rows with F_ii > 0 (patches that see their mirror image)\n";
    for (const auto& [key, value] : withProvenance(F.provenance, F.parameters))
        std::cout << "  " << key << " = " << value << '\n';
    return 0;
}

}  // namespace hemirad
