// Delta form factors of the hemicube atlas.
#include "preprocess/hemicube/hemicube_layout.hpp"

#include "engine/error.hpp"
#include "engine/math.hpp"

namespace hemirad {

HemicubeLayout::HemicubeLayout(std::uint32_t R) : m_R(R) {
    if (R < 2 || R > 8192 || R % 2 != 0)
        throw Error("hemicube resolution must be an even number in 2..8192, got " + std::to_string(R));
    const int r = static_cast<int>(R), half = r / 2;
    m_viewports[Top] = {0, 0, r, r};
    m_viewports[PlusT] = {r, 0, r, half};
    m_viewports[MinusT] = {r, half, r, half};
    m_viewports[PlusB] = {2 * r, 0, r, half};
    m_viewports[MinusB] = {2 * r, half, r, half};
    std::vector<double> w(std::size_t(width()) * height(), 0.0);
    const double step = 2.0 / R, dA = step * step;
    for (int face = 0; face < 5; ++face) {
        const Viewport& v = m_viewports[face];
        for (int py = 0; py < v.height; ++py)
            for (int px = 0; px < v.width; ++px) {
                const double x = -1.0 + (px + 0.5) * step;
                double value;
                if (face == Top) {
                    const double y = -1.0 + (py + 0.5) * step;
                    const double d = x * x + y * y + 1.0;
                    value = dA / (kPi * d * d);
                } else {
                    const double z = (py + 0.5) * step;  // elevation above the patch plane
                    const double d = x * x + z * z + 1.0;
                    value = z * dA / (kPi * d * d);
                }
                w[std::size_t(v.y + py) * width() + std::size_t(v.x + px)] = value;
                m_rawSum += value;
            }
    }
    m_weights.resize(w.size());
    for (std::size_t k = 0; k < w.size(); ++k) m_weights[k] = static_cast<float>(w[k] / m_rawSum);
}

double HemicubeLayout::faceShare(int face) const {
    const Viewport& v = m_viewports[face];
    double sum = 0.0;
    for (int py = 0; py < v.height; ++py)
        for (int px = 0; px < v.width; ++px) sum += m_weights[std::size_t(v.y + py) * width() + std::size_t(v.x + px)];
    return sum;
}

std::array<HemicubeFace, 5> hemicubeFaces(const Vec3& n, const Vec3& t, const Vec3& b) {
    const Vec3 forward[5] = {n, t, -t, b, -b};
    std::array<HemicubeFace, 5> faces;
    for (int f = 0; f < 5; ++f) {
        faces[f].forward = forward[f];
        faces[f].up = f == 0 ? b : n;
        faces[f].right = faces[f].forward.cross(faces[f].up);
    }
    return faces;
}

}  // namespace hemirad
