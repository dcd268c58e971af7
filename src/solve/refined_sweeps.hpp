// Gauss-Seidel and SOR over many channels by iterative refinement: corrections swept in float,
// residuals in double (refined_sweeps.cpp).
#pragma once

#include "solve/solver_detail.hpp"

#include <vector>

namespace hemirad::detail {

/// Below this many channels, one thread sweeps them all (the threads would share a tile's cache
/// lines row after row); from it on, the channels are refined in float (refined_sweeps.cpp).
constexpr int kSplitChannels = 32;

/// Solves every channel to options.tolerance (the relative residual in double, as the double
/// sweeps do), SOR's factor adapted when `relax`. Each channel's B holds the start on entry.
void gaussSeidelRefined(const FormFactors& F, std::vector<Channel*>& channels, const SolverOptions& options, bool relax);

}  // namespace hemirad::detail
