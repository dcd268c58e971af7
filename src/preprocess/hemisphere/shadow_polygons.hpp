// Exact visibility of a polygon from a point past polygonal blockers: the analytic estimator's
// partial visibility for pairs whose factor is too large to trust one shadow ray.
#pragma once

#include "engine/math.hpp"
#include "preprocess/hemisphere/convex_pieces.hpp"
#include "preprocess/hemisphere/convex_solids.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hemirad {

/// The shadow-polygon method (as View3D treats partly obstructed views): every blocker reaching
/// into the cone from a point x through a convex receiver is clipped to that cone and projected
/// from x onto the receiver's plane; the receiver's part outside all these shadows, kept as convex
/// pieces, gets Lambert's factor. Exact for planar convex blockers (back faces block too); the
/// blockers are the patches flagged by obstructingPatches, found through a bounding-volume tree.
/// A convex solid's faces that the point sees from behind cast no shadow where the faces it sees
/// cover theirs (ConvexSolids): about half the shadows that a block or a faceted sphere casts; and
/// where such a solid has 8 blocker polygons or more and neither the point's patch nor the
/// receiver is one of its faces, the faces the point sees cast one shadow together, the convex
/// hull of their projected corners (a faceted sphere's dozens of facets in a cone one cut).
class ShadowPolygons {
public:
    /// Per-thread scratch (reused between calls).
    struct Scratch {
        std::vector<std::uint32_t> stack;
        std::vector<Vec3> cut, cutNext;           // a blocker clipped to the cone
        std::vector<double> sides;                // its corners' distances to a plane of the cone
        ConvexPieces clear;                       // the receiver's clear part, 2D
        std::vector<double> shadow, firstShadow;
        std::vector<Vec3> image, first;           // the shadow's corners on the receiver (3D)
        std::vector<Vec3> lifted;
        std::vector<Vec3> onPlane;                // a beam's receiver corners moved along it onto the receiver's plane
        std::vector<Vec3> planeNormals;           // the cone's planes (inward normals and offsets)
        std::vector<double> planeOffsets;
        Vec3 u, v;                                // the receiver plane's 2D axes (origin its corner 0)
        std::size_t shadows = 0;                  // shadows met by the last call
        std::vector<std::pair<std::uint32_t, bool>> solidsSeen;  // this point's solids: entered by a front face?
        std::vector<std::uint32_t> solidHint;     // per solid, the plane last found in front
        std::vector<std::pair<std::uint32_t, int>> hullFits;  // this call's solids: one shadow each? (castShadows)
        std::vector<std::uint32_t> deferred;      // their faces met in the region
        std::vector<std::array<double, 2>> hullPoints, hull;  // a solid's projected corners, their hull
        std::vector<double> outline, hullScratch, hullRest;  // the receiver in 2D (counter-clockwise); scratch
    };

    /// The tree over the patches with blocks[j] != 0 of `geometry` (its neighbours built). Connected
    /// coplanar blockers whose union is convex (a subdivided face) become one blocker polygon: one
    /// shadow instead of a tile per patch.
    /// `merge` false: every blocker stays its own patch (owner() names it), for searches of patches.
    /// `solids` (with `merge`): the faces of convex solids (ConvexSolids) that a point sees from
    /// behind cast no shadow from it, as the solid's faces turned towards it cover theirs; false
    /// keeps every face (tests compare the two).
    void build(const PatchGeometry& geometry, const std::vector<std::uint8_t>& blocks, bool merge = true,
               bool solids = true);
    /// Convex solids found among the blockers (0 without `solids`).
    std::size_t solids() const { return m_solids.size(); }
    /// The patches that are faces of those solids.
    std::size_t solidFaces() const { return m_solids.faces(); }
    bool empty() const { return m_owner.empty(); }
    /// Blocker polygons (after merging).
    std::size_t size() const { return m_owner.size(); }
    /// The patch blocker b is (built without merging: every blocker is one).
    PatchId owner(std::uint32_t b) const { return m_owner[b]; }

    /// The 2D axes of a plane with unit `normal` that shadow polygons use (u, v, normal right-handed).
    static void planeAxes(const Vec3& normal, Vec3& u, Vec3& v);
    /// Appends the sides of the prism that convex polygon p sweeps along `along` (either way): a
    /// plane through each edge and the direction, unit normal inward, normal . y = offset.
    static void prismSides(const Vec3* p, std::size_t count, const Vec3& along, std::vector<Vec3>& normals,
                           std::vector<double>& offsets);

    /// Lambert's factor from x (unit normal n) to the part of the convex polygon p[0..count) that no
    /// blocker other than patches e and r hides from x. p is receiver r's polygon or its part above
    /// x's plane; `whole` is its unobstructed factor, returned unchanged when no shadow falls on it.
    /// `within` (optional): the blockers to consider, from collect() over a region that holds every
    /// cone this is asked for (a pair's shaft), instead of a search of the tree.
    double visibleFactor(const Vec3& x, const Vec3& n, const Vec3* p, std::size_t count, PatchId e, PatchId r,
                         double whole, Scratch& scratch, const std::vector<std::uint32_t>* within = nullptr) const;

    /// The fraction of the convex polygon p[0..count) (receiver r, unit `normal`) that a parallel
    /// beam from the unit direction `toSource` reaches past every blocker other than r: each
    /// blocker's part inside the prism swept from p towards the source and in front of p's plane
    /// (a blocker within `tolerance` of the plane or behind it casts nothing) projected along the
    /// beam and cut out. 0 where p faces away. Exact for planar convex blockers (back faces block
    /// too), as visibleFactor.
    double litFraction(const Vec3* p, std::size_t count, const Vec3& normal, PatchId r, const Vec3& toSource,
                       double tolerance, Scratch& scratch) const;

    /// Cuts out of scratch.clear.pieces (convex 2D pieces, counter-clockwise, in the plane of p:
    /// origin p[0], axes planeAxes(normal)) what a parallel beam from the unit direction `toSource`
    /// cannot reach: each blocker other than r inside the prism swept from p towards the source, in
    /// front of p's plane and, with `slabNormal`, of the plane slabNormal . y = slabOffset, projected
    /// along the beam. No piece is left where p faces away.
    void shadeBeam(const Vec3* p, std::size_t count, const Vec3& normal, PatchId r, const Vec3& toSource, double tolerance,
                   const Vec3* slabNormal, double slabOffset, Scratch& scratch) const;

    /// Whether the ray from x along the unit direction d meets a blocker further than `tolerance`
    /// from x (the blocker x lies on is not met), a polygon's edges counting as in it.
    bool blocksRay(const Vec3& x, const Vec3& d, double tolerance, Scratch& scratch) const;

    /// Whether some blocker other than patches e and r may reach into the convex region where
    /// m_k . y - d_k > tolerance for every plane k (conservative: a blocker that no single plane
    /// leaves wholly outside counts). A pair's shaft test (contact_pairs.hpp).
    bool reaches(const Vec3* m, const double* d, std::size_t planes, double tolerance, PatchId e, PatchId r,
                 Scratch& scratch) const;
    /// The blockers (indices for visibleFactor's `within`) that reaches() would find, all of them.
    void collect(const Vec3* m, const double* d, std::size_t planes, double tolerance, PatchId e, PatchId r,
                 std::vector<std::uint32_t>& blockers, Scratch& scratch) const;

private:
    /// Cuts out of p[0..count) (in the plane of unit `normal`) the shadow of each blocker other than
    /// e and r inside the region of the scratch's first `planes` planes (from the tree, or `within`):
    /// the blocker clipped to them and each corner sent onto p's plane by project(y). Leaves
    /// scratch.shadows, and the one shadow (first, firstShadow) or the clear pieces. `base`: the
    /// offset of the region's plane along p's (normal . y >= base), where a convex solid's faces are
    /// cut when they cast one shadow together (castShadows' hullShadow).
    /// `nearFirst` and `box` as traverse takes them. `given`: the clear pieces are scratch.clear's
    /// already (every shadow cut from them), not the whole of p.
    /// `eye` (a central projection from that point) or `beam` (a parallel one from that direction
    /// to the source): a convex solid's faces turned away from it pass (turnedAway, beamTurnedAway).
    template <class Project>
    void castShadows(const Vec3* p, std::size_t count, const Vec3& normal, double base, std::size_t planes,
                     double tolerance, PatchId e, PatchId r, Scratch& s, const std::vector<std::uint32_t>* within,
                     Project project,
                     const Vec3* nearFirst = nullptr, const Vec3* box = nullptr, bool given = false,
                     const Vec3* eye = nullptr, const Vec3* beam = nullptr) const;
    /// Whether blocker b is a face of a convex solid (ConvexSolids) turned away from x, with every
    /// line from x into the solid entering by a face turned towards it: b's shadow from x lies in
    /// theirs. Caches each solid's answer in s.solidsSeen (cleared per point by the caller).
    bool turnedAway(std::uint32_t b, const Vec3& x, Scratch& s) const;
    /// Whether every line from x into the solid enters by a face turned towards x
    /// (ConvexSolids::entersByFrontFace), cached in s.solidsSeen.
    bool entered(std::uint32_t solid, const Vec3& x, Scratch& s) const;
    /// Whether blocker b is a face of a convex solid turned away from the source of a parallel beam
    /// along `toSource`, with every line of the beam that meets the solid entering by a face turned
    /// towards the source (ConvexSolids::beamEntersByFrontFace): b's shadow lies in theirs.
    bool beamTurnedAway(std::uint32_t b, const Vec3& toSource) const;
    /// The scratch's planes for a parallel beam from `toSource` through p (the prism's sides, p's
    /// plane, the slab's plane when given), and in `box` (lo, hi) a box holding the prism's part in
    /// the tree's box; false where there is none to give (the box then unused).
    bool beamRegion(const Vec3* p, std::size_t count, const Vec3& normal, const Vec3& toSource, double tolerance,
                    const Vec3* slabNormal, double slabOffset, Scratch& s, Vec3* box) const;
    /// Calls visit(b) for each blocker b other than e and r that no plane (m, d) leaves entirely
    /// outside (m . y - d <= tolerance), until visit returns false; with `nearFirst`, the child
    /// whose box lies lower along that direction first; with `box` (lo, hi: a box holding the
    /// region's part that matters), nodes whose boxes miss it are passed over.
    template <class Visit>
    void traverse(const Vec3* m, const double* d, std::size_t planes, double tolerance, PatchId e, PatchId r,
                  Scratch& s, Visit visit, const Vec3* nearFirst = nullptr, const Vec3* box = nullptr) const;
    struct Node {
        Vec3 lo, hi;
        std::uint32_t first = 0, count = 0;  ///< items of a leaf (count > 0)
        std::uint32_t right = 0;             ///< an inner node's second child (the first follows it)
    };
    /// Whether blocker b's corners all lie outside one of the planes (m . y - d <= tolerance).
    bool outsideSomePlane(std::uint32_t b, const Vec3* m, const double* d, std::size_t planes, double tolerance) const;
    std::uint32_t buildNode(std::uint32_t first, std::uint32_t count);
    /// `face`: a patch in the blocker's plane (the blocker itself, or a tile of a union); `solid`:
    /// the convex solid it is a face of, or ConvexSolids::kNone.
    void addBlocker(const Vec3* corners, std::size_t count, PatchId owner, PatchId face, std::uint32_t solid);

    static constexpr PatchId kMerged = ~PatchId(0);
    const PatchGeometry* m_geometry = nullptr;  ///< for the receivers' planes
    std::vector<Vec3> m_corners;         ///< blocker polygons' corners
    std::vector<std::uint32_t> m_first;  ///< per blocker, into m_corners (one past the end appended)
    std::vector<PatchId> m_owner;        ///< the patch a blocker is, or kMerged for a union of tiles
    std::vector<Vec3> m_centre;          ///< per blocker, its corners' mean (for the tree's splits)
    std::vector<std::pair<Vec3, double>> m_plane;  ///< per blocker, its plane (normal . y = offset)
    std::vector<std::uint32_t> m_solid;  ///< per blocker, its convex solid or ConvexSolids::kNone
    std::vector<std::uint32_t> m_solidBlockers;  ///< per solid, its blockers (after merging)
    /// A solid of fewer blockers casts its faces' shadows one by one (castShadows' hullShadow).
    static constexpr std::uint32_t kHullBlockers = 8;
    ConvexSolids m_solids;               ///< built with merging (searches of patches take every face)
    std::vector<std::uint32_t> m_items;  ///< blockers in tree order
    std::vector<Node> m_nodes;
};

}  // namespace hemirad
