// A fault for the MPI tests, preloaded into one rank (LD_PRELOAD): MPI_Finalize returns 20 s late, so
// that the rank is still finalising when mpirun ends the job because another rank exited non-zero.
// The MPI profiling interface (PMPI_Finalize) does the work. It says when it starts waiting and when
// it is done, so that a test can tell that the rank was ended while it waited.
#include <mpi.h>

#include <cstddef>

#include <unistd.h>

namespace {

void say(const char* text, std::size_t length) { [[maybe_unused]] auto n = ::write(STDERR_FILENO, text, length); }

}  // namespace

extern "C" int MPI_Finalize() {
    const int code = PMPI_Finalize();
    const char waiting[] = "slow_finalize: waiting\n", done[] = "slow_finalize: done\n";
    say(waiting, sizeof waiting - 1);
    ::sleep(20);
    say(done, sizeof done - 1);
    return code;
}
