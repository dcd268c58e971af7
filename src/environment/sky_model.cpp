// Sky cells and sky models: Tregenza/Reinhart cells, the CIE skies and Perez's all-weather sky.
#include "environment/sky_model.hpp"

#include "engine/error.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hemirad {

namespace {


// Perez, Seals & Michalsky (1993), "All-weather model for sky luminance distribution - preliminary
// configuration and validation", Solar Energy 50(3) 235-245, Table 1: per clearness bin, a1..a4,
// b1..b4, c1..c4, d1..d4, e1..e4 (x = x1 + x2 Z + Delta (x3 + x4 Z), Z the sun's zenith in radians).
constexpr double kPerez[8][20] = {
    {1.3525, -0.2576, -0.2690, -1.4366, -0.7670, 0.0007, 1.2734, -0.1233, 2.8000, 0.6004,
     1.2375, 1.0000, 1.8734, 0.6297, 0.9738, 0.2809, 0.0356, -0.1246, -0.5718, 0.9938},
    {-1.2219, -0.7730, 1.4148, 1.1016, -0.2054, 0.0367, -3.9128, 0.9156, 6.9750, 0.1774,
     6.4477, -0.1239, -1.5798, -0.5081, -1.7812, 0.1080, 0.2624, 0.0672, -0.2190, -0.4285},
    {-1.1000, -0.2515, 0.8952, 0.0156, 0.2782, -0.1812, -4.5000, 1.1766, 24.7219, -13.0812,
     -37.7000, 34.8438, -5.0000, 1.5218, 3.9229, -2.6204, -0.0156, 0.1597, 0.4199, -0.5562},
    {-0.5484, -0.6654, -0.2672, 0.7117, 0.7234, -0.6219, -5.6812, 2.6297, 33.3389, -18.3000,
     -62.2500, 52.0781, -3.5000, 0.0016, 1.1477, 0.1062, 0.4659, -0.3296, -0.0876, -0.0329},
    {-0.6000, -0.3566, -2.5000, 2.3250, 0.2937, 0.0496, -5.6812, 1.8415, 21.0000, -4.7656,
     -21.5906, 7.2492, -3.5000, -0.1554, 1.4062, 0.3988, 0.0032, 0.0766, -0.0656, -0.1294},
    {-1.0156, -0.3670, 1.0078, 1.4051, 0.2875, -0.5328, -3.8500, 3.3750, 14.0000, -0.9999,
     -7.1406, 7.5469, -3.4000, -0.1078, -1.0750, 1.5702, -0.0672, 0.4016, 0.3017, -0.4844},
    {-1.0000, 0.0211, 0.5025, -0.5119, -0.3000, 0.1922, 0.7023, -1.6317, 19.0000, -5.0000,
     1.2438, -1.9094, -4.0000, 0.0250, 0.3844, 0.2656, 1.0468, -0.3788, -2.4517, 1.4656},
    {-1.0500, 0.0289, 0.4260, 0.3590, -0.3250, 0.1156, 0.7781, 0.0025, 31.0625, -14.5000,
     -46.1148, 55.3750, -7.2312, 0.4050, 13.3500, 0.6234, 1.5000, -0.6426, 1.8564, 0.5636}};
// The bins' lower clearness limits (Perez et al. 1990, Table 1).
constexpr double kPerezBins[8] = {1.000, 1.065, 1.230, 1.500, 1.950, 2.800, 4.500, 6.200};

// ISO 15469:2004 / CIE S 011/E:2003: the six gradation groups (a, b), the six indicatrix groups
// (c, d, e), and each of the 15 sky types' pair of groups.
constexpr double kGradation[6][2] = {{4.0, -0.70}, {1.1, -0.8}, {0.0, -1.0}, {-1.0, -0.55}, {-1.0, -0.32}, {-1.0, -0.15}};
constexpr double kIndicatrix[6][3] = {{0, -1.0, 0}, {2, -1.5, 0.15}, {5, -2.5, 0.30}, {10, -3.0, 0.45}, {16, -3.0, 0.30}, {24, -2.8, 0.15}};
constexpr int kCieTypes[15][2] = {{0, 0}, {0, 1}, {1, 0}, {1, 1}, {2, 0}, {2, 1}, {2, 2}, {2, 3},
                                  {3, 1}, {3, 2}, {3, 3}, {4, 3}, {4, 4}, {5, 4}, {5, 5}};

double angleBetween(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(a.dot(b), -1.0, 1.0)); }

}  // namespace

double SkyGrid::Cell::solidAngle() const { return (std::sin(altitudeHigh) - std::sin(altitudeLow)) * (azimuthHigh - azimuthLow); }

SkyGrid skyGrid(int subdivision) {
    if (subdivision < 1 || subdivision > 8)
        throw Error("sky: subdivision " + std::to_string(subdivision) + " is outside 1..8 (1: Tregenza's 145 cells)");
    static constexpr int kRow[7] = {30, 30, 24, 24, 18, 12, 6};
    SkyGrid grid;
    grid.subdivision = subdivision;
    const double alpha = (kPi / 2.0) / (7.0 * subdivision + 0.5);
    for (int r = 0; r < 7 * subdivision; ++r) {
        const int count = kRow[r / subdivision] * subdivision;
        for (int j = 0; j < count; ++j)  // cell j centred on azimuth 2 pi j / count, cell 0 on north
            grid.cells.push_back({alpha * r, alpha * (r + 1), 2.0 * kPi * (j - 0.5) / count, 2.0 * kPi * (j + 0.5) / count});
    }
    grid.cells.push_back({alpha * 7 * subdivision, kPi / 2.0, 0.0, 2.0 * kPi});
    return grid;
}

Vec3 skyDirection(double altitude, double azimuth) {
    return Vec3(std::cos(altitude) * std::sin(azimuth), std::cos(altitude) * std::cos(azimuth), std::sin(altitude));
}

std::vector<Vec3> cellSamples(const SkyGrid::Cell& cell, int samples) {
    std::vector<Vec3> out;
    out.reserve(std::size_t(samples) * std::size_t(samples));
    const double s0 = std::sin(cell.altitudeLow), s1 = std::sin(cell.altitudeHigh);
    for (int a = 0; a < samples; ++a) {
        const double altitude = std::asin(s0 + (s1 - s0) * (a + 0.5) / samples);
        for (int b = 0; b < samples; ++b)
            out.push_back(skyDirection(altitude, cell.azimuthLow + (cell.azimuthHigh - cell.azimuthLow) * (b + 0.5) / samples));
    }
    return out;
}

namespace {
/// The sky's frame in the scene: columns east, north, up.
Eigen::Matrix3d skyFrame(const Vec3& up, const Vec3& north) {
    const Vec3 u = up.normalized();
    const Vec3 n = (north - north.dot(u) * u).normalized();
    Eigen::Matrix3d m;
    m << n.cross(u), n, u;
    return m;
}
}  // namespace

Vec3 skyToScene(const Vec3& d, const Vec3& up, const Vec3& north) { return skyFrame(up, north) * d; }

Vec3 sceneToSky(const Vec3& d, const Vec3& up, const Vec3& north) { return skyFrame(up, north).transpose() * d; }

std::string SkyModel::name() const {
    switch (kind) {
    case Kind::Uniform: return "uniform";
    case Kind::CieOvercast: return "cie-overcast";
    case Kind::CieStandard: return "cie:" + std::to_string(cieType);
    case Kind::Perez: return "perez";
    }
    return "?";
}

SkyModel parseSkyModel(const std::string& text) {
    SkyModel m;
    if (text == "uniform") return m;
    if (text == "cie-overcast") {
        m.kind = SkyModel::Kind::CieOvercast;
        return m;
    }
    if (text == "perez") {
        m.kind = SkyModel::Kind::Perez;
        return m;
    }
    if (text.rfind("cie:", 0) == 0) {
        const std::string number = text.substr(4);
        if (!number.empty() && number.size() <= 2 && std::all_of(number.begin(), number.end(), ::isdigit)) {
            m.kind = SkyModel::Kind::CieStandard;
            m.cieType = std::stoi(number);
            if (m.cieType >= 1 && m.cieType <= 15) return m;
        }
    }
    throw Error("sky: '" + text + "' is not a sky model (uniform, cie-overcast, cie:1 .. cie:15, perez)");
}

PerezParameters perezParameters(const SkyConditions& c) {
    PerezParameters p;
    if (!(c.dhi > 0.0)) return p;
    const double Z = std::min(std::acos(std::clamp(c.toSun.normalized().z(), -1.0, 1.0)), kPi / 2.0);
    const double kappa = 1.041, z3 = Z * Z * Z;  // Perez et al. (1990), eqn 1
    p.epsilon = ((c.dhi + c.dni) / c.dhi + kappa * z3) / (1.0 + kappa * z3);
    const double airMass = 1.0 / (std::cos(Z) + 0.15 * std::pow(93.885 - Z * 180.0 / kPi, -1.253));  // Kasten (1966)
    double eccentricity = 1.0;
    if (c.dayOfYear > 0) {  // Spencer (1971)
        const double g = 2.0 * kPi * (c.dayOfYear - 1) / 365.0;
        eccentricity = 1.00011 + 0.034221 * std::cos(g) + 0.00128 * std::sin(g) + 0.000719 * std::cos(2 * g) + 0.000077 * std::sin(2 * g);
    }
    p.delta = c.dhi * airMass / (1367.0 * eccentricity);
    // The ranges the model was fitted over, as Radiance's gendaylit keeps them: beyond (the sun near
    // or below the horizon, where the air mass explodes) the luminance turns negative everywhere.
    p.clamped = p.delta < 0.01 || p.delta > 0.6 || p.epsilon > 12.01;
    p.delta = std::clamp(p.delta, 0.01, 0.6);
    p.epsilon = std::min(p.epsilon, 12.01);
    p.bin = 0;
    while (p.bin < 7 && p.epsilon >= kPerezBins[p.bin + 1]) ++p.bin;
    // Bins 2-4 with a dark sky (low sun, thin diffuse light) give a gradation a < -1 with b near 0:
    // negative everywhere. Radiance's gendaymtx keeps Delta at 0.2 or more there; so do we.
    if (p.epsilon > 1.065 && p.epsilon < 2.8 && p.delta < 0.2) {
        p.delta = 0.2;
        p.clamped = true;
    }
    const double* x = kPerez[p.bin];
    const auto linear = [&](int k) { return x[4 * k] + x[4 * k + 1] * Z + p.delta * (x[4 * k + 2] + x[4 * k + 3] * Z); };
    p.a = linear(0);
    p.b = linear(1);
    p.c = linear(2);
    p.d = linear(3);
    p.e = linear(4);
    if (p.bin == 0) {  // the overcast bin: eqns 7 and 8
        p.c = std::exp(std::pow(p.delta * (x[8] + x[9] * Z), x[10])) - x[11];
        p.d = -std::exp(p.delta * (x[12] + x[13] * Z)) + x[14] + p.delta * x[15];
    }
    return p;
}

double relativeRadiance(const SkyModel& model, const PerezParameters& perez, const Vec3& toSun, const Vec3& d) {
    const double cosZ = std::max(d.z(), 0.0);
    switch (model.kind) {
    case SkyModel::Kind::Uniform: return 1.0;
    case SkyModel::Kind::CieOvercast: return 1.0 + 2.0 * cosZ;  // Moon & Spencer (1942), CIE (1955)
    case SkyModel::Kind::CieStandard: {
        const double* g = kGradation[kCieTypes[model.cieType - 1][0]];
        const double* f = kIndicatrix[kCieTypes[model.cieType - 1][1]];
        const double chi = angleBetween(toSun.normalized(), d);
        const double gradation = 1.0 + g[0] * (cosZ > 0.0 ? std::exp(g[1] / cosZ) : 0.0);
        const double indicatrix = 1.0 + f[0] * (std::exp(f[1] * chi) - std::exp(f[1] * kPi / 2.0)) + f[2] * std::cos(chi) * std::cos(chi);
        return std::max(0.0, gradation * indicatrix);
    }
    case SkyModel::Kind::Perez: {
        // cos Z kept at 0.01 or more at the horizon, as Radiance's perezlum.cal does, where b > 0 would blow up.
        const double gamma = angleBetween(toSun.normalized(), d);
        const double value = (1.0 + perez.a * std::exp(perez.b / std::max(cosZ, 0.01))) *
                             (1.0 + perez.c * std::exp(perez.d * gamma) + perez.e * std::cos(gamma) * std::cos(gamma));
        return std::max(0.0, value);
    }
    }
    return 0.0;
}

std::vector<double> horizontalWeights(const SkyGrid& grid, int samples) {
    std::vector<double> H(grid.size(), 0.0);
    for (std::size_t k = 0; k < grid.size(); ++k) {
        const double w = grid.cells[k].solidAngle() / double(samples * samples);
        for (const Vec3& d : cellSamples(grid.cells[k], samples)) H[k] += w * d.z();
    }
    return H;
}

std::vector<double> skyRadiance(const SkyGrid& grid, int samples, const SkyModel& model, const SkyConditions& c, bool* uniformFallback) {
    if (uniformFallback) *uniformFallback = false;
    if (!(std::isfinite(c.dhi) && c.dhi >= 0.0) || !(std::isfinite(c.dni) && c.dni >= 0.0))
        throw Error("sky: the direct-normal and diffuse-horizontal irradiance must be finite and >= 0");
    if (!c.toSun.allFinite() || c.toSun.norm() == 0.0) throw Error("sky: the sun's direction must be finite and not zero");
    if (samples < 1) throw Error("sky: at least one sample per cell side");
    std::vector<double> L(grid.size(), 0.0);
    if (c.dhi == 0.0) return L;
    const PerezParameters perez = model.kind == SkyModel::Kind::Perez ? perezParameters(c) : PerezParameters();
    // A sun below the horizon is taken at it: the models are defined for the sun in the sky.
    Vec3 toSun = c.toSun.normalized();
    if (toSun.z() < 0.0) toSun = Vec3(toSun.x(), toSun.y(), 0.0).norm() > 0.0 ? Vec3(toSun.x(), toSun.y(), 0.0).normalized() : Vec3(0, 1, 0);
    for (std::size_t k = 0; k < grid.size(); ++k) {
        double sum = 0.0;
        const std::vector<Vec3> parts = cellSamples(grid.cells[k], samples);
        for (const Vec3& d : parts) sum += relativeRadiance(model, perez, toSun, d);
        L[k] = sum / double(parts.size());
    }
    const std::vector<double> H = horizontalWeights(grid, samples);
    double horizontal = std::inner_product(L.begin(), L.end(), H.begin(), 0.0);
    if (!(horizontal > 0.0) && model.kind == SkyModel::Kind::Perez) {
        // The fitted model can still be dark everywhere at the edges of its range: the DHI then comes
        // from a uniform sky, and the caller is told.
        std::fill(L.begin(), L.end(), 1.0);
        horizontal = std::accumulate(H.begin(), H.end(), 0.0);
        if (uniformFallback) *uniformFallback = true;
    }
    if (!(horizontal > 0.0)) throw Error("sky: the " + model.name() + " sky gives no light on a horizontal plane for this hour");
    for (double& v : L) v *= c.dhi / horizontal;
    return L;
}

}  // namespace hemirad
