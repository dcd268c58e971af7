// The hemicube atlas and its delta form factors (Cohen & Greenberg 1985).
#pragma once

#include "engine/math.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace hemirad {

/// One face camera of a hemicube: a pixel at face coordinates (x, y) looks along
/// forward + x right + y up (top face: x, y in [-1, 1]; sides: x in [-1, 1], y = elevation in [0, 1]).
struct HemicubeFace {
    Vec3 forward, up, right;
};

/// The five face cameras around a patch with normal n and tangents t, b (atlas order of
/// HemicubeLayout): the top looks along n with b up; the sides look along +t, -t, +b, -b with n up.
std::array<HemicubeFace, 5> hemicubeFaces(const Vec3& n, const Vec3& t, const Vec3& b);

/// Five faces of the hemicube of half-width 1 packed in a 3R x R atlas (pixel rows bottom-up):
///
///     y = R   +-----------+-----------+-----------+
///             |           |  -t side  |  -b side  |
///     y = R/2 |   top     +-----------+-----------+   side faces: R x R/2, their bottom row
///             |  (R x R)  |  +t side  |  +b side  |   lies on the patch plane (elevation 0)
///     y = 0   +-----------+-----------+-----------+
///             x = 0       x = R       x = 2R      x = 3R
///
/// Delta form factor of a pixel of area dA = (2/R)^2 (the squares are required):
///   top:  dA / (pi (x^2 + y^2 + 1)^2);   side:  z dA / (pi (x^2 + z^2 + 1)^2).
/// A midpoint sum overshoots 1 by about 0.54 / R^2, so the table is normalised to sum 1.
class HemicubeLayout {
public:
    /// R even, 2..8192.
    explicit HemicubeLayout(std::uint32_t resolution);

    struct Viewport {
        int x, y, width, height;
    };
    enum Face { Top = 0, PlusT = 1, MinusT = 2, PlusB = 3, MinusB = 4 };

    std::uint32_t resolution() const { return m_R; }
    std::uint32_t width() const { return 3 * m_R; }
    std::uint32_t height() const { return m_R; }
    const Viewport& viewport(int face) const { return m_viewports[face]; }
    /// Per pixel, row-major from the bottom row; sums to 1.
    const std::vector<float>& weights() const { return m_weights; }
    /// The midpoint sum before normalisation.
    double rawSum() const { return m_rawSum; }
    /// Sum of the normalised weights of one face.
    double faceShare(int face) const;

private:
    std::uint32_t m_R;
    Viewport m_viewports[5];
    std::vector<float> m_weights;
    double m_rawSum = 0;
};

}  // namespace hemirad
