// Overlapping pairs of axis-aligned boxes through a hierarchy of uniform grids (a loose multigrid).
#pragma once

#include "engine/math.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace hemirad {

/// An axis-aligned box, lo <= hi per axis.
struct Box {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    bool overlaps(const Box& o) const {
        return lo.x() <= o.hi.x() && o.lo.x() <= hi.x() && lo.y() <= o.hi.y() && o.lo.y() <= hi.y() &&
               lo.z() <= o.hi.z() && o.lo.z() <= hi.z();
    }
};

/// Calls visit(a, b), a < b, once for every pair of boxes that overlap (touching counts).
///
/// Each box goes into the grid level whose cells are at least its size (level 0: the median box
/// size; level L: 2^L times that), so it covers at most 2 x 2 x 2 cells there. A box looks for
/// partners in its own level and every coarser one, so each pair is met from its smaller box; of the
/// cells both boxes cover, only the one holding the low corner of their intersection reports it.
/// Work is O(n log n) for boxes of any size mix (sorting the cell entries), O(n) pairs for a mesh.
/// Boxes with non-finite coordinates are left out. Single-threaded; `visit` runs on the caller's thread.
void forEachOverlappingPair(const std::vector<Box>& boxes,
                            const std::function<void(std::uint32_t, std::uint32_t)>& visit);

}  // namespace hemirad
