// The machine's available memory, and sizes said in messages.
#include "engine/memory.hpp"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include <sys/mman.h>

namespace hemirad {

std::size_t availableMemory() {
    std::ifstream in("/proc/meminfo");
    std::string key, unit;
    std::size_t value = 0;
    while (in >> key >> value >> unit)
        if (key == "MemAvailable:") return value * 1024;
    return 0;
}

void adviseHugePages(const void* data, std::size_t bytes) {
    constexpr std::uintptr_t kHuge = std::uintptr_t(1) << 21;
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kHuge - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

std::string bytesText(double bytes) {
    char text[32];
    if (bytes >= double(1ull << 30)) std::snprintf(text, sizeof text, "%.2f GiB", bytes / double(1ull << 30));
    else std::snprintf(text, sizeof text, "%.1f MiB", bytes / double(1ull << 20));
    return text;
}

}  // namespace hemirad
