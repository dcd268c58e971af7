// Closed convex solids among the blockers: a block, a faceted sphere or cylinder, a building on its
// ground. From a point outside such a solid, its faces turned away from the point lie in the
// shadows of its faces turned towards it, so shadow polygons need only the latter.
#pragma once

#include "engine/math.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

/// The solids: blocker patches joined along lines where the edges of one side are covered by the
/// other side's, running the other way (consistently oriented; whole edges shared or T-junctions:
/// a roof's edge against a wall in strips), at convex or flat edges; whose remaining (open) edges
/// all lie in one plane, the solid's open side (none for a closed surface; the bottom of a block
/// standing on a floor, of a building on its ground); with every corner behind or on every face's
/// plane and the open side's (convex, facing out). A component that fails any of these (an
/// inward-facing box, a dented or L-shaped solid, open edges in two planes: a building whose wall
/// stands on a neighbour's roof) is no solid, and its faces cast their shadows as before.
class ConvexSolids {
public:
    static constexpr std::uint32_t kNone = ~std::uint32_t(0);

    /// blocks[j] != 0 marks the blockers. Components whose planes times corners exceed kMostChecks
    /// are not checked (and are no solid).
    void build(const PatchGeometry& geometry, const std::vector<std::uint8_t>& blocks);

    /// The solid patch j is a face of, or kNone.
    std::uint32_t solidOf(PatchId j) const { return m_solidOf.empty() ? kNone : m_solidOf[j]; }
    std::size_t size() const { return m_solids.size(); }
    /// The patches that are faces of a solid.
    std::size_t faces() const { return m_faces; }
    /// Whether every line from x into solid `solid` enters through a face turned towards x: x lies
    /// in front of some face's plane (outside the solid, further than the solid's tolerance) and
    /// not in front of its open side's plane (a line entering by the open side meets no face
    /// first: a lidless box seen from below). Then a face turned away from x casts no shadow of
    /// its own.
    /// `hint`: per solid, the plane to try first (the last one found in front; sized by the
    /// call, one per thread).
    bool entersByFrontFace(std::uint32_t solid, const Vec3& x, std::vector<std::uint32_t>& hint) const;
    /// The same for the lines of a parallel beam along the direction `toSource` (towards the source,
    /// light travelling the other way): every such line that meets the solid enters it through a
    /// face turned towards the source, and leaves it (or reaches a receiver inside) only after that;
    /// true unless the open side faces the source (a lidless box with the sun above its rim).
    bool beamEntersByFrontFace(std::uint32_t solid, const Vec3& toSource) const {
        const Solid& q = m_solids[solid];
        return !q.open || q.openNormal.dot(toSource) <= 0.0;
    }
    /// Whether the solid has an open side.
    bool open(std::uint32_t solid) const { return m_solids[solid].open; }
    /// The box around the solid's corners: lo, hi; and the ball about the box's centre that holds
    /// them, its radius.
    const Vec3& lo(std::uint32_t solid) const { return m_solids[solid].lo; }
    const Vec3& hi(std::uint32_t solid) const { return m_solids[solid].hi; }
    double radius(std::uint32_t solid) const { return m_solids[solid].radius; }

    /// Convex, flat and outside within this share of the solid's size (the rounding of corners as
    /// files give them): a line grazing a face closer than that may lose a sliver of its shadow.
    static constexpr double kFlatness = 1e-5;
    /// The most plane-corner checks of convexity per component (a finer solid than this is no solid).
    static constexpr std::uint64_t kMostChecks = 50000000;

private:
    struct Solid {
        std::uint32_t firstPlane = 0, planes = 0;  ///< its distinct face planes in m_normals/m_offsets
        bool open = false;                         ///< has an open side
        Vec3 openNormal = Vec3::Zero();            ///< the open side's plane, normal out of the solid
        double openOffset = 0.0;
        double tolerance = 0.0;                    ///< kFlatness of its size
        Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< the box around its corners
        double radius = 0.0;                        ///< of the ball about the box's centre holding them
    };
    std::vector<std::uint32_t> m_solidOf;
    std::size_t m_faces = 0;
    std::vector<Solid> m_solids;
    std::vector<Vec3> m_normals;
    std::vector<double> m_offsets;
};

}  // namespace hemirad
