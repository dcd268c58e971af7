// The machine's available memory.
#include "engine/memory.hpp"

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

}  // namespace hemirad
