// The hemicube back end's own options.
#pragma once

#include "gl/gl_context.hpp"

#include <cstdint>

namespace hemirad {

/// Where a hemicube's pixels are summed into its row.
enum class Reduction { Cpu, Gpu };
/// How the hemicube follows mirrors: stencil portals with reflected views, or Embree rays from the
/// pixels that see a mirror (the reference system's hybrid).
enum class HemicubeMirrors { Portals, Rays };

struct HemicubeOptions {
    static constexpr const char* kMethod = "hemicube";
    std::uint32_t resolution = 128;  ///< top face R x R pixels, sides R x R/2 (R even)
    Reduction reduce = Reduction::Cpu;
    GlApiKind gl = GlApiKind::Auto;
    bool parentPolygons = true;      ///< draw subdivided parents whole, patch ids from their grids
    HemicubeMirrors mirrors = HemicubeMirrors::Portals;
    /// Hemicubes per patch: 1 = the centroid; K > 1 = the m x m Gauss-Legendre points (m = ceil(sqrt K))
    /// the analytic estimator uses, each hemicube weighted by its point's weight (area sampling).
    std::uint32_t origins = 1;
    /// Hemicubes drawn per pass (layers of the atlas array, one instanced draw); 0 = by renderer
    /// (hemicubeLayers). Scenes with mirrors go row by row.
    std::uint32_t batch = 0;
};

}  // namespace hemirad
