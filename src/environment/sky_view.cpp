// Sky view factors from the form-factor back end: direct on the two-sided scene, and the balance of
// what mirrors send on (Sillion & Puech's extended factors) for the sky seen through them.
#include "environment/sky_view.hpp"

#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "engine/error.hpp"
#include "preprocess/form_factor_job.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numeric>

namespace hemirad {

std::vector<double> SkyView::total() const {
    std::vector<double> t(direct.size());
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = direct[i] + (mirrored.empty() ? 0.0 : mirrored[i]);
    return t;
}

Scene twoSidedScene(const Scene& scene, double offset) {
    Scene two = scene;
    const std::size_t n = scene.size();
    for (std::size_t i = 0; i < n; ++i) {
        Patch& p = two.patches[i];
        p.specular = 0.0;
        p.rho = Rgb::Constant(0.5);
    }
    for (PatchId i = 0; i < n; ++i) {
        const Patch& p = scene.patches[i];
        std::vector<std::uint32_t> ids;
        for (std::uint32_t k = p.cornerCount; k-- > 0;) {
            two.vertices.push_back(scene.corner(p, k) - offset * p.normal);
            ids.push_back(std::uint32_t(two.vertices.size() - 1));
        }
        const PatchId twin = two.addPatch(ids, p.material, p.object, p.sourceLine);
        two.patches[twin].specular = 0.0;
        two.patches[twin].rho = Rgb::Constant(0.5);
        two.patches[twin].emission = Rgb::Zero();
    }
    return two;
}

SkyView skyViewFactors(const Scene& scene, const MethodSettings& settings) {
    const std::size_t n = scene.size();
    SkyView sky;
    std::vector<PatchId> rows(n);
    std::iota(rows.begin(), rows.end(), PatchId(0));
    const Scene two = twoSidedScene(scene, 1e-6 * scene.extent());
    std::string note;
    const FormFactorRun direct = computeFormFactors(two, resolveSettings(two, settings, rows, note), rows);
    sky.method = settings.method;
    if (const auto it = direct.F.parameters.find("estimator"); it != direct.F.parameters.end())
        sky.method += ", " + it->second.substr(0, it->second.find(':'));
    sky.direct.assign(n, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        double blocked = 0.0;
        for (std::uint64_t k = direct.F.rowBegin(i); k < direct.F.rowEnd(i); ++k) blocked += direct.F.values()[k];
        sky.direct[i] = std::clamp(1.0 - blocked, 0.0, 1.0);
    }
    if (!scene.hasMirrors()) return sky;
    // Through mirrors: each ray leaving a mirror with weight s x what reached it either lands (the
    // extended factors' surplus over the direct ones) or reaches the sky.
    const FormFactorRun extended = computeFormFactors(scene, resolveSettings(scene, settings, rows, note), rows);
    sky.cutoffWeight = extended.counts.cutoffWeight;
    sky.mirrored.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        double sent = 0.0, landed = 0.0;
        for (std::uint64_t k = extended.F.rowBegin(i); k < extended.F.rowEnd(i); ++k) {
            const std::uint32_t j = extended.F.columns()[k];
            sent += scene.patches[j].specular * extended.F.values()[k];
            landed += extended.F.values()[k];
        }
        for (std::uint64_t k = direct.F.rowBegin(i); k < direct.F.rowEnd(i); ++k)
            if (direct.F.columns()[k] < n) landed -= direct.F.values()[k];  // the twins' columns are back faces
        sky.mirrored[i] = std::max(0.0, sent - landed);
    }
    return sky;
}

void writeSkyViewCsv(const std::string& path, const Scene& scene, const SkyView& sky) {
    AtomicFile file(path, false);
    std::ostream& out = file.stream();
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    const std::string unit = scene.unit.empty() ? "" : " (" + scene.unit + "^2)";
    out << "patch,object,area" << unit << ",sky_view_factor,direct,through_mirrors,x,y,z,nx,ny,nz\n";
    const std::vector<double> total = sky.total();
    for (PatchId i = 0; i < scene.size(); ++i) {
        const Vec3& c = scene.patches[i].centroid;
        const Vec3& m = scene.patches[i].normal;
        out << i << ',' << csvField(scene.objects[scene.patches[i].object]) << ',' << scene.patches[i].area << ',' << total[i] << ',' << sky.direct[i] << ','
            << (sky.mirrored.empty() ? 0.0 : sky.mirrored[i]) << ',' << c.x() << ',' << c.y() << ',' << c.z() << ',' << m.x() << ','
            << m.y() << ',' << m.z() << '\n';
    }
    file.commit();
}

SkyView readSkyViewCsv(const std::string& path, const Scene& scene) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open the sky view factors");
    const std::size_t n = scene.size();
    std::string line;
    std::size_t number = 0;
    auto fail = [&](const std::string& what) { throw Error(path + ":" + std::to_string(number) + ": " + what); };
    auto trimmed = [](std::string s) {
        if (!s.empty() && s.back() == '\r') s.pop_back();
        return s;
    };
    if (!std::getline(in, line)) throw Error(path + ": empty (no header): not a sky view factor file");
    ++number;
    line = trimmed(line);
    if (line.rfind("patch,object,area", 0) != 0 || line.find(",sky_view_factor,direct,through_mirrors,x,y,z,nx,ny,nz") == std::string::npos)
        fail("not a sky view factor file as hemirad sky-view writes it (header '" + line.substr(0, 80) +
             "'; expected patch,object,area,sky_view_factor,direct,through_mirrors,x,y,z,nx,ny,nz)");
    SkyView sky;
    sky.direct.resize(n);
    sky.mirrored.assign(n, 0.0);
    sky.method = "read from " + path;
    const double place = 1e-9 * std::max(scene.extent(), 1e-300);
    bool anyMirrored = false;
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        ++number;
        line = trimmed(line);
        if (line.empty()) continue;
        bool ok = true;
        const std::vector<std::string> f = splitQuotedCsvLine(line, ok);
        if (!ok || f.size() != 12)
            fail("expected 12 fields (patch,object,area,sky_view_factor,direct,through_mirrors,x,y,z,nx,ny,nz), read " +
                 std::to_string(f.size()) + (ok ? "" : " with an unclosed quote"));
        double v[11];
        for (int k = 0; k < 11; ++k) {
            const std::string& text = f[k == 0 ? 0 : std::size_t(k + 1)];
            char* end = nullptr;
            v[k] = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || !std::isfinite(v[k])) fail("'" + text + "' is not a number");
        }
        if (rows >= n) fail("more rows than the scene's " + std::to_string(n) + " patches: computed for other geometry");
        const Patch& p = scene.patches[rows];
        if (v[0] != double(rows)) fail("patch " + f[0] + " where patch " + std::to_string(rows) + " was expected");
        if (f[1] != scene.objects[p.object])
            fail("patch " + std::to_string(rows) + " belongs to object '" + f[1] + "' here and to '" + scene.objects[p.object] +
                 "' in the scene: computed for other geometry");
        if (std::abs(v[1] - p.area) > 1e-9 * p.area + place * place)
            fail("patch " + std::to_string(rows) + "'s area " + f[2] + " is not the scene's " + std::to_string(p.area) +
                 ": computed for other geometry");
        if ((Vec3(v[5], v[6], v[7]) - p.centroid).norm() > place)
            fail("patch " + std::to_string(rows) + "'s centroid (" + f[6] + ", " + f[7] + ", " + f[8] +
                 ") is not the scene's: computed for other geometry");
        if (!((Vec3(v[8], v[9], v[10]) - p.normal).norm() <= 1e-9))
            fail("patch " + std::to_string(rows) + " faces (" + f[9] + ", " + f[10] + ", " + f[11] +
                 ") here and the other way in the scene: computed for other geometry (a flipped patch sees other sky)");
        for (int k : {2, 3, 4})
            if (v[k] < 0.0 || v[k] > 1.0 + 1e-9) fail("a sky view factor of " + f[std::size_t(k + 1)] + " is not within 0..1");
        sky.direct[rows] = v[3];
        sky.mirrored[rows] = v[4];
        anyMirrored = anyMirrored || v[4] > 0.0;
        ++rows;
    }
    if (rows != n) throw Error(path + ": " + std::to_string(rows) + " rows for the scene's " + std::to_string(n) + " patches: computed for other geometry");
    if (!anyMirrored && !scene.hasMirrors()) sky.mirrored.clear();
    return sky;
}

}  // namespace hemirad
