// Hemicube back end: OpenGL renders patch ids on the five faces of a hemicube around each patch.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemicube/hemicube_geometry.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "preprocess/hemicube/hemicube_options.hpp"
#include "rays/ray_scene.hpp"

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace hemirad {

/// Whether GL_RENDERER names a renderer that rasterises on the CPU (Mesa's llvmpipe, softpipe,
/// swrast): there each context renders on its own core.
bool isSoftwareRenderer(std::string_view renderer);

/// GL contexts (worker threads) for the hemicube: `requested` when the user asked (--threads > 0);
/// else one per core on a software renderer, and one on a GPU, where contexts serialise (measured on
/// an H100: 4.0 s with one context, 6.0 s with two, 35 s with sixteen for a 13k-patch box).
int hemicubeWorkers(std::string_view renderer, int requested, int cores);

/// Whether the workers' contexts take turns, each GL command sequence under the process's one
/// sharedDriverMutex (their CPU reductions still overlap): on a software renderer. Mesa 22.3's
/// llvmpipe (Debian 12) crashes now and then when two contexts draw at once: a segmentation fault
/// inside the driver in about one run of 250 of a mirror scene on a loaded 2-core machine
/// (cornell_mirror, --subdivide 100, R = 32).
bool hemicubeSerializesContexts(std::string_view renderer);

/// Where pixels are summed (--reduce): `requested` unless Auto; else on the CPU with a software
/// renderer (its compute shaders run on the same cores, and reading the atlas costs a memcpy) and
/// on the GPU otherwise (only a row's nonzeros cross the bus: at R = 256 the atlas is 768 KiB a row).
Reduction hemicubeReduction(std::string_view renderer, Reduction requested);

/// Passes in flight (--in-flight): `requested` when given (> 0); else 1 on a software renderer
/// (its contexts, one per core, already overlap each other's work) and 3 on a GPU (it draws two
/// passes ahead while the CPU copies one pass's rows).
std::uint32_t hemicubeInFlight(std::string_view renderer, std::uint32_t requested);

/// CPU threads per GL context that sum finished passes into rows (--row-threads): `requested` when
/// given (>= 0); else none on a software renderer (its `workers` contexts rasterise on every core)
/// and on a GPU the `cores` the workers leave, shared among them (a single GL thread would
/// otherwise copy every row itself).
int hemicubeRowThreads(std::string_view renderer, int requested, int cores, int workers);

/// Hemicubes drawn per pass (--batch): `requested` when given (> 0), else by renderer (software: see
/// the definition; GPU: up to 256, so that one round trip serves many rows); at most `maxLayers` (the
/// driver's array layers), what keeps each GPU-reduction buffer within `maxBlockBytes` (the largest
/// shader storage block; 0 = no limit), and what fits in 256 MiB of atlas (`stencil`: a mirror
/// scene's), reduction and `inFlight` result buffers; when batching, at least a row's `points`
/// hemicubes where the driver's limits allow.
std::uint32_t hemicubeLayers(std::string_view renderer, std::uint32_t requested, std::uint32_t resolution,
                             std::size_t patches, bool gpuReduction, std::uint32_t points, std::uint32_t maxLayers,
                             std::uint32_t inFlight = 1, bool stencil = false, double maxBlockBytes = 0);

/// Per patch, whether a hemicube on it may see a mirror's front (then its row goes row by row, with
/// portals): some corner of the mirror's group (its bounding box) above the patch's plane, and some
/// corner of the patch in front of the group's plane, with margins wider than the draw's own
/// plane test and float rounding. Conservative: false only where no hemicube pixel can land on a mirror.
std::vector<bool> rowsThatMaySeeMirrors(const Scene& scene, double extent);

/// Cohen & Greenberg (1985): each pixel of the hemicube atlas carries its delta form factor;
/// F_ij sums the pixels that see patch j's front. One GL context per worker thread (headless EGL
/// on Mesa's llvmpipe here, any GPU driver elsewhere), each computing its own rows.
class HemicubeBackend final : public FormFactorBackend {
public:
    HemicubeBackend(const HemicubeOptions& options, const CommonOptions& common);
    ~HemicubeBackend() override;

    std::string_view name() const override { return "hemicube"; }
    void prepare(const Scene& scene) override;
    using FormFactorBackend::computeRows;
    void computeRows(RowSource& rows, FormFactorBuilder& builder) override;
    FormFactorProvenance provenance() const override;
    std::map<std::string, std::string> parameters() const override;
    std::string device() const override;

private:
    HemicubeOptions m_options;
    CommonOptions m_common;
    const Scene* m_scene = nullptr;
    std::unique_ptr<HemicubeLayout> m_layout;
    HemicubeGeometry m_geometry;
    std::unique_ptr<RayScene> m_rays;  ///< for --mirrors rays
    int m_workers = 1;
    std::vector<double> m_nodes, m_nodeWeights;  ///< the Gauss-Legendre rule on [0, 1] for --origins
    std::uint32_t m_points = 1;  ///< hemicubes per row
    std::uint32_t m_layers = 1;  ///< hemicubes per pass
    std::uint32_t m_inFlight = 1;  ///< passes in flight
    int m_rowThreads = 0;  ///< CPU threads summing finished passes, beside the GL contexts
    Reduction m_reduction = Reduction::Cpu;  ///< --reduce, resolved by renderer
    std::vector<bool> m_mirrorRows;  ///< rows that go row by row (rowsThatMaySeeMirrors)
    std::string m_renderer;  ///< GL_RENDERER of the context prepare() made
};

struct BackendDescriptor;
/// The registry entry (hemicube_descriptor.cpp).
const BackendDescriptor& hemicubeDescriptor();

}  // namespace hemirad
