// The entry point of hemirad-mpi.so: hemirad loads this module only when an MPI launcher started it
// (src/cli/mpi_launch.cpp), so that a plain run never loads MPI, PETSc and their libraries.
#include "engine/atomic_file.hpp"
#include "engine/crash_report.hpp"
#include "mpi/mpi_driver.hpp"

/// Runs hemirad's command line as one rank (mpi::runUnderMpi). The module carries its own copy of
/// hemirad's libraries, so it installs its own interrupt and fatal-signal handlers for the files it writes.
extern "C" __attribute__((visibility("default"))) int hemirad_mpi_main(int argc, char** argv) {
    hemirad::AtomicFile::removePendingFilesOnInterrupt();
    hemirad::reportFatalSignals("hemirad");
    return hemirad::mpi::runUnderMpi(argc, argv);
}
