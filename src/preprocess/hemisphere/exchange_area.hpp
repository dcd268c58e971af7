// The exact unoccluded exchange area A_e F_er of two planar convex polygons in any contact (shared
// corners, partly shared or collinear edges, corners on the other's edge): Stokes' double contour
// integral with the singular edge pairs integrated on graded rules.
#pragma once

#include "engine/math.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hemirad {

/// How two patches touch, classified once per pair (geometry only, tolerance relative to their size).
enum class PairContact : std::uint8_t {
    None,            ///< apart: no point of one lies on the other
    SharedCorner,    ///< a corner of each at one point, nothing more
    CornerOnEdge,    ///< a corner of one inside an edge of the other (a T-junction's contact)
    CornerOnPatch,   ///< a corner of one inside the other (touching its plane at one point)
    EdgeOverlap,     ///< collinear edges sharing a segment, in part or whole
    Coplanar,        ///< in one plane (no exchange whatever they share)
};
const char* contactName(PairContact contact);

/// The contact of convex polygons a[0..na) and b[0..nb) (normals na_, nb_), with distances below
/// `tolerance` counted as touching.
PairContact classifyContact(const Vec3* a, std::size_t na, const Vec3& normalA, const Vec3* b, std::size_t nb,
                            const Vec3& normalB, double tolerance);

/// An edge of a contour: start, unit direction, length.
struct ContourEdge {
    Vec3 start, direction;
    double length;
};

/// Per-thread scratch of exchangeArea: the clipped polygons and their edges.
struct ExchangeAreaScratch {
    std::vector<Vec3> e, r;  ///< after a call with a positive result: the parts in front of each other
    std::vector<ContourEdge> edgesE, edgesR;
};

/// A_e F_er = A_r F_re for the convex planar polygons e[0..ne) and r[0..nr), corners counter-clockwise
/// about their unit normals normalE and normalR, with nothing in between: the factor of their parts
/// in front of each other (each clipped to the half-space in front of the other's plane, where the
/// kernel cos cos' / (pi s^2) is not zero), by Stokes' theorem
///     A_e F_er = 1 / (2 pi) sum_(edges a of e, b of r) (u_a . u_b) int_a int_b ln |x - y| dt ds
/// (Sparrow 1963; Howell's catalogue derives C-14 the same way, and NIST View3D integrates shared
/// edges analytically). The inner integral is closed-form; the outer one Gauss-Legendre on pieces
/// cut where edge a comes closest to edge b or to its ends, graded towards a contact, so that a
/// touching pair (shared or overlapping edges, a corner on an edge) is as exact as a distant one:
/// about 1e-12 relative. Symmetric in (e, r) up to rounding; 0 for coplanar or back-to-back pairs.
double exchangeArea(const Vec3* e, std::size_t ne, const Vec3& normalE, const Vec3* r, std::size_t nr,
                    const Vec3& normalR, ExchangeAreaScratch& scratch);

}  // namespace hemirad
