// What the machine can hold: the memory budget behind F's and the direct solvers' size checks.
#pragma once

#include <cstddef>

namespace hemirad {

/// Bytes of memory available to this process (MemAvailable in /proc/meminfo), 0 if unknown.
std::size_t availableMemory();

}  // namespace hemirad
