// The `hemirad` subcommands; each returns the process exit status.
#pragma once

#include "cli/options.hpp"

namespace hemirad {

int runFormFactors(const Options& options);
int runSolve(const Options& options);
int runRender(const Options& options);
int runInfo(const Options& options);
int runSubdivide(const Options& options);
int runThermal(const Options& options);
int runSkyView(const Options& options);
int runSun(const Options& options);
int runIrradiance(const Options& options);
int runYear(const Options& options);
int runSensors(const Options& options);
int runCheck(const Options& options);
int runBench(const Options& options);
int runBenchRun(const Options& options);

}  // namespace hemirad
