// Hemicube back end: OpenGL renders patch ids on the five faces of a hemicube around each patch.
#pragma once

#include "preprocess/form_factor_backend.hpp"
#include "preprocess/hemicube/hemicube_geometry.hpp"
#include "preprocess/hemicube/hemicube_layout.hpp"
#include "preprocess/hemicube/hemicube_options.hpp"
#include "rays/ray_scene.hpp"

#include <memory>

namespace hemirad {

/// Cohen & Greenberg (1985): each pixel of the hemicube atlas carries its delta form factor;
/// F_ij sums the pixels that see patch j's front. One GL context per worker thread (headless EGL
/// on Mesa's llvmpipe here, any GPU driver elsewhere), each computing its own rows.
class HemicubeBackend final : public FormFactorBackend {
public:
    HemicubeBackend(const HemicubeOptions& options, const CommonOptions& common);
    ~HemicubeBackend() override;

    std::string_view name() const override { return "hemicube"; }
    void prepare(const Scene& scene) override;
    using FormFactorBackend::computeRows;
    void computeRows(RowSource& rows, FormFactorBuilder& builder) override;
    FormFactorProvenance provenance() const override;
    std::map<std::string, std::string> parameters() const override;

private:
    HemicubeOptions m_options;
    CommonOptions m_common;
    const Scene* m_scene = nullptr;
    std::unique_ptr<HemicubeLayout> m_layout;
    HemicubeGeometry m_geometry;
    std::unique_ptr<RayScene> m_rays;  ///< for --mirrors rays
    int m_workers = 1;
};

struct BackendDescriptor;
/// The registry entry (hemicube_descriptor.cpp).
const BackendDescriptor& hemicubeDescriptor();

}  // namespace hemirad
