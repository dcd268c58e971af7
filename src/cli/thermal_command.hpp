// The stages of `hemirad thermal`, shared by the one-process command and the MPI driver (which
// computes F's rows across ranks and solves the model where they are, or gathers them for
// rank 0 where a step needs F whole: thermalNeedsWholeF).
#pragma once

#include "cli/options.hpp"
#include "cli/report.hpp"
#include "engine/form_factors.hpp"
#include "engine/warnings.hpp"
#include "thermal/exchange_rows.hpp"
#include "thermal/gebhart.hpp"
#include "thermal/solar_band.hpp"
#include "thermal/thermal_model.hpp"
#include "thermal/thermal_solver.hpp"

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

/// What was solved and computed for the outputs.
struct ThermalResults {
    thermal::ThermalModel model;  ///< the inputs' model with the absorbed sun and the solved emissivities
    thermal::ThermalSolution solution;
    thermal::Conductors conductors;               ///< with --conductors
    std::vector<std::vector<double>> exchange;    ///< with --exchange, between objectNodes
    std::vector<std::string> objectNodes;
};

/// What in the run needs F whole in one process (an IR band or a solar band with mirrors of its own:
/// their own F; --conductors, --exchange), comma-separated, or "": then the gray solve runs on
/// F's rows where they are (solveThermalModel with rows across MPI ranks and no `whole`).
std::string thermalNeedsWholeF(const Options& options, const Scene& scene, const ThermalInputs& inputs);

/// Solves the solar band and the IR exchange on `rows`, and what --conductors and --exchange ask on
/// `whole` (F in this process; nullptr where thermalNeedsWholeF says ""), reporting through `reporter`.
/// Throws hemirad::Error.
ThermalResults solveThermalModel(const Options& options, const Scene& scene, const ThermalInputs& inputs,
                                 const thermal::ExchangeRows& rows, const FormFactors* whole, Timings& timings,
                                 const Reporter& reporter, Warnings& warnings);

/// Writes what -o, --objects, --conductors and --exchange ask (each atomically).
void writeThermalResults(const Options& options, const Scene& scene, const ThermalResults& results, Timings& timings,
                         const Reporter& reporter);

/// Solves the solar band (on F, or on its own F computed here when its specular reflectances differ)
/// and the IR exchange on F, computes what -o, --objects, --conductors and --exchange ask, then
/// writes them (nothing is written if any step fails), reporting through `reporter`.
void solveThermalAndWrite(const Options& options, const Scene& scene, const ThermalInputs& inputs, const FormFactors& F,
                          Timings& timings, const Reporter& reporter, Warnings& warnings);

}  // namespace hemirad
