// The hemicube back end's own options.
#pragma once

#include "gl/gl_context.hpp"

#include <cstdint>

namespace hemirad {

/// Where a hemicube's pixels are summed into its row; Auto: by renderer (hemicubeReduction).
enum class Reduction { Auto, Cpu, Gpu };
/// How the hemicube follows mirrors: stencil portals with reflected views, or Embree rays from the
/// pixels that see a mirror (the reference system's hybrid).
enum class HemicubeMirrors { Portals, Rays };

struct HemicubeOptions {
    static constexpr const char* kMethod = "hemicube";
    std::uint32_t resolution = 128;  ///< top face R x R pixels, sides R x R/2 (R even)
    Reduction reduce = Reduction::Auto;
    GlApiKind gl = GlApiKind::Auto;
    bool parentPolygons = true;      ///< draw subdivided parents whole, patch ids from their grids
    HemicubeMirrors mirrors = HemicubeMirrors::Portals;
    /// Hemicubes per patch: 1 = the centroid; K > 1 = the m x m Gauss-Legendre points (m = ceil(sqrt K))
    /// the analytic estimator uses, each hemicube weighted by its point's weight (area sampling).
    std::uint32_t origins = 1;
    /// Hemicubes drawn per pass (layers of the atlas array, one instanced draw); 0 = by renderer
    /// (hemicubeLayers). Rows that may see a mirror go row by row (their portals depend on what
    /// each hemicube saw).
    std::uint32_t batch = 0;
    /// Passes in flight (read back or reduced while the next ones draw); 0 = by renderer
    /// (hemicubeInFlight). 1 = each pass finished before the next starts.
    std::uint32_t inFlight = 0;
    /// CPU threads that sum finished passes into rows beside the GL contexts; -1 = by renderer
    /// (hemicubeRowThreads), 0 = the GL thread does it.
    int rowThreads = -1;
};

}  // namespace hemirad
