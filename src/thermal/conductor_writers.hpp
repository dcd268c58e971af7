// Thermal results on disk (atomic writes): per-patch and per-object tables (CSV), the object
// exchange matrix (CSV) and the radiative conductors as CSV, Matrix Market or the conductor blocks
// thermal-network tools read (ESATAN-TMS $CONDUCTORS, SINDA/FLUINT CONDUCTOR DATA). docs/thermal.md.
#pragma once

#include "thermal/gebhart.hpp"
#include "thermal/thermal_solver.hpp"

#include <string>
#include <vector>

namespace hemirad::thermal {

/// patch,object,area (m^2),emissivity,specular,condition,T (K),T (C),J (W/m^2),H (W/m^2),
/// absorbed solar (W/m^2),q (W/m^2),Q (W); q and Q are the net heat leaving (IR out minus the sun in).
void writePatchTable(const std::string& path, const Scene& scene, const ThermalModel& model, const ThermalSolution& solution);

/// One row per object: object,patches,area (m^2),T_mean (K) (area-weighted),T_min (K),T_max (K),q_mean (W/m^2),Q (W);
/// then a last row "environment" with Q_env.
void writeObjectThermalTable(const std::string& path, const Scene& scene, const ThermalSolution& solution);

/// Net power between objects (W): a header of object names and "environment", one row per object.
void writeExchangeMatrix(const std::string& path, const std::vector<std::string>& nodes,
                         const std::vector<std::vector<double>>& Q);

/// Conductor formats by name: "csv" (node_a,node_b,GR (m^2)), "mtx" (symmetric coordinate, 1-based,
/// the environment as the last node), "esatan" (GR(a, b) = v; lines of a $CONDUCTORS block) and
/// "sinda" (HEADER CONDUCTOR DATA with radiation conductors -ID, a, b, GR). Node numbers are 1-based
/// in `nodes` order; the environment is node `environmentNode`.
const std::vector<std::string>& conductorFormats();
/// The format for a path's extension (.csv, .mtx, .esatan/.cnd, .sinda/.inp) or "" if none matches.
std::string conductorFormatFor(const std::string& path);
void writeConductors(const std::string& path, const std::string& format, const Conductors& conductors,
                     std::uint32_t environmentNode = 99999);

}  // namespace hemirad::thermal
