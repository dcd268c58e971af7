// Explanations of F's statistics.
#include "engine/form_factor_notes.hpp"

namespace hemirad {

std::vector<std::string> formFactorStatsNotes(const FormFactorStats& stats) {
    std::vector<std::string> notes;
    if (stats.computedRows > 0 && stats.rowSumMin <= 0.0)
        notes.push_back("a row sum of 0 is a patch that sees no patch (it faces out of an opening, or all its rays "
                        "missed): its power leaves the scene, as it should");
    if (stats.reciprocityMax > 0.5)
        notes.push_back("the reciprocity max compares single pairs, where a few rays or pixels decide; judge the "
                        "area-weighted mean, which falls with more directions, origins or resolution");
    return notes;
}

}  // namespace hemirad
