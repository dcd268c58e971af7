// Patch polygons packed for the analytic estimator's scans over every patch (direct factors and
// mirror images).
#pragma once

#include "engine/scene.hpp"

#include <cstdint>
#include <cmath>
#include <vector>

namespace hemirad {

struct PatchShape {
    Vec3 centroid, normal;
    double radius = 0.0;  ///< largest centroid-to-corner distance
    std::uint32_t first = 0, count = 0;  ///< corners in PatchGeometry::corners
};

struct PatchGeometry {
    std::vector<PatchShape> shapes;
    std::vector<Vec3> corners;  ///< corner positions in patch order
    std::vector<std::uint32_t> neighbourStart;  ///< CSR: patches sharing a corner position with patch j
    std::vector<PatchId> neighbours;
    std::vector<std::uint8_t> openEdge;  ///< per patch: some edge of it is no other patch's edge

    void build(const Scene& scene) {
        shapes.resize(scene.size());
        corners.resize(scene.corners.size());
        for (PatchId j = 0; j < scene.size(); ++j) {
            const Patch& p = scene.patches[j];
            PatchShape& t = shapes[j];
            t = {p.centroid, p.normal, 0.0, p.firstCorner, p.cornerCount};
            for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
                corners[p.firstCorner + k] = scene.vertices[scene.corners[p.firstCorner + k]];
                t.radius = std::max(t.radius, (corners[p.firstCorner + k] - p.centroid).norm());
            }
        }
    }
    const Vec3* polygon(PatchId j) const { return &corners[shapes[j].first]; }
    /// Corner k of patch j a hundredth of the way to its centroid: where the corner probes start
    /// (PairRules::cornerProbe) and where CoveredEmitters tests a corner.
    Vec3 insetCorner(PatchId j, std::uint32_t k) const {
        const Vec3& corner = corners[shapes[j].first + k];
        return corner + 0.01 * (shapes[j].centroid - corner);
    }

    /// Whether patch r's plane cuts patch e: e's corners lie on both sides of it, further than 1e-9
    /// of e's radius. Lambert's factor from e's points to r is 0 behind r's plane and grows from 0
    /// in front of it: a kink across e that no rule over e's points weighs.
    bool planeCuts(PatchId r, PatchId e) const {
        const PatchShape& a = shapes[e];
        const PatchShape& b = shapes[r];
        const double centre = b.normal.dot(a.centroid - b.centroid), margin = 1e-9 * a.radius;
        if (!(std::abs(centre) < a.radius)) return false;  // e lies on one side whole
        bool front = false, back = false;
        for (std::uint32_t k = 0; k < a.count; ++k) {
            const double h = b.normal.dot(corners[a.first + k] - b.centroid);
            front = front || h > margin;
            back = back || h < -margin;
        }
        return front && back;
    }

    /// Fills neighbourStart and neighbours: patches sharing a corner position within 1e-9 of the
    /// scene's size (generators compute shared corners by different float expressions), and
    /// openEdge. After build().
    void buildNeighbours(const Scene& scene);

    /// Whether a mesh neighbour of j has a visibility status (0 = not aimed at) other than j's, or j
    /// is hidden (2) and has an open edge (no neighbour there to tell: the strip along a plate's rim
    /// can show past a blocker while its centre and its neighbours are hidden): j sits on a
    /// silhouette and is split into pieces.
    bool onSilhouette(PatchId j, const std::vector<std::uint8_t>& status) const {
        if (status[j] == 2 && openEdge[j]) return true;
        for (std::uint32_t e = neighbourStart[j]; e < neighbourStart[j + 1]; ++e) {
            const std::uint8_t other = status[neighbours[e]];
            if (other != 0 && other != status[j]) return true;
        }
        return false;
    }
};

}  // namespace hemirad
