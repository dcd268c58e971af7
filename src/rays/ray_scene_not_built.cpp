// A build without Embree (HEMIRAD_WITH_EMBREE=OFF): ray casting is not available. Front ends ask
// rayCastingNotBuilt() before they load anything; a RayScene made anyway throws that text, so no
// other member can ever run.
#include "rays/ray_scene.hpp"

#include "engine/error.hpp"

namespace hemirad {

struct RayScene::Impl {};

const std::string& rayCastingNotBuilt() {
    static const std::string why = "not built: configure with -DHEMIRAD_WITH_EMBREE=ON (needs libembree-dev)";
    return why;
}

namespace {
[[noreturn]] void refuse() { throw Error("ray casting (Embree) is " + rayCastingNotBuilt()); }
}  // namespace

RayScene::RayScene(const Scene&, int) { refuse(); }

RayScene::~RayScene() = default;

void RayScene::toLocal(const Vec3& p, float out[3]) const {
    for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(p[k] - m_centre[k]);
}

// Unreachable: no RayScene exists in this build (the constructor throws).
RayScene::Hit RayScene::intersect(const Vec3&, const Vec3&, float) const { refuse(); }

void RayScene::intersectFan(const float*, const float*, std::size_t, PatchId*, float*, float) const { refuse(); }

void RayScene::occludedSegments(const float*, const float*, std::size_t, std::uint8_t*) const { refuse(); }
void RayScene::occludedSegmentPairs(const float*, const float*, std::size_t, std::uint8_t*) const { refuse(); }

}  // namespace hemirad
