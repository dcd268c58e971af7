// Sensors through mirrors against references derived here by images: a sensor facing a mirror wall
// sees a plate behind it in the mirror with Lambert's factor from its image (arc-cosine form
// computed in this file), times s; the mirror's part the plate leaves is sky; a panel on the
// reflected path hides the plate; the sun reflected onto the sensor, and shadowed on either leg.
#include "support.hpp"

#include "environment/sensor_mirrors.hpp"
#include "environment/sensor_sky.hpp"
#include "environment/sky_coefficients.hpp"
#include "environment/sensors.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

using Polygon = std::vector<Vec3>;

/// The rectangle x = const, y in [y0, y1], z in [z0, z1].
Polygon wallAt(double x, double y0, double y1, double z0, double z1) {
    return {Vec3(x, y0, z0), Vec3(x, y1, z0), Vec3(x, y1, z1), Vec3(x, y0, z1)};
}

double entry(const SensorFactors& f, std::size_t sensor, PatchId patch) {
    for (std::uint64_t k = f.rowStart[sensor]; k < f.rowStart[sensor + 1]; ++k)
        if (f.columns[k] == patch) return f.values[k];
    return 0.0;
}

constexpr double kS = 0.8;

/// A mirror wall in the plane x = 0 facing +x (patch 0, s = 0.8; y in [-2, 2], z in [-2, 3]), a
/// diffuse plate at x = 3 facing -x (patch 1), and with `panel` an opaque panel at x = 2 facing -x
/// (patch 2) between them.
Scene mirrorScene(bool panel) {
    SceneBuilder b;
    const std::uint32_t mirror = b.material("mirror", Rgb::Constant(0.1), Rgb::Zero(), kS);
    b.rectangle(0, 0.0, -2, 2, -2, 3, true, mirror);
    b.rectangle(0, 3.0, -0.5, 0.5, 0, 1, false);
    if (panel) b.rectangle(0, 2.0, -1, 1, -0.5, 1.5, false);
    return b.scene;
}

Sensors oneSensor(const Vec3& x, const Vec3& n) {
    Sensors s;
    s.position.push_back(x);
    s.normal.push_back(n.normalized());
    s.name.push_back("0");
    return s;
}

}  // namespace

TEST_CASE("Sensors through a mirror: a plate behind the sensor seen in the mirror with s times its image's factor, the rest of the mirror sky") {
    if (!rayCastingNotBuilt().empty()) return;  // the reflected paths' shadow rays need Embree
    const Vec3 x(1, 0, 0.5), n(-1, 0, 0);       // facing the mirror
    const Vec3 image(-1, 0, 0.5), imageNormal(1, 0, 0);
    const double mirror = lambertFactor(x, n, wallAt(0, -2, 2, -2, 3));
    for (const bool panel : {false, true}) {
        CAPTURE(panel);
        const Scene scene = mirrorScene(panel);
        const SensorFactors f = sensorFactors(scene, oneSensor(x, n));
        REQUIRE(f.skyMirrored.size() == 1);
        CHECK(f.mirrors.rfind("followed by images", 0) == 0);
        // Behind the sensor: the plate and the panel are seen only in the mirror; the panel hides the plate.
        const double plate = lambertFactor(image, imageNormal, wallAt(3, -0.5, 0.5, 0, 1));
        const double hider = lambertFactor(image, imageNormal, wallAt(2, -1, 1, -0.5, 1.5));
        MESSAGE("mirror " << entry(f, 0, 0) << " (" << mirror << "), plate " << entry(f, 0, 1) << " (" << (panel ? 0.0 : kS * plate)
                          << "), sky in the mirror " << f.skyMirrored[0] << " (" << kS * (mirror - (panel ? hider : plate)) << ")");
        CHECK(entry(f, 0, 0) == doctest::Approx(mirror).epsilon(1e-12));
        CHECK(f.skyView[0] == doctest::Approx(1.0 - mirror).epsilon(1e-12));
        if (panel) {
            CHECK(entry(f, 0, 1) == 0.0);
            CHECK(entry(f, 0, 2) == doctest::Approx(kS * hider).epsilon(1e-10));
            CHECK(f.skyMirrored[0] == doctest::Approx(kS * (mirror - hider)).epsilon(1e-10));
        } else {
            CHECK(entry(f, 0, 1) == doctest::Approx(kS * plate).epsilon(1e-10));
            CHECK(f.skyMirrored[0] == doctest::Approx(kS * (mirror - plate)).epsilon(1e-10));
        }
        // By rays: the same within their error (65,536 stratified directions).
        const SensorFactors r = sensorFactorsByRays(scene, oneSensor(x, n), 65536);
        REQUIRE(r.skyMirrored.size() == 1);
        MESSAGE("by rays: plate " << entry(r, 0, 1) << ", sky in the mirror " << r.skyMirrored[0]);
        for (PatchId j = 0; j < scene.size(); ++j) CHECK(std::abs(entry(r, 0, j) - entry(f, 0, j)) < 3e-3);
        CHECK(std::abs(r.skyMirrored[0] - f.skyMirrored[0]) < 3e-3);
        CHECK(std::abs(r.skyView[0] - f.skyView[0]) < 3e-3);
    }
}

TEST_CASE("Sensors through two facing mirrors: the second image's sky and the chains cut off at --max-depth") {
    if (!rayCastingNotBuilt().empty()) return;
    // Mirrors x = 0 facing +x and x = 4 facing -x, both s = 0.8; the sensor between them faces -x.
    SceneBuilder b;
    const std::uint32_t mirror = b.material("mirror", Rgb::Constant(0.1), Rgb::Zero(), kS);
    b.rectangle(0, 0.0, -1, 1, -1, 1, true, mirror);
    b.rectangle(0, 4.0, -1, 1, -1, 1, false, mirror);
    const Vec3 x(1, 0, 0), n(-1, 0, 0);
    const Polygon near = wallAt(0, -1, 1, -1, 1);
    // Images by hand: x at 1 -> -1 in the near mirror (facing +x); the far mirror (x = 4) is seen
    // from there through the near one's aperture, whose cone is 5 wide at x = 4: all of it.
    const double first = lambertFactor(x, n, near);
    const double far = lambertFactor(Vec3(-1, 0, 0), Vec3(1, 0, 0), wallAt(4, -1, 1, -1, 1));
    MirrorChainLimits one;
    one.maxDepth = 1;
    const SensorFactors f1 = sensorFactors(b.scene, oneSensor(x, n), 0, one);
    // Depth 1: the far mirror's front seen in the near one with s x its image's factor; what it
    // would reflect on is cut off (counted as sky).
    CHECK(entry(f1, 0, 1) == doctest::Approx(kS * far).epsilon(1e-10));
    CHECK(f1.cutoffWeight == doctest::Approx(kS * kS * far).epsilon(1e-10));
    CHECK(f1.skyMirrored[0] == doctest::Approx(kS * (first - far) + kS * kS * far).epsilon(1e-10));
    const SensorFactors f8 = sensorFactors(b.scene, oneSensor(x, n));
    // Deeper: the near mirror seen again in the far one (depth 2), and so on; each image's share
    // is smaller, and the sky in the mirrors less than with the cut-off counted as sky.
    CHECK(entry(f8, 0, 0) > first);
    CHECK(f8.skyMirrored[0] < f1.skyMirrored[0]);
    CHECK(f8.cutoffWeight < f1.cutoffWeight);
}

TEST_CASE("The sun reflected onto a sensor by a mirror: s DNI cos, and nothing when either leg is shadowed") {
    if (!rayCastingNotBuilt().empty()) return;
    const Vec3 x(1, 0, 0.5), n(-1, 0, 0);
    const Vec3 toSun = Vec3(1, 0, 1).normalized();  // reflected at (0, 0, 1.5) toward the sensor
    const double dni = 800.0;
    const Sensors sensor = oneSensor(x, n);
    {
        const Scene scene = mirrorScene(false);
        const SensorReflections reflections(scene);
        REQUIRE(reflections.active());
        const std::vector<double> glare = reflections.sun(BeamShadows(scene), sensor, toSun, dni);
        CHECK(glare[0] == doctest::Approx(kS * dni * std::sqrt(0.5)).epsilon(1e-12));
        // A sensor facing away from the mirror gets none; nor one the beam misses (its reflection
        // point (0, 0, 3.5) lies above the mirror's top edge at z = 3).
        CHECK(reflections.sun(BeamShadows(scene), oneSensor(x, Vec3(1, 0, 0)), toSun, dni)[0] == 0.0);
        CHECK(reflections.sun(BeamShadows(scene), oneSensor(Vec3(1, 0, 2.5), n), toSun, dni)[0] == 0.0);
        // The hour: the reflected sun and the sky in the mirror in the sensor's total.
        const SensorFactors f = sensorFactors(scene, sensor);
        const SensorIrradiance h = sensorIrradiance(sensor, f, {0.0}, toSun, dni, 100.0, std::vector<double>(scene.size(), 0.0), glare);
        CHECK(h.reflectedSun[0] == glare[0]);
        CHECK(h.reflectedSky[0] == doctest::Approx(100.0 * f.skyMirrored[0]));
        CHECK(h.total[0] == doctest::Approx(h.directSky[0] + h.reflectedSun[0] + h.reflectedSky[0]));
    }
    {
        // A roof over the mirror point shades it from the sun: no reflection.
        Scene scene = mirrorScene(false);
        SceneBuilder b;
        b.scene = scene;
        b.rectangle(2, 2.5, 0.1, 3, -1, 1, false);  // z = 2.5 over x in [0.1, 3], facing down: the sun's ray from (0, 0, 1.5) meets it at x = 1
        const std::vector<double> glare = SensorReflections(b.scene).sun(BeamShadows(b.scene), sensor, toSun, dni);
        CHECK(glare[0] == 0.0);
    }
    {
        // A small panel on the reflected leg, between the mirror point and the sensor.
        SceneBuilder b;
        b.scene = mirrorScene(false);
        b.rectangle(0, 0.5, -0.2, 0.2, 0.8, 1.2, true);
        const std::vector<double> glare = SensorReflections(b.scene).sun(BeamShadows(b.scene), sensor, toSun, dni);
        CHECK(glare[0] == 0.0);
    }
}

TEST_CASE("hemirad sensors and year with a mirror: the sky in mirrors and the reflected sun get columns, the report says how") {
    if (!rayCastingNotBuilt().empty()) return;
    const auto dir = tempDir("sensor-mirrors-cli");
    const std::string csv = writeFile(dir / "s.csv", "x,y,z,nx,ny,nz,name\n278,1,280,0,1,0,floor middle\n100,300,280,1,0,0,facing x\n");
    const std::string scene = sourcePath("scenes/cornell_mirror.obj");
    CommandResult r = runCommand(std::string(HEMIRAD_BINARY) + " sensors " + scene + " --sensors " + csv +
                                 " --dni 800 --dhi 100 --sun-direction 0,1,0 -o " + (dir / "out.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("mirrors: followed by images") != std::string::npos);
    CHECK(r.output.find("sky seen in them") != std::string::npos);
    const std::string out = readText(dir / "out.csv");
    CHECK(out.rfind("sensor,name,x,y,z,nx,ny,nz,sky_view_factor,sky_direct,sky_through_mirrors,direct_sun (W/m^2),direct_sky "
                    "(W/m^2),reflected_sun (W/m^2),reflected_sky (W/m^2),reflected (W/m^2),total (W/m^2)\n",
                    0) == 0);
    r = runCommand(std::string(HEMIRAD_BINARY) + " year " + scene + " --up y --unit mm --weather " +
                   sourcePath("tests/data/weather/excerpt.epw") + " --sensors " + csv + " --sensor-output " + (dir / "ys.csv").string() +
                   " -o " + (dir / "ya.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(readText(dir / "ys.csv").rfind("sensor,name,sky_view_factor,sky_direct,sky_through_mirrors,direct_sun (Wh/m^2),direct_sky "
                                         "(Wh/m^2),reflected_sun (Wh/m^2),reflected_sky (Wh/m^2),reflected (Wh/m^2),total (Wh/m^2)\n0,floor middle,",
                                         0) == 0);
}

TEST_CASE("Sensors' daylight coefficients: open and facing up the horizontal weights, beside a wall a tiny patch's coefficients there") {
    const SkyGrid grid = skyGrid(1);
    const int samples = 2;
    const Vec3 up(0, 0, 1), north(0, 1, 0);
    // A wall along y = 0 facing +y, 4 high, and a tiny ground patch at (0, 1, 0): its sunlit fraction
    // in each beam is 0 or 1 (no shadow edge crosses 1e-4 of it), as a sensor's ray at its centre.
    SceneBuilder b;
    b.rectangle(1, 0.0, 0, 4, -20, 20, true);  // u = z, v = x
    const double h = 5e-5;
    b.rectangle(2, 0.0, -h, h, 1 - h, 1 + h, true);
    const SkyCoefficients patches = skyCoefficients(b.scene, 1, samples, up, north);
    Sensors sensors;
    sensors.position = {Vec3(0, 1, 0), Vec3(0, 1, 10)};  // the second above everything
    sensors.normal = {up, up};
    sensors.name = {"at the patch", "open"};
    const SensorSkyCoefficients c = sensorSkyCoefficients(b.scene, sensors, grid, samples, up, north);
    REQUIRE(c.direct.rows() == 2);
    CHECK(c.mirrored.size() == 0);
    double apart = 0.0, open = 0.0;
    for (std::size_t k = 0; k < grid.size(); ++k) {
        apart = std::max(apart, std::abs(c.direct(0, Eigen::Index(k)) - patches.direct(1, Eigen::Index(k))));
        open = std::max(open, std::abs(c.direct(1, Eigen::Index(k)) - patches.horizontal[k]));
    }
    // And against the wall's shadow worked out here: a direction is hidden where its ray from
    // (0, 1, 0) meets the wall's rectangle y = 0, |x| <= 20, 0 <= z <= 4.
    double byHand = 0.0;
    for (std::size_t k = 0; k < grid.size(); ++k) {
        double expected = 0.0;
        for (const Vec3& local : cellSamples(grid.cells[k], samples)) {
            const Vec3 d = skyToScene(local, up, north);
            const double t = d.y() < 0.0 ? -1.0 / d.y() : -1.0;
            const bool hidden = t > 0.0 && std::abs(t * d.x()) <= 20.0 && t * d.z() <= 4.0;
            if (!hidden) expected += grid.cells[k].solidAngle() / double(samples * samples) * std::max(0.0, d.z());
        }
        byHand = std::max(byHand, std::abs(c.direct(0, Eigen::Index(k)) - expected));
    }
    CHECK(byHand <= 1e-15);
    MESSAGE("beside the wall: largest difference from the tiny patch's coefficients " << apart << ", from the shadow by hand " << byHand
                                                                                       << "; open: from the horizontal weights " << open);
    CHECK(apart <= 1e-10);  // the patch's fraction in a beam is 1 to its area's rounding
    CHECK(open <= 1e-15);
    CHECK(c.direct.row(0).sum() < 0.8 * c.direct.row(1).sum());  // the wall hides the southern sky
    CHECK(c.direct.row(1).sum() == doctest::Approx(kPi).epsilon(2e-3));  // the cosine over the hemisphere
    // An hour of a uniform sky of radiance 1: the direct sky is the coefficients' sum.
    const SensorSky hour = sensorSkyHour(c, std::vector<double>(grid.size(), 1.0));
    CHECK(hour.direct[1] == doctest::Approx(c.direct.row(1).sum()).epsilon(1e-14));
}

TEST_CASE("The sun reflected by a mirror wall in four panes: a point of a seam or of the corner they share counts once") {
    if (!rayCastingNotBuilt().empty()) return;
    // The wall x = 0 (y in [-2, 2], z in [-2, 3]) cut at y = 0 and z = 1.5 into four panes of s = 0.8.
    SceneBuilder b;
    const std::uint32_t mirror = b.material("mirror", Rgb::Constant(0.1), Rgb::Zero(), kS);
    for (const auto& [y0, y1] : {std::pair{-2.0, 0.0}, std::pair{0.0, 2.0}})
        for (const auto& [z0, z1] : {std::pair{-2.0, 1.5}, std::pair{1.5, 3.0}}) b.rectangle(0, 0.0, y0, y1, z0, z1, true, mirror);
    const Vec3 toSun = Vec3(1, 0, 1).normalized(), n(-1, 0, 0);
    const double dni = 800.0, once = kS * dni * std::sqrt(0.5);
    const SensorReflections reflections(b.scene);
    REQUIRE(reflections.active());
    Sensors s;
    // Reflected at (0, 0, 1.5) (the corner), (0, 0.7, 1.5) (a seam along y), (0, 0, 1.0) (a seam along z)
    // and (0, 1, 1) (inside a pane).
    for (const Vec3& x : {Vec3(1, 0, 0.5), Vec3(1, 0.7, 0.5), Vec3(1, 0, 0), Vec3(1, 1, 0)}) {
        s.position.push_back(x);
        s.normal.push_back(n);
        s.name.push_back(std::to_string(s.name.size()));
    }
    const std::vector<double> glare = reflections.sun(BeamShadows(b.scene), s, toSun, dni);
    for (std::size_t k = 0; k < s.size(); ++k) {
        CAPTURE(k);
        CHECK(glare[k] == doctest::Approx(once).epsilon(1e-12));
    }
}

TEST_CASE("Sensors through the Cornell box's mirror: a floor of one patch, half hidden from the image by a block, in pieces") {
    if (!rayCastingNotBuilt().empty()) return;
    // The bundled box with a mirror wall, unsubdivided: the floor is one patch, and the ray to its
    // middle from the sensor's image is blocked. Its visible part, and the sky in the mirror, come
    // from pieces; the ray estimator (2^18 directions) is the reference.
    const Scene scene = bundledScene("cornell_mirror.obj");
    Sensors s;
    s.position = {Vec3(300, 100, 20), Vec3(102.14, 246.28, 82.94)};
    s.normal = {Vec3(-1, -0.3, 0).normalized(), Vec3(-0.239, -0.564, -0.133).normalized()};
    s.name = {"0", "1"};
    const SensorFactors exact = sensorFactors(scene, s);
    const SensorFactors rays = sensorFactorsByRays(scene, s, 1u << 18);
    REQUIRE(exact.skyMirrored.size() == 2);
    for (std::size_t k = 0; k < 2; ++k) {
        CAPTURE(k);
        MESSAGE("sky in the mirror: exact " << exact.skyMirrored[k] << ", rays " << rays.skyMirrored[k]);
        CHECK(std::abs(exact.skyMirrored[k] - rays.skyMirrored[k]) < 2.5e-3);
        for (PatchId j = 0; j < scene.size(); ++j) {
            CAPTURE(j);
            CHECK(std::abs(entry(exact, k, j) - entry(rays, k, j)) < 2.5e-3);
        }
    }
}
