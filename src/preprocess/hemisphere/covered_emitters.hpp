// Emitters that a solid stands on in part: a block on a floor patch, a building on a ground face
// that was not cut around its footprint (non-conforming meshes). The part under the solid sees
// nothing, wherever the emitter's rule points lie; the rules over such an emitter integrate over
// its free part alone.
#pragma once

#include "preprocess/hemisphere/patch_geometry.hpp"
#include "rays/ray_scene.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

class CoveredEmitters {
public:
    /// Cells per side of the grid a covered patch is resolved on (polygonQuadrature's map: the
    /// quad's bilinear square, or each fan triangle's collapsed one), per part (fan triangle).
    static constexpr int kCells = 16;
    /// A cell whose centre's status differs from a neighbour's holds the solid's edge: it takes
    /// this many points per side instead (its free part's area and centroid).
    static constexpr int kSubcells = 8;
    /// Every patch is looked at first on a grid this fine and at its corners; the full grid only
    /// where that finds a covered point (a sliver of cover between those points is missed).
    static constexpr int kFirstLook = 4;

    /// Finds the covered patches. A point is covered when the ray along its patch's normal meets
    /// the back of a patch first, and so do eight rays tilted 60 and 85 degrees from it, four
    /// ways each: it lies inside a closed solid. A one-sided slab (a table top without an
    /// underside) covers a point only where it reaches past 11 times its height on every side.
    /// A patch counts as covered only where some of its area is.
    void build(const PatchGeometry& geometry, const RayScene& rays);
    bool covered(PatchId e) const { return !m_index.empty() && m_index[e] != kNone; }
    /// Covered patches found.
    std::size_t count() const { return m_cells.size(); }
    /// The m x m rule over covered e's free part: per block of (kCells / m)^2 cells, their free
    /// area over e's (the weights sum to e's free fraction) at the area centroid of its free
    /// cells; where the solid covers some of the block, per tile of kTile x kTile cells of it, at
    /// the tile's free centroid if all of the tile is free, else at its free cell nearest to that
    /// centroid (the centroid of an L-shaped strip lies under the solid). At most
    /// (kCells / kTile)^2 points where m is below that.
    static constexpr int kTile = 4;
    void freeRule(PatchId e, int m, std::vector<Vec3>& points, std::vector<double>& weights) const;
    /// Whether corner k of e, a hundredth inside, is covered (false for a patch not covered).
    bool cornerCovered(PatchId e, std::uint32_t k) const;

private:
    static constexpr std::uint32_t kNone = ~std::uint32_t(0);
    struct Cells {
        std::vector<Vec3> centres;
        std::vector<double> weights;  ///< area over e's; 0 for a covered cell
        std::vector<std::uint8_t> whole;  ///< per cell: all of it free
        std::uint32_t parts = 1;      ///< fan triangles (1 for a quad)
        std::vector<std::uint8_t> cornerCovered;
    };
    std::vector<std::uint32_t> m_index;  ///< per patch: into m_cells, or kNone
    std::vector<Cells> m_cells;
};

}  // namespace hemirad
