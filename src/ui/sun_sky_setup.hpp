// hemirad-gui's Sky and sun inputs and result: one hour of sun and sky as `hemirad irradiance`
// computes it (ui/sun_sky_job.hpp runs it).
#pragma once

#include "engine/math.hpp"
#include "environment/irradiance.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hemirad::ui {

/// The Sky and sun section's inputs, as hemirad irradiance's flags.
struct SunSkySetup {
    bool byTime = true;                          ///< the sun from time and place (--sun-time), else `direction`
    std::string time = "2026-06-21T12:00Z";      ///< UTC, or with an offset (solar_position.hpp)
    double latitude = 48.14, longitude = 11.58;  ///< degrees north and east
    Vec3 direction = Vec3(0.3, 0.2, 0.9);        ///< toward the sun, in the scene's frame
    double dni = 800.0, dhi = 100.0;             ///< W/m^2
    std::string sky = "isotropic";               ///< or a model: uniform, cie-overcast, cie:N, perez
    int subdivision = 2;                         ///< a model's Reinhart cells (1: Tregenza's 145)
};

/// The frame the sun and sky are placed in: the scene's up (1 y, 2 z) and north (+y for z up, -z for
/// y up), as the command line's defaults.
Vec3 sceneUp(int upAxis);
Vec3 sceneNorth(int upAxis);

struct SunSkyResult {
    SunSkySetup setup;
    Vec3 toSun = Vec3(0, 0, 1);  ///< unit, toward the sun, scene frame
    std::string where;           ///< how the sun was placed ("elevation 61.2 deg, azimuth 142 deg ...")
    std::vector<double> sunlit;  ///< per patch, 0..1
    std::vector<double> skyView; ///< per patch, the direct sky view factor (the isotropic sky; empty with a model)
    IrradianceResult irradiance;
    std::uint64_t geometryHash = 0;
    std::uint64_t materialsRevision = 0;  ///< set by AppState: the materials it was computed with
};

}  // namespace hemirad::ui
