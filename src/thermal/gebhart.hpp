// Gebhart factors and radiative conductors (Gebhart 1961; with specular surfaces through extended
// factors): B_ij, the fraction of patch i's emission absorbed by patch j along every path, satisfies
// B_ij = F_ij eps_j + sum_k F_ik rho_d,k B_kj. Per node (a patch or an object), GR_IJ =
// sum_{i in I, j in J} eps_i A_i B_ij (m^2), symmetric by reciprocity, and Q_IJ = sigma GR_IJ (T_I^4 -
// T_J^4) between isothermal nodes. The environment is a node too: what no surface absorbs.
#pragma once

#include "engine/form_factors.hpp"
#include "solve/solver.hpp"
#include "thermal/thermal_model.hpp"
#include "thermal/thermal_solver.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hemirad::thermal {

/// Nodes of the conductor network: each patch its own node, or each object (lumped, isothermal).
enum class Lumping : std::uint8_t { Patches, Objects };

/// How the Gebhart factors are found: a column solve per node (batched over F), one dense symmetric
/// factorisation of every patch pair (patch_conductance.hpp: n^3 flops, n^2 doubles), or whichever
/// is expected to be faster and fits in memory.
enum class GebhartMethod : std::uint8_t { Auto, Columns, Dense };

struct GebhartOptions {
    Lumping lumping = Lumping::Objects;
    /// A coupling is dropped when both of its Gebhart factors (B_IJ = GR_IJ / (eps A)_I and B_JI) are
    /// below this; their number and sum are reported. 0 keeps every coupling.
    double threshold = 0.0;
    std::size_t batch = 64;  ///< nodes solved together (one factorisation serves all)
    GebhartMethod method = GebhartMethod::Auto;
};

struct Coupling {
    std::uint32_t a = 0, b = 0;  ///< node indices, a < b; b == nodes.size() is the environment
    double gr = 0.0;             ///< m^2, symmetrised (GR_ab + GR_ba) / 2
};

struct Conductors {
    std::vector<std::string> nodes;       ///< names: object names, or "patch N"
    std::vector<std::vector<PatchId>> members;  ///< patches of each node
    std::vector<double> emittingArea;     ///< sum eps_i A_i per node, m^2
    std::vector<Coupling> couplings;      ///< sorted by (a, b); environment couplings last per a
    /// sum_{i, j in I} eps_i A_i B_ij: what a node absorbs of its own emission after reflections (no
    /// heat flows through it; B_II = self / (eps A)_I), m^2.
    std::vector<double> self;
    /// B_IJ per node as a dense matrix (nodes x nodes, row I), environment column last; filled for
    /// up to 4096 nodes (the Gebhart-factor table), empty above.
    std::vector<std::vector<double>> B;
    std::size_t dropped = 0;              ///< couplings below the threshold
    double droppedSum = 0.0;              ///< their GR sum, m^2
    /// Columns: max |GR_IJ - GR_JI| / max GR before symmetrising (F's reciprocity and the solve's
    /// residual). Dense: F's reciprocity defect max |A_i F_ij - A_j F_ji| / max A_i F_ij, which that
    /// route removes before solving.
    double asymmetry = 0.0;
    /// max_I |sum_J B_IJ + B_I,env - 1|: 0 by construction of the environment column; reported for
    /// a closed scene as max_I B_I,env (what escapes).
    double escapeMax = 0.0;
    SolveReport report;                   ///< the last batch's solve (columns)
    GebhartMethod method = GebhartMethod::Columns;  ///< the route taken
};

/// GR and B for the model's surfaces on `F` (all rows computed). Throws hemirad::Error as solveThermal.
Conductors computeConductors(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                             const GebhartOptions& options, const SolverOptions& solver);

/// Net power between nodes from a thermal solution, W: Q[I][J] = sum_{i in I, j in J} sigma GR_ij
/// (T_i^4 - T_j^4) with the per-patch temperatures (exact for non-isothermal objects too, since it
/// uses every patch's own Gebhart row); the last column is the environment. Row sums equal each
/// node's net IR leaving: its Q plus the external heat (sun) it absorbs (to the solve's residual).
std::vector<std::vector<double>> exchangeMatrix(const Scene& scene, const FormFactors& F, const ThermalModel& model,
                                                const ThermalSolution& solution, const std::vector<std::vector<PatchId>>& nodes,
                                                const SolverOptions& solver);

/// The nodes of a lumping: objects with patches (in scene order) or every patch.
void makeNodes(const Scene& scene, Lumping lumping, std::vector<std::string>& names,
               std::vector<std::vector<PatchId>>& members);

}  // namespace hemirad::thermal
