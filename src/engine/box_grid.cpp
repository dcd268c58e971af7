// Loose multigrid of boxes: one cell size per level, doubling, each box at the level of its size.
#include "engine/box_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace hemirad {
namespace {

// Cell keys pack (level, i, j, k): 6 bits of level, 19 bits per axis. The finest cell is at least
// the boxes' span / 2^18, so every index fits.
constexpr int kAxisBits = 19;
constexpr double kFinestCells = double(1 << 18);

struct Levels {
    Vec3 origin = Vec3::Zero();
    double base = 1.0;

    double cell(int level) const { return std::ldexp(base, level); }
    std::int64_t index(double x, double o, int level) const {
        return std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((x - o) / cell(level))));
    }
    std::array<std::int64_t, 3> cellOf(const Vec3& p, int level) const {
        return {index(p.x(), origin.x(), level), index(p.y(), origin.y(), level), index(p.z(), origin.z(), level)};
    }
    static std::uint64_t key(int level, std::int64_t i, std::int64_t j, std::int64_t k) {
        return std::uint64_t(level) << (3 * kAxisBits) | std::uint64_t(i) << (2 * kAxisBits) |
               std::uint64_t(j) << kAxisBits | std::uint64_t(k);
    }
};

bool finite(const Box& b) { return b.lo.allFinite() && b.hi.allFinite(); }

double largestSide(const Box& b) { return (b.hi - b.lo).maxCoeff(); }

}  // namespace

void forEachOverlappingPair(const std::vector<Box>& boxes,
                            const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    Box all;
    all.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    all.hi = -all.lo;
    std::vector<double> sides;
    sides.reserve(boxes.size());
    for (const Box& b : boxes) {
        if (!finite(b)) continue;
        all.lo = all.lo.cwiseMin(b.lo);
        all.hi = all.hi.cwiseMax(b.hi);
        sides.push_back(largestSide(b));
    }
    if (sides.empty()) return;

    Levels grid;
    grid.origin = all.lo;
    const double span = largestSide(all);
    std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
    grid.base = std::max(sides[sides.size() / 2], span / kFinestCells);
    if (!(grid.base > 0.0)) grid.base = 1.0;  // every box one and the same point

    // Each box in the cells it covers at its level (at most 2 per axis).
    std::vector<std::uint8_t> level(boxes.size(), 0);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
    entries.reserve(boxes.size() * 2);
    bool used[64] = {};
    for (std::uint32_t id = 0; id < boxes.size(); ++id) {
        const Box& b = boxes[id];
        if (!finite(b)) continue;
        int L = 0;
        while (grid.cell(L) < largestSide(b) && L < 63) ++L;
        level[id] = static_cast<std::uint8_t>(L);
        used[L] = true;
        const auto lo = grid.cellOf(b.lo, L), hi = grid.cellOf(b.hi, L);
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
            for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
                for (std::int64_t k = lo[2]; k <= hi[2]; ++k) entries.emplace_back(Levels::key(L, i, j, k), id);
    }
    std::sort(entries.begin(), entries.end());
    std::unordered_map<std::uint64_t, std::uint32_t> first;  // cell key -> its first entry
    first.reserve(entries.size());
    for (std::uint32_t e = 0; e < entries.size(); ++e)
        if (e == 0 || entries[e].first != entries[e - 1].first) first.emplace(entries[e].first, e);

    for (std::uint32_t p = 0; p < boxes.size(); ++p) {
        const Box& b = boxes[p];
        if (!finite(b)) continue;
        for (int L = level[p]; L < 64; ++L) {
            if (!used[L]) continue;
            const auto lo = grid.cellOf(b.lo, L), hi = grid.cellOf(b.hi, L);
            for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
                for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
                    for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
                        const std::uint64_t key = Levels::key(L, i, j, k);
                        const auto it = first.find(key);
                        if (it == first.end()) continue;
                        for (std::uint32_t e = it->second; e < entries.size() && entries[e].first == key; ++e) {
                            const std::uint32_t q = entries[e].second;
                            // Same level: both boxes find the pair; the lower id reports it.
                            if (q == p || (level[q] == level[p] && q < p)) continue;
                            if (!b.overlaps(boxes[q])) continue;
                            if (grid.cellOf(b.lo.cwiseMax(boxes[q].lo), L) != std::array<std::int64_t, 3>{i, j, k})
                                continue;
                            visit(std::min(p, q), std::max(p, q));
                        }
                    }
        }
    }
}

}  // namespace hemirad
