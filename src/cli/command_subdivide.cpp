// `hemirad subdivide in.obj|in.stl -o out.obj --max-edge L [--materials M.mtl]`.
#include "cli/commands.hpp"
#include "cli/report.hpp"
#include "engine/obj_writer.hpp"
#include "engine/scene_loader.hpp"
#include "engine/subdivide.hpp"

#include <iostream>

namespace hemirad {

int runSubdivide(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    timings.start("load scene");
    const Scene scene = loadScene(options.inputs.at(0), warnings, {options.materials});
    timings.start("subdivide");
    const Scene out = subdivide(scene, options.maxEdge);
    timings.start("write OBJ");
    saveObj(out, options.output);
    timings.stop();
    reporter.line(options.inputs[0] + ": " + std::to_string(scene.size()) + " patches -> " + options.output + ": " +
                  std::to_string(out.size()) + " patches (edges <= " + std::to_string(options.maxEdge) + ")");
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
