// `hemirad render SCENE.obj -o IMAGE.png`: form factors, solve, Gouraud radiosity, camera rays (or, for
// --false-color sky_view_factor, the sky view factors and no solve).
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

/// --false-color: one colour per patch from the quantity's `values`, and the legend.
void writeFalseColour(const Options& options, const Scene& scene, const std::vector<double>& values, Timings& timings,
                      const Reporter& reporter) {
    const FalseColourQuantity quantity = *options.falseColour;
    // --range's sides, else the quantity's natural ones (the sky view factor's 0 and 1), else automatic.
    auto [min, max] = falseColourDefaultRange(quantity, options.falseColourScale);
    std::ostringstream sides;
    if (!options.rangeMin && min) sides << "min " << *min;
    if (!options.rangeMax && max) sides << (min && !options.rangeMin ? ", " : "") << "max " << *max;
    std::string note = sides.str();
    if (!note.empty()) note += ": the " + falseColourTitle(quantity) + "'s range";
    if (options.rangeMin) min = options.rangeMin;
    if (options.rangeMax) max = options.rangeMax;
    const FalseColourRange range = falseColourRange(values, options.falseColourScale, min, max);
    if (range.automatic) note += (note.empty() ? "" : "; min: ") + falseColourRangeNote(range);
    const RenderOptions render = renderOptions(options, scene);
    timings.start("false colour " + std::to_string(render.width) + "x" + std::to_string(render.height));
    const RayScene rays(scene, options.formFactors.common.threads);
    const Rgb8Image image = renderFalseColour(scene, rays, values, range, quantity, render);
    timings.start("write PNG");
    writePng(options.output, image.width, image.height, image.rgb);
    timings.stop();
    std::ostringstream line;
    line.precision(9);
    line << "false colour: " << falseColourTitle(quantity) << " (" << falseColourUnit(quantity) << "), "
         << falseColourScaleName(range.scale) << " scale " << range.min << " .. " << range.max
         << (note.empty() ? "" : " (" + note + ")");
    reporter.line(line.str());
    reporter.line("wrote " + outputName(options.output) + " (" + std::to_string(image.width) + "x" + std::to_string(image.height) +
                  ": the picture and a " + std::to_string(kFalseColourLegendWidth) + "-pixel legend)");
}

}  // namespace

void writeRenderOutput(const Options& options, const Scene& scene, const Radiosity& result, Timings& timings,
                       const Reporter& reporter) {
    if (options.falseColour)
        return writeFalseColour(options, scene, falseColourValues(scene, result.B, *options.falseColour), timings, reporter);
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
    if (options.falseColour == FalseColourQuantity::SkyViewFactor) {
        // No B needed: sky-view's F over the two-sided scene, and no solve.
        const Scene scene = loadScene(options, timings, reporter, warnings);
        const std::vector<double> sky = skyViewTotals(options, scene, timings, reporter, warnings);
        writeFalseColour(options, scene, sky, timings, reporter);
        finishCommand(reporter, timings, warnings);
        return 0;
    }
    const SolvedScene solved = solveFromOptions(options, timings, reporter, warnings);
    writeRenderOutput(options, solved.scene, solved.result, timings, reporter);
    finishCommand(reporter, timings, warnings);
    return 0;
}

}  // namespace hemirad
