// `hemirad render SCENE.obj -o IMAGE.png`: form factors, solve, Gouraud radiosity, camera rays.
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "engine/result_writer.hpp"
#include "engine/vertex_radiosity.hpp"
#include "rays/ray_scene.hpp"
#include "render/false_colour.hpp"
#include "render/raytracer.hpp"

#include <sstream>

namespace hemirad {

namespace {

RenderOptions renderOptions(const Options& options, const Scene& scene) {
    RenderOptions render;
    render.width = options.width;
    render.height = options.height;
    render.camera = options.camera ? *options.camera : defaultCamera(scene);
    render.samplesPerPixel = options.samplesPerPixel;
    render.flat = options.flat;
    render.maxMirrorDepth = static_cast<int>(options.formFactors.common.maxDepth);
    return render;
}

/// --false-color: one colour per patch from the quantity's value, and the legend.
void writeFalseColour(const Options& options, const Scene& scene, const Radiosity& result, Timings& timings,
                      const Reporter& reporter) {
    const FalseColourQuantity quantity = *options.falseColour;
    const std::vector<double> values = falseColourValues(scene, result.B, quantity);
    const FalseColourRange range = falseColourRange(values, options.falseColourScale, options.rangeMin, options.rangeMax);
    const RenderOptions render = renderOptions(options, scene);
    timings.start("false colour " + std::to_string(render.width) + "x" + std::to_string(render.height));
    const RayScene rays(scene, options.formFactors.common.threads);
    const Rgb8Image image = renderFalseColour(scene, rays, values, range, quantity, render);
    timings.start("write PNG");
    writePng(options.output, image.width, image.height, image.rgb);
    timings.stop();
    std::ostringstream line;
    line.precision(9);
    line << "false colour: " << falseColourTitle(quantity) << " (W/m^2, luminance Y), "
         << falseColourScaleName(range.scale) << " scale " << range.min << " .. " << range.max
         << (range.automatic ? " (" + falseColourRangeNote(range) + ")" : "");
    reporter.line(line.str());
    reporter.line("wrote " + outputName(options.output) + " (" + std::to_string(image.width) + "x" + std::to_string(image.height) +
                  ": the picture and a " + std::to_string(kFalseColourLegendWidth) + "-pixel legend)");
}

}  // namespace

void writeRenderOutput(const Options& options, const Scene& scene, const Radiosity& result, Timings& timings,
                       const Reporter& reporter) {
    if (options.falseColour) return writeFalseColour(options, scene, result, timings, reporter);
    timings.start("vertex radiosity");
    const std::vector<Rgb> corner = cornerRadiosity(scene, result.B, options.crease);
    const RenderOptions render = renderOptions(options, scene);
    timings.start("render " + std::to_string(render.width) + "x" + std::to_string(render.height));
    const RayScene rays(scene, options.formFactors.common.threads);
    const RadianceImage image = renderRadiance(scene, rays, result.B, corner, render);
    timings.start("write PNG");
    double scale = 0.0;
    const std::vector<std::uint8_t> rgb = toneMap(image, options.exposure, scale);
    writePng(options.output, image.width, image.height, rgb);
    timings.stop();
    reporter.line("wrote " + outputName(options.output) + " (" + std::to_string(image.width) + "x" + std::to_string(image.height) +
                  ", exposure " + std::to_string(scale) + (options.exposure > 0 ? "" : ", automatic") + ")");
}

int runRender(const Options& options) {
    Reporter reporter(options.quiet, reportsToStandardError(options));
    Warnings warnings;
    Timings timings;
    const SolvedScene solved = solveFromOptions(options, timings, reporter, warnings);
    writeRenderOutput(options, solved.scene, solved.result, timings, reporter);
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
