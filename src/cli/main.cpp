// hemirad: command-line entry point; the only place (with the GUI) that catches hemirad::Error.
#include "cli/commands.hpp"
#include "cli/mpi_launch.hpp"
#include "engine/atomic_file.hpp"
#include "engine/console.hpp"
#include "engine/crash_report.hpp"
#include "engine/threads.hpp"

#include <iostream>
#include <new>

int main(int argc, char** argv) {
    using namespace hemirad;
    AtomicFile::removePendingFilesOnInterrupt();
    reportFatalSignals("hemirad");
#ifdef HEMIRAD_WITH_MPI
    // Started by mpirun: the command runs as one rank of the job (src/mpi, a module loaded only
    // then); otherwise MPI stays out.
    if (cli::launchedByMpiLauncher()) return cli::runMpiModule(argc, argv);
#endif
    try {
        const Options options = parseOptions(argc, argv);
        configureProcessThreads(options.formFactors.common.threads);
        if (isStandardOutput(options.output) && outputIsBinary(options)) requireBinaryStandardOutput();  // before any work
        if (options.command == "help") {
            std::cout << usageText();
            return 0;
        }
        if (options.command == "formfactors") return runFormFactors(options);
        if (options.command == "solve") return runSolve(options);
        if (options.command == "render") return runRender(options);
        if (options.command == "info") return runInfo(options);
        if (options.command == "subdivide") return runSubdivide(options);
        if (options.command == "thermal") return runThermal(options);
        if (options.command == "sky-view") return runSkyView(options);
        if (options.command == "sun") return runSun(options);
        if (options.command == "irradiance") return runIrradiance(options);
        if (options.command == "sensors") return runSensors(options);
        if (options.command == "year") return runYear(options);
        if (options.command == "check") return runCheck(options);
        if (options.command == "bench") return runBench(options);
        if (options.command == "bench-run") return runBenchRun(options);
        throw UsageError("unknown command '" + options.command + "'");
    } catch (const UsageError& e) {
        printError(e.what(), true);
        return 2;
    } catch (const Error& e) {
        printError(e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        printError("out of memory");
        return 1;
    } catch (const std::exception& e) {
        printError(e.what());
        return 1;
    }
}
