// What a patch sees, for hemirad-gui's inspector: over its Nusselt disk (hemisphere method) or on its
// unfolded hemicube atlas (hemicube method), ray-cast from the patch centroid. Pixels keep the
// radiance they see; tone mapping happens when the picture is drawn, with the view's exposure of
// that frame (a picture made before a solve or an exposure change is never drawn too bright or dark).
#pragma once

#include "engine/scene.hpp"
#include "preprocess/backend_registry.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hemirad {
class RayScene;
}

namespace hemirad::ui {

struct InspectorPicture {
    /// Unused: between the atlas's faces; Outside: beyond the disk's rim.
    enum class Pixel : std::uint8_t { Unused, Outside, Miss, BackFace, Hit };
    int width = 0, height = 0;
    std::vector<Pixel> kind;     ///< row-major, top row first
    std::vector<Rgb> radiance;   ///< B / pi of what a Hit pixel sees
    std::string caption;

    /// RGBA8, top row first: hits tone-mapped with `exposure` (as the view), misses dark blue (the
    /// power is lost), back faces dark red, outside the disk grey, the atlas's unused area white.
    std::vector<std::uint8_t> rgba(double exposure) const;
};

/// The picture of patch `id` of `scene` with radiosity B, as `projection` lays it out.
InspectorPicture makeInspectorPicture(const Scene& scene, const RayScene& rays, const std::vector<Rgb>& B, PatchId id,
                                      Projection projection);

}  // namespace hemirad::ui
