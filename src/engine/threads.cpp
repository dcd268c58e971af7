// Process thread configuration (OpenMP default, llvmpipe rasteriser threads).
#include "engine/threads.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <thread>

namespace hemirad {

int resolveThreads(int requested) {
    if (requested > 0) return requested;
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void configureProcessThreads(int requested) {
    const int threads = resolveThreads(requested);
    omp_set_num_threads(threads);
    if (threads > 1 && !std::getenv("LP_NUM_THREADS")) ::setenv("LP_NUM_THREADS", "0", 0);
}

}  // namespace hemirad
