// Scene bookkeeping: adding measured patches, bounds, and the geometry hash that keys stored F files.
#include "engine/scene.hpp"

#include "engine/error.hpp"
#include "engine/hash.hpp"
#include "engine/polygon.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace hemirad {

std::vector<Vec3> Scene::polygon(PatchId id) const {
    const Patch& p = patches[id];
    std::vector<Vec3> points(p.cornerCount);
    for (std::uint32_t k = 0; k < p.cornerCount; ++k) points[k] = corner(p, k);
    return points;
}

PatchId Scene::addPatch(const std::vector<std::uint32_t>& vertexIds, std::uint32_t material,
                        std::uint32_t object, int sourceLine) {
    Patch p;
    p.firstCorner = static_cast<std::uint32_t>(corners.size());
    p.cornerCount = static_cast<std::uint32_t>(vertexIds.size());
    corners.insert(corners.end(), vertexIds.begin(), vertexIds.end());
    p.object = object;
    p.sourceLine = sourceLine;
    const auto id = static_cast<PatchId>(patches.size());
    patches.push_back(p);
    const PolygonMeasures m = measurePolygon(polygon(id));
    Patch& q = patches.back();
    q.area = m.area;
    q.normal = m.normal;
    q.centroid = m.centroid;
    Parent parent;
    parent.firstCorner = static_cast<std::uint32_t>(parentCorners.size());
    parent.cornerCount = q.cornerCount;
    parent.firstPatch = id;
    parent.sourcePatch = id;
    parentCorners.insert(parentCorners.end(), vertexIds.begin(), vertexIds.end());
    q.parent = static_cast<std::uint32_t>(parents.size());
    parents.push_back(parent);
    applyMaterial(id, material);
    return id;
}

void Scene::updateMeasures() {
    for (PatchId id = 0; id < size(); ++id) {
        const PolygonMeasures m = measurePolygon(polygon(id));
        Patch& p = patches[id];
        p.area = m.area;
        p.normal = m.normal;
        p.centroid = m.centroid;
    }
}

void Scene::applyMaterial(PatchId id, std::uint32_t material) {
    Patch& p = patches[id];
    p.material = material;
    if (material < materials.size()) {
        const Material& m = materials[material];
        p.rho = m.rho;
        p.emission = m.emission;
        p.specular = m.specular;
    }
}

bool Scene::hasMirrors() const {
    for (const Patch& p : patches)
        if (p.specular > 0.0) return true;
    return false;
}

void Scene::bounds(Vec3& lo, Vec3& hi) const {
    lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (const Patch& p : patches)
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            lo = lo.cwiseMin(corner(p, k));
            hi = hi.cwiseMax(corner(p, k));
        }
    if (patches.empty()) lo = hi = Vec3::Zero();
}

double Scene::extent() const {
    Vec3 lo, hi;
    bounds(lo, hi);
    return (hi - lo).norm();
}

double Scene::totalArea() const {
    double sum = 0.0;
    for (const Patch& p : patches) sum += p.area;
    return sum;
}

std::uint64_t Scene::geometryHash() const {
    Fnv1a h;
    h.addValue(static_cast<std::uint64_t>(patches.size()));
    for (const Patch& p : patches) {
        h.addValue(p.cornerCount);
        for (std::uint32_t k = 0; k < p.cornerCount; ++k) {
            const Vec3 v = corner(p, k);
            h.add(v.data(), 3 * sizeof(double));
        }
        h.addValue(p.specular);
    }
    return h.value();
}

std::uint64_t Scene::contentHash() const {
    Fnv1a h;
    auto text = [&h](const std::string& s) {
        h.addValue(std::uint64_t(s.size()));
        h.add(s.data(), s.size());
    };
    auto rgb = [&h](const Rgb& c) { h.add(c.data(), 3 * sizeof(double)); };
    auto vector = [&h](const Vec3& v) { h.add(v.data(), 3 * sizeof(double)); };
    auto indices = [&h](const std::vector<std::uint32_t>& list) {
        h.addValue(std::uint64_t(list.size()));
        h.add(list.data(), list.size() * sizeof(std::uint32_t));
    };
    h.addValue(std::uint64_t(vertices.size()));
    for (const Vec3& v : vertices) vector(v);
    indices(corners);
    // Field by field: a struct's padding bytes are not its value.
    h.addValue(std::uint64_t(patches.size()));
    for (const Patch& p : patches) {
        h.addValue(p.firstCorner); h.addValue(p.cornerCount); h.addValue(p.material); h.addValue(p.object);
        rgb(p.emission); rgb(p.rho); h.addValue(p.specular);  // area, normal, centroid follow from the corners
        h.addValue(p.parent); h.addValue(p.cellI); h.addValue(p.cellJ); h.addValue(p.sourceLine);
    }
    h.addValue(std::uint64_t(materials.size()));
    for (const Material& m : materials) {
        text(m.name); rgb(m.rho); rgb(m.emission); h.addValue(m.specular); rgb(m.ks); h.addValue(m.illum);
    }
    h.addValue(std::uint64_t(objects.size()));
    for (const std::string& o : objects) text(o);
    indices(parentCorners);
    h.addValue(std::uint64_t(parents.size()));
    for (const Parent& p : parents) {
        h.addValue(p.firstCorner); h.addValue(p.cornerCount); h.addValue(std::uint8_t(p.kind)); h.addValue(p.nu);
        h.addValue(p.nv); h.addValue(p.firstPatch); h.addValue(p.patchCount); h.addValue(p.sourcePatch);
    }
    h.addValue(camera.has_value());
    if (camera) {
        vector(camera->eye); vector(camera->target); vector(camera->up); h.addValue(camera->fovY);
    }
    text(unit);
    return h.value();
}

}  // namespace hemirad

namespace hemirad {

MirrorGroups groupMirrors(const Scene& scene) {
    MirrorGroups g;
    g.groupOfPatch.assign(scene.size(), 0);
    const double tolerance = 1e-6 * scene.extent();
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Patch& p = scene.patches[i];
        if (!(p.specular > 0.0)) continue;
        for (std::size_t k = 0; k < g.representative.size() && !g.groupOfPatch[i]; ++k) {
            const Patch& q = scene.patches[g.representative[k]];
            if (q.specular == p.specular && q.normal.dot(p.normal) > 1.0 - 1e-9 &&
                std::abs((p.centroid - q.centroid).dot(q.normal)) <= tolerance)
                g.groupOfPatch[i] = std::uint32_t(k + 1);
        }
        if (!g.groupOfPatch[i]) {
            g.representative.push_back(i);
            g.groupOfPatch[i] = std::uint32_t(g.representative.size());
        }
    }
    return g;
}

namespace {

std::string cameraNumber(double x) {
    std::ostringstream out;
    out << std::setprecision(10) << x;
    return out.str();
}

std::string cameraPoint(const Vec3& p) {
    return "(" + cameraNumber(p.x()) + ", " + cameraNumber(p.y()) + ", " + cameraNumber(p.z()) + ")";
}

}  // namespace

void checkCamera(const Camera& camera) {
    if (!camera.eye.allFinite()) throw Error("camera eye " + cameraPoint(camera.eye) + " is not a finite point");
    if (!camera.target.allFinite()) throw Error("camera target " + cameraPoint(camera.target) + " is not a finite point");
    if (!(camera.fovY > 0.0 && camera.fovY < 180.0))
        throw Error("camera field of view " + cameraNumber(camera.fovY) + " is outside (0, 180) degrees");
    if (camera.eye == camera.target) throw Error("camera eye and target coincide at " + cameraPoint(camera.eye));
    // The view direction is normalised: its length must neither overflow nor underflow.
    const double distance = (camera.target - camera.eye).norm();
    if (!std::isfinite(distance))
        throw Error("camera eye " + cameraPoint(camera.eye) + " and target " + cameraPoint(camera.target) +
                    " are too far apart");
    if (!(distance > 0.0))
        throw Error("camera eye " + cameraPoint(camera.eye) + " and target " + cameraPoint(camera.target) +
                    " are too close together");
    const double up = camera.up.norm();
    if (!std::isfinite(up) || !(up > 0.0)) throw Error("camera up " + cameraPoint(camera.up) + " is not a direction");
}

namespace {
const double kMetres[] = {1.0, 0.01, 0.001, 0.0254, 0.3048};  // per lengthUnits() entry
}  // namespace

const std::vector<std::string>& lengthUnits() {
    static const std::vector<std::string> units = {"m", "cm", "mm", "in", "ft"};
    return units;
}

double metresPerUnit(const std::string& unit) {
    if (unit.empty()) return 0.0;
    const auto& units = lengthUnits();
    for (std::size_t k = 0; k < units.size(); ++k)
        if (unit == units[k]) return kMetres[k];
    throw Error("unknown length unit '" + unit + "' (m, cm, mm, in or ft)");
}

}  // namespace hemirad
