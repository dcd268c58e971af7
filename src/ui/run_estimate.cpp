// The Pipeline panel's Run estimate line.
#include "ui/run_estimate.hpp"

#include "ui/units.hpp"

#include <cstdio>

namespace hemirad::ui {

std::string runEstimateText(const FormFactorEstimate& e) {
    if (e.rows == 0) return "Run: F is current, it only solves";
    std::string text = "Run: " + std::to_string(e.rows) + (e.rows == 1 ? " row" : " rows");
    // The analytic estimator integrates each pair: its rays are shadow tests, one per patch and
    // origin point (issue 38 #15: "315 rows x 315 rays" read as directions it never casts).
    if (e.analytic) text += " of analytic factors (" + formatNumber(e.workPerRow) + " shadow rays a row, no directions cast)";
    else text += " x " + formatNumber(e.workPerRow) + " " + e.workUnit;
    char memory[64];
    std::snprintf(memory, sizeof memory, ", F at most %.1f MiB, ", e.memoryBound / 1048576.0);
    text += memory;
    // A rate measured on another scene or mesh is no basis (issue 38 #5: after 20 patches, 315 were
    // announced at 14.22 s and took 0.11 s): fixed costs dominate a small run.
    text += e.seconds ? "about " + formatNumber(*e.seconds) + " s" : "time known after a first run on this mesh";
    return text;
}

}  // namespace hemirad::ui
