// hemirad under mpirun: the MPI driver (src/mpi, with Open MPI and PETSc) lives in hemirad-mpi.so,
// loaded only then: a plain run does not load MPI, PETSc and their ~100 libraries (0.1 s a start).
#pragma once

namespace hemirad::cli {

/// True when an MPI launcher started this process (Open MPI, MPICH/Hydra, PMIx or Slurm's PMI set
/// its environment). hemirad run without a launcher never loads MPI.
bool launchedByMpiLauncher();

/// Loads hemirad-mpi.so from the folder of the hemirad executable and runs the command line as one
/// rank of the job; returns its exit status. When the module cannot be loaded, every rank that
/// cannot load it prints why, naming itself ("rank R of K: "), and returns 1.
int runMpiModule(int argc, char** argv);

}  // namespace hemirad::cli
