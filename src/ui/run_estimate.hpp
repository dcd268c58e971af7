// The Pipeline panel's line on what Run will do, from AppState::formFactorEstimate: rows, work,
// F's memory bound and, once this mesh has been run with the method, the time.
#pragma once

#include "ui/app_state.hpp"

#include <string>

namespace hemirad::ui {

/// "Run: 315 rows x 3072 rays, F at most 1.2 MiB, about 0.4 s"; analytic factors say they cast
/// shadow rays, not directions; without a rate measured on this mesh the time is not guessed.
std::string runEstimateText(const FormFactorEstimate& e);

}  // namespace hemirad::ui
