// A fault for the MPI tests, preloaded into one rank (LD_PRELOAD): every MPI_Test fails with
// MPI_ERR_OTHER, as a broken link would make it, so that the rank's main thread fails while it waits
// for form-factor rows (the only MPI_Test hemirad calls) and its worker thread waits in the row queue.
// It says when it first fails, so that a test can tell the fault was in place.
#include <mpi.h>

#include <atomic>
#include <cstddef>

#include <unistd.h>

extern "C" int MPI_Test(MPI_Request*, int* flag, MPI_Status*) {
    static std::atomic<bool> said{false};
    if (!said.exchange(true)) {
        const char text[] = "mpi_test_fails: MPI_Test fails\n";
        [[maybe_unused]] auto n = ::write(STDERR_FILENO, text, sizeof text - 1);
    }
    *flag = 0;
    return MPI_ERR_OTHER;
}
