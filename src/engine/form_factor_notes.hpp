// What F's statistics mean where a newcomer would misread them: one wording for the CLI's report and
// the GUI's Pipeline panel (issue 38 #15).
#pragma once

#include "engine/form_factors.hpp"

#include <string>
#include <vector>

namespace hemirad {

/// Explanations of `stats` that need one: a row summing to 0 (a patch that sees no patch), a
/// reciprocity max above 0.5 (single pairs decided by a few rays or pixels). Empty when none applies.
std::vector<std::string> formFactorStatsNotes(const FormFactorStats& stats);

}  // namespace hemirad
