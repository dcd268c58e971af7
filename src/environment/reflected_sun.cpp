// The sun's first reflections by planar mirrors: each mirror's sunlit pieces (sunlit.hpp) carried
// along the reflected beam onto each receiver's plane, cut to the receiver, less the shadows of the
// patches between the mirror's plane and the receiver's.
#include "environment/reflected_sun.hpp"

#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "engine/error.hpp"
#include "environment/sunlit.hpp"
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

ReflectedSun reflectedSun(const Scene& scene, const Vec3& toSunGiven, double dni) {
    if (!toSunGiven.allFinite() || !(toSunGiven.norm() > 0.0)) throw Error("sun: the direction to the sun must be a finite non-zero vector");
    if (!(std::isfinite(dni) && dni >= 0.0)) throw Error("sun: the direct-normal irradiance must be finite and >= 0");
    const Vec3 d = toSunGiven.normalized();
    const std::size_t n = scene.size();
    const double tolerance = 1e-9 * std::max(scene.extent(), 1e-300);
    ReflectedSun out;
    out.irradiance.assign(n, 0.0);
    std::vector<PatchId> mirrors;
    for (PatchId m = 0; m < n; ++m)
        if (scene.patches[m].specular > 0.0 && scene.patches[m].normal.dot(d) > 0.0 && scene.patches[m].area > 0.0) mirrors.push_back(m);
    if (mirrors.empty()) return out;
    const std::vector<std::vector<PatchId>> sunCandidates = beamCandidates(scene, d);

    for (const PatchId m : mirrors) {
        const Patch& mirror = scene.patches[m];
        Vec3 um, vm;
        orthonormalBasis(mirror.normal, um, vm);
        const Vec3 om = scene.corner(mirror, 0);
        std::vector<std::vector<Vec3>> lit;
        double litArea = 0.0;
        for (const std::vector<Vec2>& piece : sunlitPieces(scene, m, d, sunCandidates[m], um, vm, tolerance)) {
            litArea += polygonArea2d(piece);
            lit.emplace_back();
            for (const Vec2& c : piece) lit.back().push_back(om + c.x() * um + c.y() * vm);
        }
        if (!(litArea > 1e-12 * mirror.area)) continue;  // in the shade: what is left is the cuts' rounding
        ++out.mirrorsLit;
        // From a receiver toward the sun's image in the mirror: the reflected beam travels along -toImage.
        const Vec3 toImage = d - 2.0 * mirror.normal.dot(d) * mirror.normal;
        const std::vector<std::vector<PatchId>> beam = beamCandidates(scene, toImage);
        const Plane front{mirror.normal, mirror.normal.dot(om) + tolerance};
        const double peakBase = mirror.specular * dni;
        const std::vector<PatchId>& receivers = beam[m];
#pragma omp parallel for schedule(dynamic, 16)
        for (std::int64_t kk = 0; kk < std::int64_t(receivers.size()); ++kk) {
            const PatchId r = receivers[std::size_t(kk)];
            const Patch& receiver = scene.patches[r];
            const double cosine = receiver.normal.dot(toImage);
            if (r == m || !(cosine > 0.0) || !(receiver.area > 0.0)) continue;
            Vec3 ur, vr;
            orthonormalBasis(receiver.normal, ur, vr);
            const Vec3 origin = scene.corner(receiver, 0);
            // The receiver's part in front of the mirror, counter-clockwise in its plane.
            const std::vector<Vec3> whole = scene.polygon(r);
            std::vector<Vec3> part;
            clipAbovePlane(front.offset * front.normal, front.normal, whole.data(), whole.size(), part);
            if (part.empty()) continue;
            std::vector<Vec2> window = planeCoordinates(part, origin, ur, vr);
            if (signedArea2d(window) < 0.0) std::reverse(window.begin(), window.end());
            // The mirror's sunlit pieces in front of the receiver, carried along the beam onto its plane.
            std::vector<std::vector<Vec2>> pieces;
            const double offset = receiver.normal.dot(origin) + tolerance;
            std::vector<Vec3> piece;
            for (const std::vector<Vec3>& sent : lit) {
                clipAbovePlane(offset * receiver.normal, receiver.normal, sent.data(), sent.size(), piece);
                if (piece.empty()) continue;
                std::vector<Vec2> footprint;
                for (const Vec3& c : piece) {
                    const Vec3 x = c - toImage * (receiver.normal.dot(c - origin) / cosine) - origin;
                    footprint.emplace_back(x.dot(ur), x.dot(vr));
                }
                footprint = clipToWindow(footprint, window);
                if (!footprint.empty() && polygonArea2d(footprint) > 0.0) pieces.push_back(std::move(footprint));
            }
            if (pieces.empty()) continue;
            pieces = shadowedPieces(scene, std::move(pieces), origin, receiver.normal, ur, vr, toImage, beam[r], r, &front, tolerance);
            double area = 0.0;
            for (const std::vector<Vec2>& piece : pieces) area += polygonArea2d(piece);
            if (!(area > 0.0)) continue;
            const double peak = peakBase * cosine;
            const double mean = peak * std::min(1.0, area / receiver.area);
            out.irradiance[r] += mean;
#pragma omp critical(hemirad_reflected_sun_spots)
            out.spots.push_back({m, r, mean, peak, area});
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
