// Items placed at points, looked up by position within a matching distance: how the analytic
// estimator finds corners that files give as the same point (mesh neighbours, a solid's edges).
#pragma once

#include "engine/math.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace hemirad {

/// A hash grid of cells 4 matching distances wide: two points within the matching distance lie in
/// the same or adjacent cells, so a look-up visits the point's cell and the 26 around it. The
/// visits are candidates, in a fixed order (cells by dx, dy, dz from -1 to 1; a cell's items as
/// added): the caller checks the distance.
template <class Item>
class PointGrid {
public:
    explicit PointGrid(double match) : m_match(match) {}

    void add(const Vec3& p, const Item& item) { m_cells[cell(p)].push_back(item); }

    /// visit(item) for every item in p's cell and the cells around it.
    template <class Visit>
    void nearby(const Vec3& p, Visit visit) const {
        const Key c = cell(p);
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dz = -1; dz <= 1; ++dz) {
                    const auto it = m_cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == m_cells.end()) continue;
                    for (const Item& item : it->second) visit(item);
                }
    }

private:
    using Key = std::array<std::int64_t, 3>;
    struct Hash {
        std::size_t operator()(const Key& k) const {
            return std::size_t(k[0]) * 0x9e3779b97f4a7c15ULL ^ std::size_t(k[1]) * 0xc2b2ae3d27d4eb4fULL ^ std::size_t(k[2]);
        }
    };
    Key cell(const Vec3& p) const {
        return {std::llround(p.x() / m_match / 4), std::llround(p.y() / m_match / 4), std::llround(p.z() / m_match / 4)};
    }

    double m_match;
    std::unordered_map<Key, std::vector<Item>, Hash> m_cells;
};

}  // namespace hemirad
