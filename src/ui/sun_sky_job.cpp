// hemirad-gui's hour of sun and sky, by the library (src/environment) as hemirad irradiance.
#include "ui/sun_sky_job.hpp"

#include "engine/error.hpp"
#include "environment/reflected_sun.hpp"
#include "environment/sky_coefficients.hpp"
#include "environment/sky_view.hpp"
#include "environment/solar_position.hpp"
#include "environment/sunlit.hpp"
#include "environment/weather.hpp"

#include <sstream>

namespace hemirad::ui {

Vec3 sceneUp(int upAxis) { return upAxis == 2 ? Vec3(0, 0, 1) : Vec3(0, 1, 0); }
Vec3 sceneNorth(int upAxis) { return upAxis == 2 ? Vec3(0, 1, 0) : Vec3(0, 0, -1); }

SunSkyJob::SunSkyJob(Scene scene, std::shared_ptr<const FormFactors> F, SunSkySetup setup, int upAxis, double metres,
                     PipelineSettings settings)
    : WorkerJob(std::move(scene), std::move(F), std::move(settings), "sun and sky"), m_setup(std::move(setup)), m_upAxis(upAxis),
      m_metres(metres) {
    start();
}

SunSkyJob::~SunSkyJob() { stop(); }

void SunSkyJob::work() {
    const Vec3 up = sceneUp(m_upAxis), north = sceneNorth(m_upAxis);
    result.setup = m_setup;
    std::ostringstream where;
    where.precision(4);
    int dayOfYearValue = 0;
    bool night = false;  // the sun below the horizon: no direct sun
    if (m_setup.byTime) {
        const SolarPosition p = solarPosition(m_setup.time, m_setup.latitude, m_setup.longitude);
        night = !(p.elevation > 0.0);
        if (night) where << "below the horizon (no direct sun): ";
        result.toSun = sunDirection(p, up, north);
        where << "elevation " << p.elevation << " deg, azimuth " << p.azimuth << " deg from north at " << m_setup.time;
        dayOfYearValue = dayOfYear(m_setup.time);
    } else {
        if (!m_setup.direction.allFinite() || m_setup.direction.norm() == 0.0)
            throw Error("the direction to the sun must be a finite non-zero vector");
        result.toSun = m_setup.direction.normalized();
        where << "direction " << result.toSun.transpose() << " (given)";
    }
    result.where = where.str();
    messages.push_back("sun: " + result.where);
    std::shared_ptr<const FormFactors> F = completeRows(m_scene, m_F, true);
    if (F != m_F) newF = F;
    checkCancel();
    IrradianceInputs in;
    const BeamShadows shadows(m_scene);
    result.sunlit = night ? std::vector<double>(m_scene.size(), 0.0)
                          : timed("sunlit fractions", [&] { return shadows.sunlitFractions(result.toSun); });
    in.directSun = directIrradiance(m_scene, result.toSun, m_setup.dni, result.sunlit);
    in.dhi = m_setup.dhi;
    checkCancel();
    if (m_setup.sky == "isotropic") {
        result.skyView = timed("sky view factors", [&] { return skyViewFactors(m_scene, m_settings.formFactors).direct; });
        in.skyView = result.skyView;
    } else {
        const SkyModel model = parseSkyModel(m_setup.sky);
        const SkyCoefficients sky =
            timed("daylight coefficients", [&] { return skyCoefficients(m_scene, m_setup.subdivision, 1, up, north); });
        SkyConditions c;
        c.toSun = sceneToSky(result.toSun, up, north);
        c.dni = m_setup.dni;
        c.dhi = m_setup.dhi;
        c.dayOfYear = dayOfYearValue;
        SkyHour hour = skyHour(sky, model, c);
        if (hour.uniformFallback) messages.push_back("sky: Perez's sky is dark everywhere for this hour: the DHI comes from a uniform sky");
        in.directSky = std::move(hour.direct);
        in.reflectedSky = std::move(hour.mirrored);
        messages.push_back("sky: " + model.name() + ", " + std::to_string(sky.grid.size()) + " cells");
    }
    checkCancel();
    if (m_scene.hasMirrors() && !night) in.reflectedSun = timed("reflected sun", [&] { return reflectedSun(shadows, result.toSun, m_setup.dni).irradiance; });
    SolverOptions solver = m_settings.solver;
    solver.tolerance = std::min(solver.tolerance, 1e-10);  // the power balance is read to many digits
    result.irradiance = timed("inter-reflection", [&] { return solarIrradiance(m_scene, *F, in, m_metres, solver); });
    const IrradianceResult& r = result.irradiance;
    messages.push_back("irradiance: " + jobFigure(r.incidentPower) + " W arrive (sun and sky), " + jobFigure(r.absorbedPower) +
                       " W absorbed, " + jobFigure(r.escapedPower) + " W leave; balance " + jobFigure(r.balance, 3));
    result.geometryHash = m_scene.geometryHash();
}

}  // namespace hemirad::ui
