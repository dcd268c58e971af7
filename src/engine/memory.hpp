// What the machine can hold: the memory budget behind F's and the direct solvers' size checks.
#pragma once

#include <cstddef>
#include <string>

namespace hemirad {

/// Bytes of memory available to this process (MemAvailable in /proc/meminfo), 0 if unknown.
std::size_t availableMemory();

/// Advises the kernel to back [data, data + bytes) with transparent huge pages (the whole 2 MiB pages
/// inside it): one fault per 2 MiB instead of per 4 KiB where a large buffer is filled once. Advice
/// only; nothing happens where the kernel declines.
void adviseHugePages(const void* data, std::size_t bytes);

/// `bytes` for a message: "12.3 MiB", or "1.23 GiB" from 1 GiB up.
std::string bytesText(double bytes);

}  // namespace hemirad
