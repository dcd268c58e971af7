// The stages of `hemirad thermal`, shared by the one-process command and the MPI driver (which
// computes F's rows across ranks and gathers them for rank 0's solve).
#pragma once

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "engine/form_factors.hpp"
#include "engine/warnings.hpp"
#include "thermal/solar_band.hpp"
#include "thermal/thermal_model.hpp"

namespace hemirad {

/// The IR model and the solar band (active where the --bc file gives solar_W_m2).
struct ThermalInputs {
    thermal::ThermalModel model;
    thermal::SolarBand solar;
};

/// Reads --properties (applying a specular reflectance to `scene`: call before F) and --bc, checks
/// the model and reports where each object's properties and condition came from. Throws hemirad::Error.
ThermalInputs readThermalModel(Scene& scene, const Options& options, const Reporter& reporter, Warnings& warnings);

/// `options` as F must be computed for thermal exchange: every row (--all-rows).
Options thermalFormFactorOptions(const Options& options);

/// Solves the solar band (on F, or on its own F computed here when its specular reflectances differ)
/// and the IR exchange on F, computes what -o, --objects, --conductors and --exchange ask, then
/// writes them (nothing is written if any step fails), reporting through `reporter`.
void solveThermalAndWrite(const Options& options, const Scene& scene, const ThermalInputs& inputs, const FormFactors& F,
                          Timings& timings, const Reporter& reporter, Warnings& warnings);

}  // namespace hemirad
