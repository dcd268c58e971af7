// Result files: radiosity CSV, PLY with vertex colours, PNG images (all written atomically).
#pragma once

#include "engine/scene.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hemirad {

/// CSV columns: patch,area,E_r,E_g,E_b,rho_r,rho_g,rho_b,specular,B_r,B_g,B_b (W/m^2, scene units^2),
/// then sky_view_factor (0..1) where `skyViewFactor` is given (one per patch; empty: no column).
void writeRadiosityCsv(const std::string& path, const Scene& scene, const std::vector<Rgb>& B,
                       const std::vector<double>& skyViewFactor = {});

/// Binary PLY: one vertex per patch corner (crease-aware values from cornerRadiosity) with 8-bit
/// sRGB colours of the radiance B/pi times `exposure`, plus float properties B_r, B_g, B_b; one face
/// per patch, with a float property sky_view_factor where `skyViewFactor` is given (one per patch;
/// empty: none). Opens in MeshLab and Blender.
void writeRadiosityPly(const std::string& path, const Scene& scene, const std::vector<Rgb>& corner,
                       double exposure, const std::vector<double>& skyViewFactor = {});

/// 8-bit RGB image, rows top to bottom.
void writePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);

/// Throws hemirad::Error if any value is NaN or infinite: such values never reach an output file.
void requireFinite(const std::vector<Rgb>& values, const char* what);

}  // namespace hemirad
