// The machine's available memory, and sizes said in messages.
#include "engine/memory.hpp"

#include <cstdio>
#include <fstream>
#include <string>

namespace hemirad {

std::size_t availableMemory() {
    std::ifstream in("/proc/meminfo");
    std::string key, unit;
    std::size_t value = 0;
    while (in >> key >> value >> unit)
        if (key == "MemAvailable:") return value * 1024;
    return 0;
}

std::string bytesText(double bytes) {
    char text[32];
    if (bytes >= double(1ull << 30)) std::snprintf(text, sizeof text, "%.2f GiB", bytes / double(1ull << 30));
    else std::snprintf(text, sizeof text, "%.1f MiB", bytes / double(1ull << 20));
    return text;
}

}  // namespace hemirad
