// The hemicube back end's registry entry: its flags, work estimate and run description.
#include "preprocess/backend_registry.hpp"
#include "preprocess/hemicube/hemicube_backend.hpp"
#include "preprocess/hemisphere/emitter_rule.hpp"
#include "rays/ray_scene.hpp"

namespace hemirad {
namespace {

using C = HemicubeOptions;

RunDescription describe(const Scene&, const MethodSettings& s) {
    const C& o = s.as<C>();
    const std::string reduce = findBackend(C::kMethod).option("--reduce")->get(s);
    RunDescription d;
    const std::uint32_t points = originPoints(o.origins);
    d.settings = std::to_string(o.resolution) + " x " + std::to_string(o.resolution) + " top face (" +
                 std::to_string(3 * o.resolution * o.resolution) + " pixels), " +
                 (points == 1 ? std::string("one hemicube at the centroid")
                              : std::to_string(points) + " hemicubes per patch at Gauss-Legendre points (--origins " +
                                    std::to_string(o.origins) + ")") +
                 (o.reduce == Reduction::Auto ? ", reduction by renderer" : ", reduction on the " + reduce);
    d.record = {{"resolution", std::to_string(o.resolution)},
                {"reduce", reduce},
                {"origins", std::to_string(points)},
                {"rays_per_patch", std::to_string(3.0 * o.resolution * o.resolution * points)}};
    return d;
}

BackendDescriptor make() {
    BackendDescriptor d;
    d.name = C::kMethod;
    d.summary = "OpenGL renders patch ids on the five faces of a hemicube (Cohen & Greenberg)";
    d.workUnit = "pixels";
    d.projection = Projection::HemicubeAtlas;
    d.options = {
        integerOption<C>("--resolution", "Resolution", "R", "top face R x R pixels, sides R x R/2 (even, default 128)",
                         &C::resolution, 2, 8192, true),
        choiceOption<C, Reduction>("--reduce", "Reduction",
                                   "sum pixels into rows on the CPU or in a compute shader (default auto: the CPU on "
                                   "llvmpipe, the GPU on a GPU)",
                                   &C::reduce, {{"auto", Reduction::Auto}, {"cpu", Reduction::Cpu}, {"gpu", Reduction::Gpu}}),
        choiceOption<C, GlApiKind>("--gl", "OpenGL", "headless OpenGL API (default auto: EGL, then OSMesa)", &C::gl,
                                   {{"auto", GlApiKind::Auto}, {"egl", GlApiKind::Egl}, {"osmesa", GlApiKind::OSMesa}}),
        choiceOption<C, HemicubeMirrors>("--mirrors", "Mirrors",
                                         "mirrors by stencil portals (default) or Embree rays from mirror pixels",
                                         &C::mirrors, {{"portals", HemicubeMirrors::Portals}, {"rays", HemicubeMirrors::Rays}}),
        integerOption<C>("--origins", "Origins", "K",
                         "hemicubes per patch: 1 = centroid (default); K > 1 = ceil(sqrt K)^2 Gauss-Legendre points over "
                         "the patch, weighted (area-to-area factors next to large patches)",
                         &C::origins, 1, 1024),
        integerOption<C>("--batch", "Batch", "B",
                         "hemicubes per pass, one instanced draw into B atlas layers (default 0 = by renderer: 1 on "
                         "llvmpipe, up to 256 on a GPU); rows that may see a mirror go row by row",
                         &C::batch, 0, 4096),
        integerOption<C>("--in-flight", "Passes in flight", "N",
                         "passes read back or reduced while the next ones draw (default 0 = by renderer: 1 on "
                         "llvmpipe, 3 on a GPU)",
                         &C::inFlight, 0, 8),
        integerOption<C>("--row-threads", "Row threads", "N",
                         "CPU threads per GL context that sum finished passes into rows (default -1 = by renderer: "
                         "none on llvmpipe, whose contexts take every core; on a GPU the cores the contexts leave; "
                         "0 = the GL thread sums them)",
                         &C::rowThreads, -1, 1024),
        switchOption<C>("--no-parents", "Draw every patch",
                        "draw every patch, not subdivided parents whole (reference path)", &C::parentPolygons, false),
    };
    d.defaults = [] { return std::any(C{}); };
    d.validate = [](const MethodSettings& s) {
        const C& o = s.as<C>();
        if (o.resolution < 2 || o.resolution % 2) throw Error("--resolution must be an even number >= 2");
        if (o.origins < 1) throw Error("--origins must be at least 1");
        if (o.mirrors == HemicubeMirrors::Rays && !rayCastingNotBuilt().empty())
            throw Error("--mirrors rays casts Embree rays, which are " + rayCastingNotBuilt() + "; --mirrors portals needs none");
    };
    d.create = [](const MethodSettings& s) -> std::unique_ptr<FormFactorBackend> {
        return std::make_unique<HemicubeBackend>(s.as<C>(), s.common);
    };
    d.workPerRow = [](const Scene&, const MethodSettings& s) {
        const C& o = s.as<C>();
        return 3.0 * o.resolution * o.resolution * originPoints(o.origins);
    };
    d.describe = describe;
    return d;
}

}  // namespace

const BackendDescriptor& hemicubeDescriptor() {
    static const BackendDescriptor descriptor = make();
    return descriptor;
}

}  // namespace hemirad
