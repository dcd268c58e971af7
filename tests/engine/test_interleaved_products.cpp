// Products of F with many right-hand sides at once (a year's hours, a sky's cells): every width,
// interleaved or in tiles, against one column at a time.
#include "engine/form_factors.hpp"
#include "engine/interleaved_rows.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace hemirad;

namespace {

/// A random sparse F, rows of 0..40 entries with a self factor now and then.
FormFactors randomF(std::size_t n, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> value(0.0f, 0.05f);
    std::vector<std::vector<FormFactors::Entry>> rows(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t count = random() % 41;
        for (std::size_t k = 0; k < count; ++k) rows[i].push_back({std::uint32_t(random() % n), value(random)});
        std::sort(rows[i].begin(), rows[i].end(), [](auto& a, auto& b) { return a.column < b.column; });
        rows[i].erase(std::unique(rows[i].begin(), rows[i].end(), [](auto& a, auto& b) { return a.column == b.column; }),
                      rows[i].end());
    }
    return FormFactors::fromRows(std::move(rows), std::vector<std::uint8_t>(n, 1));
}

}  // namespace

TEST_CASE("F times many right-hand sides: each column as it is alone, whatever the width and the tiles") {
    const std::size_t n = 700;  // more than a block of rows
    const FormFactors F = randomF(n, 7);
    std::mt19937 random(3);
    std::uniform_real_distribution<double> x(-1.0, 1.0);
    for (const std::size_t width : {1, 3, 15, 16, 17, 33, 157}) {
        CAPTURE(width);
        std::vector<double> X(n * width);
        for (double& v : X) v = x(random);
        std::vector<double> Y;
        multiplyInterleaved(F, width, X.data(), Y);
        REQUIRE(Y.size() == n * width);
        // Column c alone: the interleaved product of width 1 (the same sums in the row's order).
        for (std::size_t c = 0; c < width; ++c) {
            std::vector<double> column(n), alone;
            for (std::size_t j = 0; j < n; ++j) column[j] = X[j * width + c];
            multiplyInterleaved(F, 1, column.data(), alone);
            for (std::size_t i = 0; i < n; ++i) {
                double plain = 0.0;  // and by hand, to rounding
                for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) plain += double(F.values()[k]) * column[F.columns()[k]];
                REQUIRE(Y[i * width + c] == alone[i]);
                REQUIRE(std::abs(Y[i * width + c] - plain) <= 1e-14);
            }
        }
    }
    // Tiles of uneven widths, one after the other: each tile's columns as in the interleaved product.
    const std::vector<int> widths = {16, 5, 1, 12};
    std::size_t total = 0;
    for (const int w : widths) total += std::size_t(w);
    std::vector<double> X(n * total), Y(n * total);
    for (double& v : X) v = x(random);
    multiplyTiled(F, widths, X.data(), Y.data());
    std::size_t offset = 0;
    for (const int w : widths) {
        std::vector<double> tile;
        multiplyInterleaved(F, std::size_t(w), X.data() + offset, tile);
        for (std::size_t k = 0; k < tile.size(); ++k) REQUIRE(Y[offset + k] == tile[k]);
        offset += n * std::size_t(w);
    }
}
