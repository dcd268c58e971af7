// Ray origins stratified over a patch's area, and the random numbers that drive them.
#pragma once

#include "engine/scene.hpp"

#include <cstdint>
#include <vector>

namespace hemirad {

/// SplitMix64: small, fast, statistically sound; seeded per (patch, origin) for reproducible runs.
class Random {
public:
    explicit Random(std::uint64_t seed) : m_state(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1).
    double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }

private:
    std::uint64_t m_state;
};

/// K origins spread evenly over the patch area: K = 1 is the centroid; otherwise a rank-1
/// (Fibonacci) lattice of K points in the unit square with a random shift (Cranley-Patterson),
/// mapped area-uniformly onto the polygon (bilinear for parallelograms, else by fan triangles).
std::vector<Vec3> patchOrigins(const Scene& scene, PatchId id, std::uint32_t K, Random& random);

}  // namespace hemirad
