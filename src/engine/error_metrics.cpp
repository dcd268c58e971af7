// Error metrics.
#include "engine/error_metrics.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <cmath>

namespace hemirad {

FormFactorError compareFormFactors(const FormFactors& F, const FormFactors& reference) {
    if (F.size() != reference.size())
        throw Error("compare: F has " + std::to_string(F.size()) + " rows, the reference " + std::to_string(reference.size()));
    const std::size_t n = F.size();
    FormFactorError e;
    double sumMean = 0, sumMax = 0, sumRms = 0, sumL1 = 0, worstMean = 0, worstMax = 0, worstRms = 0, worstL1 = 0;
    std::size_t rows = 0, worstRow = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : sumMean, sumMax, sumRms, sumL1, rows) \
    reduction(max : worstMean, worstMax, worstRms)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
        if (!F.rowComputed(i) || !reference.rowComputed(i)) continue;
        double l1 = 0, l2 = 0, mx = 0;
        std::uint64_t a = F.rowBegin(i), b = reference.rowBegin(i);
        const std::uint64_t aEnd = F.rowEnd(i), bEnd = reference.rowEnd(i);
        while (a < aEnd || b < bEnd) {
            const std::uint32_t ja = a < aEnd ? F.columns()[a] : UINT32_MAX;
            const std::uint32_t jb = b < bEnd ? reference.columns()[b] : UINT32_MAX;
            const std::uint32_t j = std::min(ja, jb);
            const double x = ja == j ? F.values()[a++] : 0.0;
            const double y = jb == j ? reference.values()[b++] : 0.0;
            const double d = std::abs(x - y);
            l1 += d;
            l2 += d * d;
            mx = std::max(mx, d);
        }
        const double mean = l1 / double(n), rms = std::sqrt(l2 / double(n));
        sumMean += mean;
        sumMax += mx;
        sumRms += rms;
        sumL1 += l1;
        ++rows;
        worstMean = std::max(worstMean, mean);
        worstMax = std::max(worstMax, mx);
        worstRms = std::max(worstRms, rms);
#pragma omp critical(hemirad_worst_row)
        if (l1 > worstL1) {
            worstL1 = l1;
            worstRow = std::size_t(i);
        }
    }
    e.rows = rows;
    if (rows) {
        e.mean = sumMean / double(rows);
        e.max = sumMax / double(rows);
        e.rms = sumRms / double(rows);
        e.rowL1 = sumL1 / double(rows);
    }
    e.worstMean = worstMean;
    e.worstMax = worstMax;
    e.worstRms = worstRms;
    e.worstRowL1 = worstL1;
    e.worstRow = worstRow;
    return e;
}

RadiosityError compareRadiosity(const std::vector<Rgb>& B, const std::vector<Rgb>& reference) {
    if (B.size() != reference.size()) throw Error("compare: radiosity vectors of different sizes");
    RadiosityError e;
    double sum = 0, sum2 = 0, scale = 0;
    const double count = 3.0 * double(B.size());
    for (std::size_t i = 0; i < B.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = std::abs(B[i][c] - reference[i][c]);
            sum += d;
            sum2 += d * d;
            e.max = std::max(e.max, d);
            scale += std::abs(reference[i][c]);
        }
    if (count > 0) {
        e.mean = sum / count;
        e.rms = std::sqrt(sum2 / count);
        scale /= count;
    }
    if (scale > 0) {
        e.relativeMean = e.mean / scale;
        e.relativeMax = e.max / scale;
        e.relativeRms = e.rms / scale;
    }
    return e;
}

}  // namespace hemirad
