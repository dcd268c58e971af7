// FNV-1a 64-bit hashing for scene hashes and file checksums.
#pragma once

#include <cstddef>
#include <cstdint>

namespace hemirad {

class Fnv1a {
public:
    void add(const void* data, std::size_t size) {
        const auto* bytes = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < size; ++i) m_state = (m_state ^ bytes[i]) * 0x100000001b3ULL;
    }
    template <class T> void addValue(const T& value) { add(&value, sizeof(T)); }
    std::uint64_t value() const { return m_state; }

private:
    std::uint64_t m_state = 0xcbf29ce484222325ULL;
};

}  // namespace hemirad
