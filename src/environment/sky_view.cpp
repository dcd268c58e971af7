// Sky view factors from the form-factor back end: direct on the two-sided scene, and the balance of
// what mirrors send on (Sillion & Puech's extended factors) for the sky seen through them.
#include "environment/sky_view.hpp"

#include "engine/atomic_file.hpp"
#include "engine/csv.hpp"
#include "engine/error.hpp"
#include "preprocess/form_factor_job.hpp"

#include <algorithm>
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
    out << "patch,object,area" << unit << ",sky_view_factor,direct,through_mirrors\n";
    const std::vector<double> total = sky.total();
    for (PatchId i = 0; i < scene.size(); ++i) {
        out << i << ',' << csvField(scene.objects[scene.patches[i].object]) << ',' << scene.patches[i].area << ',' << total[i] << ',' << sky.direct[i] << ','
            << (sky.mirrored.empty() ? 0.0 : sky.mirrored[i]) << '\n';
    }
    file.commit();
}

}  // namespace hemirad
