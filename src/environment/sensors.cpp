// Sensor points: reading and laying them, their exact point-to-patch factors and sky view factors
// (shadow polygons over the two-sided scene), the sun at each point, and one hour's irradiance.
#include "environment/sensors.hpp"

#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "engine/error.hpp"
#include "engine/parallel_failure.hpp"
#include "environment/sensor_mirrors.hpp"
#include "environment/sky_view.hpp"
#include "preprocess/hemisphere/patch_geometry.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"
#include "preprocess/hemisphere/shadow_polygons.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include <omp.h>

namespace hemirad {
namespace {

/// The line's fields (splitCsvLine), spaces and tabs around each trimmed.
std::vector<std::string> splitFields(const std::string& line) {
    std::vector<std::string> out = splitCsvLine(line);
    for (std::string& field : out) {
        const std::size_t first = field.find_first_not_of(" \t");
        field = first == std::string::npos ? std::string() : field.substr(first, field.find_last_not_of(" \t") - first + 1);
    }
    return out;
}

bool parseDouble(const std::string& text, double& value) {
    if (text.empty()) return false;
    char* end = nullptr;
    value = std::strtod(text.c_str(), &end);
    return *end == '\0';
}

}  // namespace

namespace {

/// Twice the signed area of the triangle (a, b, c) in 2D, computed from the edge's endpoints in one
/// fixed order (lexicographic) whatever the order given, so that two patches sharing the edge get
/// exactly opposite signs for the same point.
double orient(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c) {
    const bool swapped = b < a;
    const std::array<double, 2>& p = swapped ? b : a;
    const std::array<double, 2>& q = swapped ? a : b;
    const double s = (q[0] - p[0]) * (c[1] - p[1]) - (q[1] - p[1]) * (c[0] - p[0]);
    return swapped ? -s : s;
}

}  // namespace

/// Whether c lies inside the counter-clockwise convex polygon p, points on an edge counted for the
/// polygon on one side of it only (the top-left rule of rasterisers), and not at all on an edge
/// that `open` marks (the object's boundary: a point there would stand in a wall's plane).
bool insideTopLeft(const std::vector<std::array<double, 2>>& p, const std::vector<std::uint8_t>& open,
                   const std::array<double, 2>& c) {
    for (std::size_t k = 0; k < p.size(); ++k) {
        const std::array<double, 2>& a = p[k];
        const std::array<double, 2>& b = p[(k + 1) % p.size()];
        const double s = orient(a, b, c);
        if (s > 0.0) continue;
        if (s < 0.0 || open[k]) return false;
        const double dx = b[0] - a[0], dy = b[1] - a[1];
        const bool topLeft = dy < 0.0 || (dy == 0.0 && dx < 0.0);
        if (!topLeft) return false;
    }
    return true;
}


Sensors parseSensorsCsv(const std::string& text, const std::string& file) {
    Sensors out;
    std::istringstream in(text);
    std::string line;
    int number = 0;
    bool first = true;
    static const char* const kNames[] = {"x", "y", "z", "nx", "ny", "nz"};
    while (std::getline(in, line)) {
        ++number;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
        const std::vector<std::string> f = splitFields(line);
        double value = 0.0;
        if (first && !parseDouble(f[0], value)) {  // a header
            first = false;
            continue;
        }
        first = false;
        if (f.size() != 6 && f.size() != 7)
            throw Error(file, number, "a sensor is x,y,z,nx,ny,nz[,name]: " + std::to_string(f.size()) + " fields");
        double v[6];
        for (int k = 0; k < 6; ++k)
            if (!parseDouble(f[std::size_t(k)], v[k]) || !std::isfinite(v[k]))
                throw Error(file, number, std::string(kNames[k]) + " '" + f[std::size_t(k)] + "' is not a finite number");
        const Vec3 normal(v[3], v[4], v[5]);
        if (!(normal.norm() > 0.0) || !std::isfinite(normal.norm()))
            throw Error(file, number, "the normal (" + f[3] + ", " + f[4] + ", " + f[5] + ") is not a direction");
        out.position.emplace_back(v[0], v[1], v[2]);
        out.normal.push_back(normal.normalized());
        out.name.push_back(f.size() == 7 && !f[6].empty() ? f[6] : std::to_string(out.position.size() - 1));
    }
    if (out.size() == 0) throw Error(file, 0, "no sensor: expected lines x,y,z,nx,ny,nz[,name]");
    return out;
}

Sensors readSensorsCsv(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, 0, "cannot open the sensor file");
    std::ostringstream text;
    text << in.rdbuf();
    return parseSensorsCsv(text.str(), path);
}

Sensors sensorGrid(const Scene& scene, const std::string& object, double spacing, double height, std::size_t limit) {
    const auto found = std::find(scene.objects.begin(), scene.objects.end(), object);
    if (found == scene.objects.end()) throw Error("sensor grid: the scene has no object '" + object + "'");
    if (!(spacing > 0.0) || !std::isfinite(spacing)) throw Error("sensor grid: the spacing must be a finite length > 0");
    if (!std::isfinite(height)) throw Error("sensor grid: the height must be finite");
    const auto id = std::uint32_t(found - scene.objects.begin());
    // The object's edges by their ends' positions: an edge of one patch only is its boundary.
    using End = std::array<double, 3>;
    const auto edgeKey = [&](const Patch& p, std::uint32_t k) {
        const Vec3 a = scene.corner(p, k), b = scene.corner(p, (k + 1) % p.cornerCount);
        End u{a.x(), a.y(), a.z()}, v{b.x(), b.y(), b.z()};
        return u < v ? std::make_pair(u, v) : std::make_pair(v, u);
    };
    std::map<std::pair<End, End>, int> edges;
    for (const Patch& p : scene.patches)
        if (p.object == id)
            for (std::uint32_t k = 0; k < p.cornerCount; ++k) ++edges[edgeKey(p, k)];
    Sensors out;
    std::vector<std::array<double, 2>> polygon;
    std::vector<std::uint8_t> open;
    for (PatchId j = 0; j < scene.size(); ++j) {
        const Patch& p = scene.patches[j];
        if (p.object != id || !(p.area > 0.0)) continue;
        Vec3 u, v;
        orthonormalBasis(p.normal, u, v);
        polygon.clear();
        open.clear();
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const Vec3 c = scene.corner(p, k);
            polygon.push_back({c.dot(u), c.dot(v)});
            open.push_back(edges[edgeKey(p, k)] == 1);
            for (int a = 0; a < 2; ++a) {
                lo[a] = std::min(lo[a], polygon.back()[std::size_t(a)]);
                hi[a] = std::max(hi[a], polygon.back()[std::size_t(a)]);
            }
        }
        double twice = 0.0;
        for (std::size_t k = 0; k < polygon.size(); ++k) {
            const auto& a = polygon[k];
            const auto& b = polygon[(k + 1) % polygon.size()];
            twice += a[0] * b[1] - b[0] * a[1];
        }
        if (twice < 0.0) {  // counter-clockwise, as insideTopLeft reads it (edge k then runs from corner k + 1)
            std::reverse(polygon.begin(), polygon.end());
            std::reverse(open.begin(), open.end() - 1);
        }
        const double offset = p.normal.dot(p.centroid);  // the plane's distance from the origin
        const auto first = [&](int a) { return std::ceil(lo[a] / spacing - 0.5); };
        const auto last = [&](int a) { return std::floor(hi[a] / spacing - 0.5); };
        if ((last(0) - first(0) + 1) * (last(1) - first(1) + 1) > double(limit))
            throw Error("sensor grid: more than " + std::to_string(limit) + " points on patch " + std::to_string(j) +
                        " of '" + object + "': give a larger spacing");
        std::size_t k = 0;
        for (double i = first(0); i <= last(0); ++i)
            for (double m = first(1); m <= last(1); ++m) {
                const std::array<double, 2> c = {(i + 0.5) * spacing, (m + 0.5) * spacing};
                if (!insideTopLeft(polygon, open, c)) continue;
                if (out.size() >= limit)
                    throw Error("sensor grid: more than " + std::to_string(limit) + " points on '" + object +
                                "': give a larger spacing");
                out.position.push_back(c[0] * u + c[1] * v + (offset + height) * p.normal);
                out.normal.push_back(p.normal);
                out.name.push_back(object + ":" + std::to_string(j) + ":" + std::to_string(k++));
            }
    }
    if (out.size() == 0)
        throw Error("sensor grid: no lattice point of spacing " + std::to_string(spacing) + " falls on '" + object + "'");
    return out;
}

SensorFactors sensorFactors(const Scene& scene, const Sensors& sensors, int threads, const MirrorChainLimits& limits) {
    const std::size_t n = scene.size();
    SensorFactors out;
    out.patches = n;
    out.skyView.assign(sensors.size(), 1.0);
    out.rowStart.assign(sensors.size() + 1, 0);
    // Every patch, front or back, hides what lies behind it: the two-sided scene's receivers (patch
    // j, or its reversed twin n + j 1e-6 x the extent behind it where the sensor sees j's back),
    // and the original patches as the blockers.
    const Scene two = twoSidedScene(scene, 1e-6 * scene.extent());
    PatchGeometry geometry;
    geometry.build(two);
    geometry.buildNeighbours(two);
    std::vector<std::uint8_t> blocks(two.size(), 0);
    std::fill(blocks.begin(), blocks.begin() + std::ptrdiff_t(n), std::uint8_t(1));
    ShadowPolygons shadows;
    shadows.build(geometry, blocks);
    // Through mirrors: the images of each sensor (sensor_mirrors.hpp), with shadow rays.
    std::vector<Reflector> reflectors;
    out.mirrors = sensorMirrorsNote(scene, reflectors);
    std::unique_ptr<RayScene> cast;
    std::unique_ptr<SensorMirrors> mirrors;
    if (!reflectors.empty()) {
        out.mirrors = "followed by images (" + std::to_string(reflectors.size()) + " reflectors)";
        cast = std::make_unique<RayScene>(scene, threads);
        mirrors = std::make_unique<SensorMirrors>(scene, geometry, std::move(reflectors), *cast, limits);
        out.skyMirrored.assign(sensors.size(), 0.0);
    }

    const double planeTolerance = 1e-12 * scene.extent();
    std::vector<std::vector<std::pair<PatchId, double>>> rows(sensors.size());
    std::uint64_t terms = 0;
    double cutoff = 0.0;
    ParallelFailure failure;  // a ray scene's error: rethrown after the region
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads()) reduction(+ : terms, cutoff)
    {
        ShadowPolygons::Scratch scratch;
        std::vector<Vec3> clipped;
        SensorMirrors::Workspace ws;
        std::vector<double> reach;
        if (mirrors) {
            ws = mirrors->workspace();
            reach.assign(mirrors->reflectorCount(), 0.0);
        }
#pragma omp for schedule(dynamic, 16)
        for (std::int64_t ss = 0; ss < std::int64_t(sensors.size()); ++ss) {
            const std::size_t s = std::size_t(ss);
            const Vec3& x = sensors.position[s];
            const Vec3& normal = sensors.normal[s];
            double covered = 0.0;
            for (PatchId j = 0; j < n; ++j) {
                const PatchShape& shape = geometry.shapes[j];
                // A patch whose plane holds the sensor (the face it lies on, a wall it stands in) is
                // seen edge-on: no term, and no sky hidden (its back must not count as well).
                const double height = shape.normal.dot(x - shape.centroid);
                if (std::abs(height) <= planeTolerance) continue;
                const bool front = height > 0.0;
                const PatchId r = front ? j : PatchId(n + j);
                const PatchShape& seen = geometry.shapes[r];
                // Nothing of r above the sensor's plane: no term (most of the scene for a sensor on a wall).
                if (normal.dot(seen.centroid - x) <= -seen.radius) continue;
                const Vec3* polygon = geometry.polygon(r);
                std::size_t corners = seen.count;
                bool below = false;
                for (std::size_t k = 0; k < corners && !below; ++k) below = normal.dot(polygon[k] - x) < 0.0;
                if (below) {
                    clipAbovePlane(x, normal, polygon, corners, clipped);
                    if (clipped.size() < 3) continue;
                    polygon = clipped.data();
                    corners = clipped.size();
                }
                const double whole = pointToPolygonFactor(x, normal, polygon, corners);
                if (!(whole > 0.0)) continue;
                ++terms;
                const double visible = shadows.visibleFactor(x, normal, polygon, corners, r, r, whole, scratch);
                if (!(visible > 0.0)) continue;
                covered += visible;
                if (front) rows[s].emplace_back(j, visible);
            }
            out.skyView[s] = std::clamp(1.0 - covered, 0.0, 1.0);
            if (!mirrors || failure.failed()) continue;
            failure.run([&] {
                // Each reflector's reach (its patches' visible factors), then its images; a patch seen
                // straight and in mirrors gets one entry.
                std::vector<std::pair<PatchId, double>>& row = rows[s];
                for (const auto& [j, f] : row)
                    if (const std::int32_t k = mirrors->reflectorOf(j); k >= 0) reach[std::size_t(k)] += f;
                const std::size_t direct = row.size();
                const SensorMirrors::Totals seen = mirrors->sees(x, normal, reach, ws, row);
                std::fill(reach.begin(), reach.end(), 0.0);
                out.skyMirrored[s] = seen.sky;
                cutoff += seen.cutoff;
                terms += seen.terms;
                if (row.size() == direct) return;
                std::stable_sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
                std::size_t kept = 0;
                for (std::size_t k = 0; k < row.size(); ++k) {
                    if (kept > 0 && row[kept - 1].first == row[k].first)
                        row[kept - 1].second += row[k].second;
                    else
                        row[kept++] = row[k];
                }
                row.resize(kept);
            });
        }
    }
    failure.rethrowIfFailed();
    out.terms = terms;
    out.cutoffWeight = cutoff;
    for (std::size_t s = 0; s < sensors.size(); ++s) {
        out.rowStart[s + 1] = out.rowStart[s] + rows[s].size();
        for (const auto& [j, f] : rows[s]) {
            out.columns.push_back(j);
            out.values.push_back(f);
        }
    }
    return out;
}

std::vector<double> sensorSunlit(const Scene& scene, const Sensors& sensors, const Vec3& toSun) {
    return sensorSunlit(BeamShadows(scene), sensors, toSun);
}

std::vector<double> sensorSunlit(const BeamShadows& beams, const Sensors& sensors, const Vec3& toSunGiven) {
    if (!toSunGiven.allFinite() || !(toSunGiven.norm() > 0.0)) throw Error("sun: the direction to the sun must be a finite non-zero vector");
    const Vec3 d = toSunGiven.normalized();
    std::vector<double> lit(sensors.size(), 0.0);
    ParallelFailure failure;  // a scratch that fails to grow: rethrown after the region
#pragma omp parallel
    {
        ShadowPolygons::Scratch scratch;
#pragma omp for schedule(dynamic, 64)
        for (std::int64_t ss = 0; ss < std::int64_t(sensors.size()); ++ss) {
            const std::size_t s = std::size_t(ss);
            if (!(sensors.normal[s].dot(d) > 0.0) || failure.failed()) continue;
            failure.run([&] { lit[s] = beams.blockers().blocksRay(sensors.position[s], d, beams.tolerance(), scratch) ? 0.0 : 1.0; });
        }
    }
    failure.rethrowIfFailed();
    return lit;
}

SensorIrradiance sensorIrradiance(const Sensors& sensors, const SensorFactors& factors, const std::vector<double>& sunlit,
                                  const Vec3& toSun, double dni, double dhi, const std::vector<double>& radiosity,
                                  const std::vector<double>& reflectedSun, const SensorSky* modelSky) {
    const std::size_t count = sensors.size();
    if (factors.skyView.size() != count || sunlit.size() != count || radiosity.size() != factors.patches ||
        (!factors.skyMirrored.empty() && factors.skyMirrored.size() != count) ||
        (!reflectedSun.empty() && reflectedSun.size() != count) ||
        (modelSky && (modelSky->direct.size() != count || (!modelSky->mirrored.empty() && modelSky->mirrored.size() != count))))
        throw Error("sensors: the factors, the sunlit flags, the reflected sun and the radiosity do not match the sensors and the scene");
    const Vec3 d = toSun.normalized();
    SensorIrradiance out;
    out.directSun.resize(count);
    out.directSky.resize(count);
    out.reflectedSun.assign(count, 0.0);
    out.reflectedSky.assign(count, 0.0);
    out.reflected.resize(count);
    out.total.resize(count);
    for (std::size_t s = 0; s < count; ++s) {
        out.directSun[s] = dni * std::max(0.0, sensors.normal[s].dot(d)) * sunlit[s];
        if (!reflectedSun.empty()) out.reflectedSun[s] = reflectedSun[s];
        if (modelSky) {
            out.directSky[s] = modelSky->direct[s];
            if (!modelSky->mirrored.empty()) out.reflectedSky[s] = modelSky->mirrored[s];
        } else {
            out.directSky[s] = dhi * factors.skyView[s];
            if (!factors.skyMirrored.empty()) out.reflectedSky[s] = dhi * factors.skyMirrored[s];
        }
        double h = 0.0;
        for (std::uint64_t k = factors.rowStart[s]; k < factors.rowStart[s + 1]; ++k) h += factors.values[k] * radiosity[factors.columns[k]];
        out.reflected[s] = h;
        out.total[s] = out.directSun[s] + out.directSky[s] + out.reflectedSun[s] + out.reflectedSky[s] + h;
    }
    return out;
}

void writeSensorsCsv(const std::string& path, const Sensors& sensors, const SensorFactors& factors,
                     const SensorIrradiance* irradiance) {
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    const bool mirrors = !factors.skyMirrored.empty();
    out << "sensor,name,x,y,z,nx,ny,nz,sky_view_factor";
    if (mirrors) out << ",sky_direct,sky_through_mirrors";
    if (irradiance) {
        out << ",direct_sun (W/m^2),direct_sky (W/m^2)";
        if (mirrors) out << ",reflected_sun (W/m^2),reflected_sky (W/m^2)";
        out << ",reflected (W/m^2),total (W/m^2)";
    }
    out << '\n';
    for (std::size_t s = 0; s < sensors.size(); ++s) {
        const Vec3& x = sensors.position[s];
        const Vec3& n = sensors.normal[s];
        out << s << ',' << csvField(sensors.name[s]) << ',' << x.x() << ',' << x.y() << ',' << x.z() << ',' << n.x() << ','
            << n.y() << ',' << n.z() << ',';
        if (mirrors)
            out << factors.skyView[s] + factors.skyMirrored[s] << ',' << factors.skyView[s] << ',' << factors.skyMirrored[s];
        else
            out << factors.skyView[s];
        if (irradiance) {
            out << ',' << irradiance->directSun[s] << ',' << irradiance->directSky[s];
            if (mirrors) out << ',' << irradiance->reflectedSun[s] << ',' << irradiance->reflectedSky[s];
            out << ',' << irradiance->reflected[s] << ',' << irradiance->total[s];
        }
        out << '\n';
    }
    file.commit();
}

void writeSensorFactorsMtx(const std::string& path, const SensorFactors& factors) {
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    const std::size_t count = factors.skyView.size();
    out << "%%MatrixMarket matrix coordinate real general\n";
    out << "% hemirad sensor factors: row s = sensor s (the CSV's order), column j = patch j, 1-based\n";
    out << count << ' ' << factors.patches << ' ' << factors.values.size() << '\n';
    for (std::size_t s = 0; s < count; ++s)
        for (std::uint64_t k = factors.rowStart[s]; k < factors.rowStart[s + 1]; ++k)
            out << s + 1 << ' ' << factors.columns[k] + 1 << ' ' << factors.values[k] << '\n';
    file.commit();
}

}  // namespace hemirad
