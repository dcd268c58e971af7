// The one worker-thread setting of a process: chosen once in main(), resolved the same way everywhere.
#pragma once

namespace hemirad {

/// Worker threads for a request: `requested` when > 0, else OpenMP's default (OMP_NUM_THREADS, else
/// the cores this process may use).
int resolveThreads(int requested);

/// Sets the process-wide defaults from the user's thread count (0 = OpenMP's default): OpenMP's team
/// size and, when more than one worker may hold a GL context, Mesa llvmpipe's LP_NUM_THREADS=0 (one
/// rasteriser thread per context; the hemicube runs a context per worker). Call once from main(),
/// before any thread or GL context exists: it writes the environment, which is not thread-safe.
/// A LP_NUM_THREADS the user set is kept.
void configureProcessThreads(int requested);

}  // namespace hemirad
