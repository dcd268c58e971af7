// One GL context's hemicube machinery: scene buffers, the one-draw five-face pass, CPU/GPU reduction.
#pragma once

#include "engine/scene.hpp"
#include "gl/gl_objects.hpp"
#include "preprocess/hemicube/hemicube_geometry.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "preprocess/row_accumulator.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

enum class Reduction { Cpu, Gpu };

/// Per-stage seconds and pixel counts of the hemicubes a renderer drew.
struct HemicubeStats {
    double render = 0, readback = 0, reduce = 0, collect = 0;
    std::uint64_t hemicubes = 0, pixels = 0, missed = 0, backfaces = 0;
    double lostWeight = 0;  ///< sum over rows of the row fraction that saw nothing or a back face
};

/// Requires a current GL 4.5 context for its whole life (construction, use, destruction).
class HemicubeRenderer {
public:
    HemicubeRenderer(const Scene& scene, const HemicubeGeometry& geometry, const HemicubeLayout& layout,
                     Reduction reduction);
    ~HemicubeRenderer();

    /// Draws patch i's hemicube and deposits each pixel's delta form factor on the patch it sees
    /// (weights in `row` relative to 1 = the whole row).
    void computeRow(PatchId i, RowAccumulator& row, HemicubeStats& stats);

    /// The id atlas of the last hemicube (patch id + 1; 0 nothing; 0xffffffff back face), rows bottom-up.
    std::vector<std::uint32_t> readIds();

private:
    void render(PatchId i);
    void reduceOnCpu(RowAccumulator& row, HemicubeStats& stats);
    void reduceOnGpu(RowAccumulator& row, HemicubeStats& stats);

    const Scene& m_scene;
    const HemicubeGeometry& m_geometry;
    const HemicubeLayout& m_layout;
    Reduction m_reduction;
    gl::Program m_draw[4];  ///< one per HemicubeGeometry::Kind (empty when the scene has none)
    gl::Program m_reduce, m_collect;
    gl::VertexArray m_vao;
    gl::Buffer m_vertices, m_parents, m_weights, m_accumulator, m_touched, m_values;
    gl::Texture m_ids;
    gl::Renderbuffer m_depth;
    gl::Framebuffer m_fbo;
    std::vector<std::uint32_t> m_pixels;
    double m_fixedScale = 0;
};

}  // namespace hemirad
