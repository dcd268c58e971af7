// Process thread configuration (OpenMP default, llvmpipe rasteriser threads).
#include "engine/threads.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdlib>

namespace hemirad {

int resolveThreads(int requested) {
    if (requested > 0) return requested;
    // OpenMP's default: OMP_NUM_THREADS, else the CPUs this process may run on (affinity, cgroups).
    return std::max(1, omp_get_max_threads());
}

void configureProcessThreads(int requested) {
    const int threads = resolveThreads(requested);
    if (requested > 0) omp_set_num_threads(threads);
    if (threads > 1 && !std::getenv("LP_NUM_THREADS")) ::setenv("LP_NUM_THREADS", "0", 0);
}

}  // namespace hemirad
