// Images of a solved scene: Embree camera rays, Gouraud radiosity, mirrors showing what they reflect.
#pragma once

#include "engine/scene.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

class RayScene;

struct RenderOptions {
    int width = 640, height = 640;
    Camera camera;
    int samplesPerPixel = 4;   ///< stratified sub-pixel samples (rounded down to a square), >= 1
    int maxMirrorDepth = 8;    ///< mirror bounces followed by camera rays
    bool flat = false;         ///< per-patch B instead of Gouraud corner values
};

/// Linear radiance image (W/(m^2 sr)), rows top to bottom.
struct RadianceImage {
    int width = 0, height = 0;
    std::vector<Rgb> pixels;
};

/// The scene's own camera ("# hemirad camera" in the OBJ), else one that frames its bounds.
Camera defaultCamera(const Scene& scene);

/// Renders L = B / pi (+ s x the mirrored radiance on mirrors). `B` per patch, `corner` per patch
/// corner (cornerRadiosity()); back faces are black. Parallel over rows.
RadianceImage renderRadiance(const Scene& scene, const RayScene& rays, const std::vector<Rgb>& B,
                             const std::vector<Rgb>& corner, const RenderOptions& options);

/// What each pixel centre's camera ray meets first: a patch id, RayScene::kNoHit (nothing), or
/// kBackFace (a patch from behind). Rows top to bottom.
constexpr PatchId kBackFace = 0xfffffffeu;
std::vector<PatchId> renderPatchIds(const Scene& scene, const RayScene& rays, const RenderOptions& options);

/// 8-bit sRGB pixels; exposure <= 0 means automatic (97th percentile luminance -> 0.85).
/// Returns the scale used in `scale`.
std::vector<std::uint8_t> toneMap(const RadianceImage& image, double exposure, double& scale);

}  // namespace hemirad
