// The sun's first reflections by planar mirrors: each mirror's sunlit pieces (sunlit.hpp) carried
// along the reflected beam onto each receiver's plane, cut to the receiver, less the shadows of the
// patches between the mirror's plane and the receiver's.
#include "environment/reflected_sun.hpp"

#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "engine/error.hpp"
#include "environment/sunlit.hpp"
#include "preprocess/hemisphere/convex_pieces.hpp"
#include "preprocess/hemisphere/point_polygon.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <tuple>

namespace hemirad {
namespace {

double signedArea2d(const std::vector<Vec2>& p) {
    double a = 0.0;
    for (std::size_t k = 0; k < p.size(); ++k) a += p[k].x() * p[(k + 1) % p.size()].y() - p[(k + 1) % p.size()].x() * p[k].y();
    return 0.5 * a;
}

/// The part of the convex polygon `subject` inside the counter-clockwise convex polygon `window`.
std::vector<Vec2> clipToWindow(std::vector<Vec2> subject, const std::vector<Vec2>& window) {
    std::vector<Vec2> next;
    for (std::size_t k = 0; k < window.size() && subject.size() >= 3; ++k) {
        const Vec2& a = window[k];
        const Vec2 edge = window[(k + 1) % window.size()] - a;
        next.clear();
        for (std::size_t i = 0; i < subject.size(); ++i) {
            const Vec2& p = subject[i];
            const Vec2& q = subject[(i + 1) % subject.size()];
            const double sp = edge.x() * (p.y() - a.y()) - edge.y() * (p.x() - a.x());
            const double sq = edge.x() * (q.y() - a.y()) - edge.y() * (q.x() - a.x());
            if (sp >= 0.0) next.push_back(p);
            if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) next.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        subject.swap(next);
    }
    if (subject.size() < 3) subject.clear();
    return subject;
}

}  // namespace

ReflectedSun reflectedSun(const Scene& scene, const Vec3& toSun, double dni) { return reflectedSun(BeamShadows(scene), toSun, dni); }

ReflectedSun reflectedSun(const BeamShadows& beams, const Vec3& toSunGiven, double dni) {
    if (!toSunGiven.allFinite() || !(toSunGiven.norm() > 0.0)) throw Error("sun: the direction to the sun must be a finite non-zero vector");
    if (!(std::isfinite(dni) && dni >= 0.0)) throw Error("sun: the direct-normal irradiance must be finite and >= 0");
    const Scene& scene = beams.scene();
    const PatchGeometry& geometry = beams.geometry();
    const Vec3 d = toSunGiven.normalized();
    const std::size_t n = scene.size();
    const double tolerance = beams.tolerance();
    ReflectedSun out;
    out.irradiance.assign(n, 0.0);
    std::vector<PatchId> mirrors;
    for (PatchId m = 0; m < n; ++m)
        if (scene.patches[m].specular > 0.0 && scene.patches[m].normal.dot(d) > 0.0 && scene.patches[m].area > 0.0) mirrors.push_back(m);
    if (mirrors.empty()) return out;

    // Each mirror's spots, kept apart and summed in the mirrors' order after: the same sums whatever
    // the threads.
    struct Hit {
        PatchId receiver;
        double mean, peak, area;
    };
    std::vector<std::vector<Hit>> hits(mirrors.size());
    std::vector<std::uint8_t> litMirror(mirrors.size(), 0);
    std::string failure;
#pragma omp parallel
    {
        ShadowPolygons::Scratch s;
        std::vector<std::uint32_t> found;
        std::vector<std::vector<Vec3>> lit;
        std::vector<Vec3> part, piece, sideNormals;
        std::vector<double> sideOffsets;
#pragma omp for schedule(dynamic, 1)
        for (std::int64_t kk = 0; kk < std::int64_t(mirrors.size()); ++kk) {
            try {
                const PatchId m = mirrors[std::size_t(kk)];
                const Patch& mirror = scene.patches[m];
                const PatchShape& shape = geometry.shapes[m];
                const Vec3* corners = geometry.polygon(m);
                // The mirror's sunlit pieces, in 3D.
                Vec3 um, vm;
                ShadowPolygons::planeAxes(shape.normal, um, vm);
                const Vec3 om = corners[0];
                s.clear.pieces.assign(1, double(shape.count));
                for (std::uint32_t c = 0; c < shape.count; ++c) {
                    s.clear.pieces.push_back((corners[c] - om).dot(um));
                    s.clear.pieces.push_back((corners[c] - om).dot(vm));
                }
                if (doubleArea(&s.clear.pieces[1], shape.count) < 0.0) reverse2D(&s.clear.pieces[1], shape.count);
                beams.blockers().shadeBeam(corners, shape.count, shape.normal, m, d, tolerance, nullptr, 0.0, s);
                lit.clear();
                double litArea = 0.0;
                for (std::size_t at = 0; at < s.clear.pieces.size();) {
                    const std::size_t k = std::size_t(s.clear.pieces[at]);
                    litArea += 0.5 * std::abs(doubleArea(&s.clear.pieces[at + 1], k));
                    std::vector<Vec3>& lifted = lit.emplace_back();
                    for (std::size_t c = 0; c < k; ++c) lifted.push_back(om + s.clear.pieces[at + 1 + 2 * c] * um + s.clear.pieces[at + 2 + 2 * c] * vm);
                    at += 1 + 2 * k;
                }
                if (!(litArea > 1e-12 * mirror.area)) continue;  // in the shade: what is left is the cuts' rounding
                litMirror[std::size_t(kk)] = 1;
                // From a receiver toward the sun's image in the mirror: the reflected beam travels along -toImage.
                const Vec3 toImage = d - 2.0 * shape.normal.dot(d) * shape.normal;
                const double frontOffset = shape.normal.dot(om) + tolerance;
                // The receivers: the patches reaching into the prism the beam sweeps from the mirror, in
                // front of it.
                sideNormals.clear();
                sideOffsets.clear();
                ShadowPolygons::prismSides(corners, shape.count, toImage, sideNormals, sideOffsets);
                sideNormals.push_back(shape.normal);
                sideOffsets.push_back(frontOffset);
                beams.patches().collect(sideNormals.data(), sideOffsets.data(), sideNormals.size(), tolerance, m, m, found, s);
                const double peakBase = mirror.specular * dni;
                for (const std::uint32_t b : found) {
                    const PatchId r = beams.patches().owner(b);
                    const Patch& receiver = scene.patches[r];
                    const PatchShape& rs = geometry.shapes[r];
                    const double cosine = rs.normal.dot(toImage);
                    if (r == m || !(cosine > 0.0) || !(receiver.area > 0.0)) continue;
                    Vec3 ur, vr;
                    ShadowPolygons::planeAxes(rs.normal, ur, vr);
                    const Vec3* rc = geometry.polygon(r);
                    const Vec3 origin = rc[0];
                    // The receiver's part in front of the mirror, counter-clockwise in its plane.
                    clipAbovePlane(frontOffset * shape.normal, shape.normal, rc, rs.count, part);
                    if (part.empty()) continue;
                    std::vector<Vec2> window;
                    for (const Vec3& c : part) window.emplace_back((c - origin).dot(ur), (c - origin).dot(vr));
                    if (signedArea2d(window) < 0.0) std::reverse(window.begin(), window.end());
                    // The mirror's sunlit pieces in front of the receiver, carried along the beam onto its plane.
                    const double offset = rs.normal.dot(origin) + tolerance;
                    s.clear.pieces.clear();
                    for (const std::vector<Vec3>& sent : lit) {
                        clipAbovePlane(offset * rs.normal, rs.normal, sent.data(), sent.size(), piece);
                        if (piece.empty()) continue;
                        std::vector<Vec2> footprint;
                        for (const Vec3& c : piece) {
                            const Vec3 x = c - toImage * (rs.normal.dot(c - origin) / cosine) - origin;
                            footprint.emplace_back(x.dot(ur), x.dot(vr));
                        }
                        footprint = clipToWindow(footprint, window);
                        if (footprint.empty() || !(polygonArea2d(footprint) > 0.0)) continue;
                        if (signedArea2d(footprint) < 0.0) std::reverse(footprint.begin(), footprint.end());
                        s.clear.pieces.push_back(double(footprint.size()));
                        for (const Vec2& c : footprint) s.clear.pieces.insert(s.clear.pieces.end(), {c.x(), c.y()});
                    }
                    if (s.clear.pieces.empty()) continue;
                    // Less the shadows of what stands between the mirror's plane and the receiver.
                    beams.blockers().shadeBeam(rc, rs.count, rs.normal, r, toImage, tolerance, &shape.normal, frontOffset, s);
                    double area = 0.0;
                    for (std::size_t at = 0; at < s.clear.pieces.size();) {
                        const std::size_t k = std::size_t(s.clear.pieces[at]);
                        area += 0.5 * std::abs(doubleArea(&s.clear.pieces[at + 1], k));
                        at += 1 + 2 * k;
                    }
                    if (!(area > 0.0)) continue;
                    const double peak = peakBase * cosine;
                    hits[std::size_t(kk)].push_back({r, peak * std::min(1.0, area / receiver.area), peak, area});
                }
            } catch (const std::exception& e) {
#pragma omp critical(hemirad_reflected_sun_failure)
                if (failure.empty()) failure = e.what();
            }
        }
    }
    if (!failure.empty()) throw Error(failure);
    for (std::size_t k = 0; k < mirrors.size(); ++k) {
        out.mirrorsLit += litMirror[k];
        for (const Hit& h : hits[k]) {
            out.irradiance[h.receiver] += h.mean;
            out.spots.push_back({mirrors[k], h.receiver, h.mean, h.peak, h.area});
        }
    }
    std::sort(out.spots.begin(), out.spots.end(), [](const ReflectedSun::Spot& a, const ReflectedSun::Spot& b) {
        return a.irradiance != b.irradiance ? a.irradiance > b.irradiance
                                            : std::tie(a.mirror, a.receiver) < std::tie(b.mirror, b.receiver);
    });
    return out;
}

void writeGlareCsv(const std::string& path, const Scene& scene, const ReflectedSun& sun) {
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    const std::string unit = scene.unit.empty() ? "" : " (" + scene.unit + "^2)";
    out << "mirror,mirror_object,receiver,receiver_object,irradiance (W/m^2),peak (W/m^2),lit_area" << unit << "\n";
    for (const ReflectedSun::Spot& s : sun.spots)
        out << s.mirror << ',' << csvField(scene.objects[scene.patches[s.mirror].object]) << ',' << s.receiver << ','
            << csvField(scene.objects[scene.patches[s.receiver].object]) << ',' << s.irradiance << ',' << s.peak << ','
            << s.litArea << '\n';
    file.commit();
}

}  // namespace hemirad
