// hemirad: command-line entry point; the only place (with the GUI) that catches hemirad::Error.
#include "cli/commands.hpp"
#include "engine/atomic_file.hpp"
#include "engine/threads.hpp"
#ifdef HEMIRAD_WITH_MPI
#include "mpi/mpi_context.hpp"
#include "mpi/mpi_driver.hpp"
#endif

#include <csignal>
#include <cstring>
#include <iostream>
#include <new>
#include <unistd.h>

namespace {

extern "C" void onInterrupt(int signal) {
    // No partial output: temporaries are removed, finished files were renamed atomically.
    hemirad::AtomicFile::removePendingFiles();
    const char message[] = "\nhemirad: interrupted; no partial output was written\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, message, sizeof message - 1);
    ::_exit(128 + signal);
}

}  // namespace

int main(int argc, char** argv) {
    using namespace hemirad;
    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
#ifdef HEMIRAD_WITH_MPI
    // Started by mpirun: the command runs as one rank of the job (src/mpi); otherwise MPI stays out.
    if (mpi::launchedByMpiLauncher()) return mpi::runUnderMpi(argc, argv);
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
        if (options.command == "bench") return runBench(options);
        if (options.command == "bench-run") return runBenchRun(options);
        throw UsageError("unknown command '" + options.command + "'");
    } catch (const UsageError& e) {
        std::cerr << "hemirad: error: " << e.what() << "\n(run 'hemirad help' for usage)\n";
        return 2;
    } catch (const Error& e) {
        std::cerr << "hemirad: error: " << e.what() << '\n';
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "hemirad: error: out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "hemirad: error: " << e.what() << '\n';
        return 1;
    }
}
