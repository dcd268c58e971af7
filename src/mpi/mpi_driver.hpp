// hemirad under mpirun: the formfactors, solve and render commands across ranks (the other commands
// run on rank 0); every phase ends at an agreement point, so an error on any rank ends every rank.
#pragma once

namespace hemirad::mpi {

/// Runs hemirad's command line as one rank of an MPI job; returns the exit status (0, 1, or 2 for a
/// usage error), the same on every rank. Rank 0 alone prints messages, reports and errors.
int runUnderMpi(int argc, char** argv);

}  // namespace hemirad::mpi
