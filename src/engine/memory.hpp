// What the machine can hold: the memory budget behind F's and the direct solvers' size checks.
#pragma once

#include <cstddef>
#include <string>

namespace hemirad {

/// Bytes of memory available to this process (MemAvailable in /proc/meminfo), 0 if unknown.
std::size_t availableMemory();

/// `bytes` for a message: "12.3 MiB", or "1.23 GiB" from 1 GiB up.
std::string bytesText(double bytes);

}  // namespace hemirad
