// Sensor points against references computed here, independently of the production path: Lambert's
// point-to-polygon factor in the arc-cosine form, on visible parts worked out by hand (a courtyard's
// opening, a receiver half behind a plate); the grid's lattice, the CSV's errors, the sun past a
// roof, and one hour's irradiance under a ground that sees nothing else.
#include "support.hpp"

#include "environment/irradiance.hpp"
#include "environment/sensors.hpp"
#include "preprocess/form_factor_job.hpp"
#include "preprocess/hemisphere/hemisphere_options.hpp"

#include <doctest/doctest.h>

#include <set>

using namespace hemirad;
using namespace hemirad::test;

namespace {

using Polygon = std::vector<Vec3>;

Sensors sensorsOf(const std::vector<std::pair<Vec3, Vec3>>& points) {
    Sensors s;
    for (const auto& [x, n] : points) {
        s.position.push_back(x);
        s.normal.push_back(n.normalized());
        s.name.push_back(std::to_string(s.name.size()));
    }
    return s;
}

double factor(const SensorFactors& f, std::size_t sensor, PatchId patch) {
    for (std::uint64_t k = f.rowStart[sensor]; k < f.rowStart[sensor + 1]; ++k)
        if (f.columns[k] == patch) return f.values[k];
    return 0.0;
}

/// A courtyard: a regular `sides`-gon floor of circumradius r (z = 0, facing up) and its walls up to
/// height h, facing in; the floor is patch 0, wall k patch 1 + k.
Scene courtyard(int sides, double r, double h) {
    SceneBuilder b;
    b.disk(Vec3::Zero(), r, sides, true);
    for (int k = 0; k < sides; ++k) {
        const double a0 = 2 * kPi * k / sides, a1 = 2 * kPi * (k + 1) / sides;
        const Vec3 p0(r * std::cos(a0), r * std::sin(a0), 0), p1(r * std::cos(a1), r * std::sin(a1), 0);
        b.polygon({p0, p0 + Vec3(0, 0, h), p1 + Vec3(0, 0, h), p1});  // facing the axis
    }
    return b.scene;
}

/// The closed box [0, 1]^3, its faces outward; patch 0 is its face y = 0 (facing -y).
Scene closedUnitBox() {
    SceneBuilder box;
    box.rectangle(1, 0, 0, 1, 0, 1, false);
    box.rectangle(1, 1, 0, 1, 0, 1, true);
    box.rectangle(0, 0, 0, 1, 0, 1, false);
    box.rectangle(0, 1, 0, 1, 0, 1, true);
    box.rectangle(2, 0, 0, 1, 0, 1, false);
    box.rectangle(2, 1, 0, 1, 0, 1, true);
    return box.scene;
}

}  // namespace

TEST_CASE("Sensors: the centre of a courtyard's floor sees its opening as sky, the walls as the rest, exactly") {
    const int sides = 16;
    const double r = 5.0, h = 8.0;
    const Scene s = courtyard(sides, r, h);
    for (int k = 1; k <= sides; ++k) REQUIRE(s.patches[PatchId(k)].normal.dot(-s.patches[PatchId(k)].centroid) > 0.0);
    // On the floor facing up, and 3 above it facing down (it sees the floor and the walls below it).
    const Sensors sensors = sensorsOf({{Vec3(0, 0, 0), Vec3(0, 0, 1)}, {Vec3(0, 0, 3), Vec3(0, 0, -1)}});
    const SensorFactors f = sensorFactors(s, sensors);
    Polygon opening;
    for (int k = 0; k < sides; ++k) opening.push_back(Vec3(r * std::cos(2 * kPi * k / sides), r * std::sin(2 * kPi * k / sides), h));
    const double sky = lambertFactor(Vec3::Zero(), Vec3(0, 0, 1), opening);
    MESSAGE("courtyard centre: sky view " << f.skyView[0] << ", the opening's factor " << sky << ", the circle's R^2/(R^2+H^2) "
                                          << r * r / (r * r + h * h));
    CHECK(f.skyView[0] == relative(sky, 1e-12));
    CHECK(factor(f, 0, 0) == 0.0);  // the floor it lies on
    for (int k = 1; k <= sides; ++k) {
        CAPTURE(k);
        CHECK(factor(f, 0, PatchId(k)) == relative(lambertFactor(Vec3::Zero(), Vec3(0, 0, 1), s.polygon(PatchId(k))), 1e-12));
    }
    // Facing down: the floor and the walls' parts below z = 3 close the hemisphere; no sky.
    CHECK(f.skyView[1] <= 1e-12);
    CHECK(factor(f, 1, 0) == relative(lambertFactor(Vec3(0, 0, 3), Vec3(0, 0, -1), s.polygon(0)), 1e-12));
    double sum = 0.0;
    for (std::uint64_t k = f.rowStart[1]; k < f.rowStart[2]; ++k) sum += f.values[k];
    CHECK(sum == relative(1.0, 1e-12));
}

TEST_CASE("Sensors: a receiver half behind a plate, either way the plate faces, whose back hides the sky but has no factor") {
    // Sensor at the origin facing up, a receiver [-1, 1]^2 at z = 2 facing down, and a plate over
    // x < 0 at z = 1: its shadow from the origin covers the receiver's half x < 0.
    for (const bool plateDown : {true, false}) {
        CAPTURE(plateDown);
        SceneBuilder b;
        b.rectangle(2, 2.0, -1, 1, -1, 1, false);              // the receiver, facing -z
        b.rectangle(2, 1.0, -5, 0, -5, 5, !plateDown);         // the plate
        const SensorFactors f = sensorFactors(b.scene, sensorsOf({{Vec3::Zero(), Vec3(0, 0, 1)}}));
        const Vec3 x = Vec3::Zero(), n(0, 0, 1);
        const double visible = lambertFactor(x, n, {{0, -1, 2}, {1, -1, 2}, {1, 1, 2}, {0, 1, 2}});
        const double plate = lambertFactor(x, n, {{-5, -5, 1}, {0, -5, 1}, {0, 5, 1}, {-5, 5, 1}});
        CHECK(factor(f, 0, 0) == relative(visible, 1e-12));
        CHECK(factor(f, 0, 1) == (plateDown ? relative(plate, 1e-12) : relative(0.0, 1e-12)));
        // A back seen is its reversed twin 1e-6 x the extent behind it, a little farther: the plate's
        // back covers a little less sky (the sky view factor 9e-7 larger, relative).
        MESSAGE("sky view " << f.skyView[0] << ", by hand " << 1.0 - visible - plate << ", relative " << f.skyView[0] / (1.0 - visible - plate) - 1.0);
        CHECK(f.skyView[0] == relative(1.0 - visible - plate, plateDown ? 1e-12 : 5e-6));
    }
}

TEST_CASE("Sensors: a grid over an object's faces is the lattice, each point once where two triangles share an edge") {
    SceneBuilder b;
    b.polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}});  // the unit square split along its diagonal, which
    b.polygon({{0, 0, 0}, {1, 1, 0}, {0, 1, 0}});  // runs through the lattice points (k, k)
    b.scene.objects[0] = "ground";
    const Sensors g = sensorGrid(b.scene, "ground", 0.25, 0.5);
    REQUIRE(g.size() == 16);
    std::set<std::pair<double, double>> seen;
    for (std::size_t s = 0; s < g.size(); ++s) {
        CHECK(g.position[s].z() == 0.5);
        CHECK(g.normal[s] == Vec3(0, 0, 1));
        seen.insert({g.position[s].x(), g.position[s].y()});
    }
    CHECK(seen.size() == 16);
    for (const double x : {0.125, 0.375, 0.625, 0.875})
        for (const double y : {0.125, 0.375, 0.625, 0.875}) CHECK(seen.count({x, y}) == 1);
    CHECK(g.name[0].rfind("ground:", 0) == 0);
    CHECK_THROWS_WITH_AS(sensorGrid(b.scene, "roof", 0.25, 0.5), doctest::Contains("no object 'roof'"), Error);
    CHECK_THROWS_WITH_AS(sensorGrid(b.scene, "ground", 0.0, 0.5), doctest::Contains("spacing"), Error);
    CHECK_THROWS_WITH_AS(sensorGrid(b.scene, "ground", 10.0, 0.5), doctest::Contains("no lattice point"), Error);
}

TEST_CASE("Sensors: a grid leaves out the object's boundary, and a sensor standing in a wall's plane sees it edge-on") {
    // Lattice points at 0.25 + 0.5 k: those on the ground's left and right edges (x = 0.25, 1.25)
    // would stand in the planes of walls on them, so only x = 0.75 remains.
    SceneBuilder b;
    b.rectangle(2, 0.0, 0.25, 1.25, 0, 1, true);
    b.scene.objects[0] = "ground";
    const Sensors g = sensorGrid(b.scene, "ground", 0.5, 0.1);
    REQUIRE(g.size() == 2);
    CHECK(g.position[0].x() == 0.75);
    CHECK(g.position[1].x() == 0.75);
    // A closed box [0, 1]^3 (faces outward) and a sensor facing up in the plane of its face y = 0,
    // 0.2 up: its half y > 0 is the box's inside (back faces all round), y < 0 the sky: the sky view
    // factor 1/2 (less the twins' offset, 1.4e-6 here). A sensor 1e-4 outside sees that face's
    // front over the half instead, and nothing else of the box.
    const Scene box = closedUnitBox();
    const Vec3 up(0, 0, 1);
    const SensorFactors f = sensorFactors(box, sensorsOf({{Vec3(0.5, 0, 0.2), up}, {Vec3(0.5, -1e-4, 0.2), up}}));
    MESSAGE("in the wall's plane " << f.skyView[0] << ", 1e-4 outside " << f.skyView[1]);
    CHECK(f.skyView[0] == relative(0.5, 1e-5));
    CHECK(factor(f, 0, 0) == 0.0);  // edge-on
    const double front = lambertFactor(Vec3(0.5, -1e-4, 0.2), up, {{0, 0, 0.2}, {1, 0, 0.2}, {1, 0, 1}, {0, 0, 1}});
    CHECK(factor(f, 1, 0) == relative(front, 1e-12));
    CHECK(f.skyView[1] == relative(1.0 - front, 1e-9));
}

/// Sensors on the ground (z = 0, facing up) at x = -d for each distance d, before a wall in the
/// plane x = 0 of height h and length 2 l facing them; each one's sky view factor by hand: 1 less
/// Lambert's factor to the wall.
struct WallAndSensors {
    Scene scene;
    Sensors sensors;
    std::vector<double> sky;
};
WallAndSensors wallAndSensors(const std::vector<double>& distances, double h, double l) {
    WallAndSensors w;
    SceneBuilder b;
    b.rectangle(0, 0.0, -l, l, 0, h, false);  // facing -x
    w.scene = b.scene;
    std::vector<std::pair<Vec3, Vec3>> points;
    for (const double d : distances) {
        points.push_back({Vec3(-d, 0.1 * d, 0), Vec3(0, 0, 1)});
        w.sky.push_back(1.0 - lambertFactor(points.back().first, Vec3(0, 0, 1), w.scene.polygon(0)));
    }
    w.sensors = sensorsOf(points);
    return w;
}

TEST_CASE("Sensors by rays: the sky view beside a wall against Lambert's factor, unbiased, the error falling with the rays") {
    std::vector<double> distances;
    for (int k = 0; k < 64; ++k) distances.push_back(0.2 * std::pow(1.07, k));  // 0.2 .. 14, the wall 3 high
    const WallAndSensors w = wallAndSensors(distances, 3.0, 50.0);
    std::vector<double> rms;
    for (const std::uint32_t rays : {1024u, 4096u, 65536u}) {
        const SensorFactors f = sensorFactorsByRays(w.scene, w.sensors, rays);
        CHECK(f.rays == std::uint64_t(rays) * w.sensors.size());
        double sum = 0.0, squares = 0.0;
        for (std::size_t s = 0; s < w.sensors.size(); ++s) {
            CAPTURE(s);
            // One patch, its front towards every sensor: each ray meets it or the sky.
            CHECK(factor(f, s, 0) + f.skyView[s] == doctest::Approx(1.0).epsilon(1e-14));
            sum += f.skyView[s] - w.sky[s];
            squares += (f.skyView[s] - w.sky[s]) * (f.skyView[s] - w.sky[s]);
        }
        const double mean = sum / double(w.sensors.size());
        rms.push_back(std::sqrt(squares / double(w.sensors.size())));
        MESSAGE(rays << " rays: sky view error mean " << mean << ", rms " << rms.back());
        CHECK(std::abs(mean) < 4.0 * rms.back() / std::sqrt(double(w.sensors.size())));  // no bias
    }
    // Stratified: 4 and 64 times the rays take the error down by more than 2 and 8 (1 / sqrt).
    CHECK(rms[0] < 6e-3);
    CHECK(rms[1] < rms[0] / 2.0);
    CHECK(rms[2] < rms[0] / 8.0);
}

TEST_CASE("Sensors by rays: the same factors on 1 and 2 threads, a wall through a sensor seen edge-on, and the exact ones within the rays' error") {
    // The closed box of the grid test above: a sensor in the plane of its face y = 0 (half its
    // hemisphere inside the box, seeing back faces: no factor, no sky) and one 1e-4 outside.
    const Scene box = closedUnitBox();
    const Vec3 up(0, 0, 1);
    const Sensors sensors = sensorsOf({{Vec3(0.5, 0, 0.2), up}, {Vec3(0.5, -1e-4, 0.2), up}, {Vec3(0.3, -0.7, 0), Vec3(1, -1, 1)}});
    const SensorFactors one = sensorFactorsByRays(box, sensors, 4096, 1);
    const SensorFactors two = sensorFactorsByRays(box, sensors, 4096, 2);
    CHECK(one.rowStart == two.rowStart);
    CHECK(one.columns == two.columns);
    CHECK(one.values == two.values);
    CHECK(one.skyView == two.skyView);
    const SensorFactors exact = sensorFactors(box, sensors);
    CHECK(factor(one, 0, 0) == 0.0);  // edge-on, as the exact factors
    for (std::size_t s = 0; s < sensors.size(); ++s) {
        CAPTURE(s);
        MESSAGE("sensor " << s << ": sky view " << one.skyView[s] << " by rays, " << exact.skyView[s] << " exact");
        CHECK(std::abs(one.skyView[s] - exact.skyView[s]) < 5e-3);
        for (PatchId j = 0; j < 6; ++j) CHECK(std::abs(factor(one, s, j) - factor(exact, s, j)) < 5e-3);
    }
}

TEST_CASE("Sensors' estimator: auto is exact within its budget and rays beyond it, saying why, and what is asked is kept") {
    std::string why;
    SensorOptions options;
    CHECK(chooseSensorEstimator(options, 1000, 20000, why) == SensorEstimator::Exact);
    CHECK(why.find("within the budget") != std::string::npos);
    CHECK(chooseSensorEstimator(options, 100000, 61823, why) == SensorEstimator::Rays);
    CHECK(why.find("would exceed the exact factors' budget") != std::string::npos);
    options.estimator = SensorEstimator::Exact;
    CHECK(chooseSensorEstimator(options, 100000, 61823, why) == SensorEstimator::Exact);
    options.estimator = SensorEstimator::Rays;
    CHECK(chooseSensorEstimator(options, 1, 1, why) == SensorEstimator::Rays);
    CHECK(parseSensorEstimator("rays") == SensorEstimator::Rays);
    CHECK_THROWS_WITH_AS(parseSensorEstimator("fast"), doctest::Contains("'fast' is not one of auto, exact, rays"), Error);
    const WallAndSensors w = wallAndSensors({1.0}, 1.0, 1.0);
    CHECK_THROWS_WITH_AS(sensorFactorsByRays(w.scene, w.sensors, 0), doctest::Contains("1 to 16777216 rays per sensor, not 0"), Error);
    // Through the dispatcher: auto takes the exact factors for one sensor.
    options.estimator = SensorEstimator::Auto;
    const SensorFactors f = sensorFactors(w.scene, w.sensors, options, &why);
    CHECK(f.rays == 0);
    CHECK(f.skyView[0] == doctest::Approx(w.sky[0]).epsilon(1e-12));
}

TEST_CASE("Sensors from a CSV: a header and comments skipped, a name optional, errors with file, line and value") {
    const Sensors s = parseSensorsCsv("x,y,z,nx,ny,nz,name\n# a comment\n\n1,2,3,0,0,2,north door\n4, 5, 6, 1, 0, 0\n", "s.csv");
    REQUIRE(s.size() == 2);
    CHECK(s.position[0] == Vec3(1, 2, 3));
    CHECK(s.normal[0] == Vec3(0, 0, 1));  // normalised
    CHECK(s.name[0] == "north door");
    CHECK(s.name[1] == "1");
    CHECK_THROWS_WITH_AS(parseSensorsCsv("1,2,3,0,0,1\n1,abc,3,0,0,1\n", "s.csv"), "s.csv:2: y 'abc' is not a finite number", Error);
    CHECK_THROWS_WITH_AS(parseSensorsCsv("1,2,3,0,0,0\n", "s.csv"), doctest::Contains("s.csv:1: the normal (0, 0, 0)"), Error);
    CHECK_THROWS_WITH_AS(parseSensorsCsv("1,2,3,0,0\n", "s.csv"), doctest::Contains("s.csv:1: a sensor is x,y,z,nx,ny,nz[,name]: 5 fields"), Error);
    CHECK_THROWS_WITH_AS(parseSensorsCsv("1,2,3,0,0,nan\n", "s.csv"), doctest::Contains("nz 'nan'"), Error);
    CHECK_THROWS_WITH_AS(parseSensorsCsv("# nothing\n", "s.csv"), doctest::Contains("no sensor"), Error);
    CHECK_THROWS_WITH_AS(readSensorsCsv("/nonexistent/s.csv"), doctest::Contains("cannot open"), Error);
}

TEST_CASE("Sensors in the sun: under a roof in shadow, beside it lit, facing away dark, whatever the roof's facing") {
    SceneBuilder b;
    b.rectangle(2, 3.0, 0, 2, 0, 2, false);  // a roof [0, 2]^2 at z = 3, facing down
    b.rectangle(2, 3.0, 2, 4, 0, 2, true);   // its neighbour [2, 4] x [0, 2], facing up
    const Sensors s = sensorsOf({{Vec3(1, 1, 0), Vec3(0, 0, 1)},
                                 {Vec3(3, 1, 0), Vec3(0, 0, 1)},
                                 {Vec3(5, 1, 0), Vec3(0, 0, 1)},
                                 {Vec3(5, 1, 0), Vec3(0, 0, -1)},
                                 {Vec3(1, 1, 3), Vec3(0, 0, 1)}});  // on the roof's plane, above nothing
    const std::vector<double> lit = sensorSunlit(b.scene, s, Vec3(0, 0, 1));
    CHECK(lit == std::vector<double>{0.0, 0.0, 1.0, 0.0, 1.0});
    // A low sun from +x: the point at x = 5 is past the roofs' end, the one at x = 1 under them.
    const std::vector<double> low = sensorSunlit(b.scene, s, Vec3(1, 0, 1));
    CHECK(low[0] == 0.0);
    CHECK(low[2] == 1.0);
    CHECK_THROWS_AS(sensorSunlit(b.scene, s, Vec3::Zero()), Error);
}

TEST_CASE("Sensors in the sun among boxes of triangles: the tree's ray per sensor equals a ray tried on every patch") {
    // A 6 x 6 ground of tiles and nine boxes whose faces are two triangles each (the shadow set-up
    // merges them): 3,000 random sensors, four suns. The reference meets the ray with every patch
    // (Moller-Trumbore on the patch's fan), as sensorSunlit did before its tree.
    SceneBuilder b;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) b.rectangle(2, 0.0, 4.0 * i, 4.0 * (i + 1), 4.0 * j, 4.0 * (j + 1), true);
    std::uint32_t seed = 7;
    auto uniform = [&seed] {
        seed = seed * 1664525u + 1013904223u;
        return double(seed >> 8) / double(1u << 24);
    };
    for (int k = 0; k < 9; ++k) {
        const double x0 = 2.0 + 7.0 * (k % 3) + uniform(), y0 = 2.0 + 7.0 * (k / 3) + uniform(), h = 2.0 + 6.0 * uniform();
        SceneBuilder box;
        box.rectangle(2, h, x0, x0 + 3, y0, y0 + 2, true);
        box.rectangle(0, x0, y0, y0 + 2, 0, h, false);
        box.rectangle(0, x0 + 3, y0, y0 + 2, 0, h, true);
        box.rectangle(1, y0, 0, h, x0, x0 + 3, false);
        box.rectangle(1, y0 + 2, 0, h, x0, x0 + 3, true);
        for (PatchId i = 0; i < box.scene.size(); ++i) {
            const std::vector<Vec3> c = box.scene.polygon(i);
            b.polygon({c[0], c[1], c[2]});
            b.polygon({c[0], c[2], c[3]});
        }
    }
    const Scene& scene = b.scene;
    std::vector<std::pair<Vec3, Vec3>> points;
    for (int k = 0; k < 3000; ++k) {
        const Vec3 x(24.0 * uniform(), 24.0 * uniform(), 9.0 * uniform());
        const Vec3 n = Vec3(uniform() - 0.5, uniform() - 0.5, uniform()).normalized();
        points.emplace_back(x, n);
    }
    const Sensors s = sensorsOf(points);
    const BeamShadows beams(scene);
    auto hits = [&](const Vec3& x, const Vec3& d) {
        for (PatchId j = 0; j < scene.size(); ++j) {
            const std::vector<Vec3> c = scene.polygon(j);
            for (std::size_t t = 1; t + 1 < c.size(); ++t) {
                const Vec3 e1 = c[t] - c[0], e2 = c[t + 1] - c[0], h = d.cross(e2);
                const double a = e1.dot(h);
                if (std::abs(a) < 1e-14) continue;
                const Vec3 q = x - c[0];
                const double u = q.dot(h) / a;
                const Vec3 r = q.cross(e1);
                const double v = d.dot(r) / a, along = e2.dot(r) / a;
                if (u >= 0 && v >= 0 && u + v <= 1 && along > 1e-7) return true;
            }
        }
        return false;
    };
    for (const Vec3& sun : {Vec3(0.3, 0.2, 1.0), Vec3(-1.0, 0.4, 0.5), Vec3(0.2, -1.0, 0.15), Vec3(1.0, 1.0, 0.08)}) {
        CAPTURE(sun.transpose());
        const Vec3 d = sun.normalized();
        const std::vector<double> lit = sensorSunlit(beams, s, sun);
        std::size_t differ = 0, sunny = 0;
        for (std::size_t k = 0; k < s.size(); ++k) {
            const double expected = s.normal[k].dot(d) > 0.0 && !hits(s.position[k], d) ? 1.0 : 0.0;
            differ += lit[k] != expected;
            sunny += expected == 1.0;
        }
        MESSAGE("sun " << sun.transpose() << ": " << sunny << " of " << s.size() << " sensors lit");
        CHECK(differ == 0);
        CHECK(sunny > 300);
        CHECK(sunny < s.size() - 300);
        CHECK(lit == sensorSunlit(scene, s, sun));
    }
}

TEST_CASE("Sensors' hour: a sensor over a ground sees its reflected radiosity F rho (DNI cos + DHI), the sky the rest") {
    SceneBuilder b;
    const std::uint32_t grey = b.material("grey", Rgb::Constant(0.4));
    b.rectangle(2, 0.0, -1, 1, -1, 1, true, grey);  // the ground [-1, 1]^2, facing up: it sees nothing
    const Scene& scene = b.scene;
    const Sensors s = sensorsOf({{Vec3(0, 0, 1), Vec3(0, 0, -1)}, {Vec3(0.5, 0, 1), Vec3(0, 0, 1)}});
    const SensorFactors f = sensorFactors(scene, s);
    const Vec3 toSun = Vec3(1, 0, 2).normalized();
    const double dni = 800, dhi = 100, cosGround = toSun.z();
    const FormFactors F = computeFormFactors(scene, MethodSettings::of(HemisphereOptions{}), neededRows(scene, true)).F;
    IrradianceInputs in;
    in.directSun = {dni * cosGround};
    in.skyView = {1.0};
    in.dhi = dhi;
    const IrradianceResult patches = solarIrradiance(scene, F, in, 1.0, SolverOptions{});
    REQUIRE(patches.radiosity.size() == 1);
    CHECK(patches.radiosity[0] == relative(0.4 * (dni * cosGround + dhi), 1e-12));
    const std::vector<double> lit = sensorSunlit(scene, s, toSun);
    const SensorIrradiance e = sensorIrradiance(s, f, lit, toSun, dni, dhi, patches.radiosity);
    const double down = lambertFactor(Vec3(0, 0, 1), Vec3(0, 0, -1), scene.polygon(0));
    CHECK(e.directSun[0] == 0.0);  // facing the ground
    CHECK(e.reflected[0] == relative(down * 0.4 * (dni * cosGround + dhi), 1e-12));
    CHECK(e.directSky[0] == relative(dhi * (1.0 - down), 1e-12));  // what no patch covers is sky
    CHECK(e.total[0] == relative(e.directSky[0] + e.reflected[0], 1e-15));
    // Facing up beside it: the sun and the whole sky, nothing reflected.
    CHECK(e.directSun[1] == relative(dni * cosGround, 1e-15));
    CHECK(e.directSky[1] == relative(dhi, 1e-15));
    CHECK(e.reflected[1] == 0.0);
}

TEST_CASE("hemirad sensors: the CSV and the factors' Matrix Market file, the grid, and usage errors") {
    const auto dir = tempDir("sensors-cli");
    const std::string csv = writeFile(dir / "s.csv", "x,y,z,nx,ny,nz,name\n278,1,280,0,1,0,floor middle\n278,540,280,0,-1,0,under the light\n");
    const std::string hemirad = std::string(HEMIRAD_BINARY) + " sensors " + sourcePath("scenes/cornell_box.obj");
    CommandResult r = runCommand(hemirad + " --sensors " + csv + " -o " + (dir / "out.csv").string() + " --factors " +
                                 (dir / "F.mtx").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const std::string out = readText(dir / "out.csv");
    CHECK(out.rfind("sensor,name,x,y,z,nx,ny,nz,sky_view_factor\n0,floor middle,278,1,280,0,1,0,", 0) == 0);
    const std::string mtx = readText(dir / "F.mtx");
    CHECK(mtx.rfind("%%MatrixMarket matrix coordinate real general\n", 0) == 0);
    CHECK(mtx.find("\n2 20 ") != std::string::npos);  // 2 sensors x 20 patches
    r = runCommand(hemirad + " --grid floor --spacing 100 --height 1 --dni 800 --dhi 100 --sun-direction 0,1,0 -o " +
                   (dir / "grid.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(readText(dir / "grid.csv").find(",direct_sun (W/m^2),direct_sky (W/m^2),reflected (W/m^2),total (W/m^2)\n") != std::string::npos);
    CHECK(r.output.find("sensors: 35 on a grid over 'floor'") != std::string::npos);
    // A year at the sensors: their annual sums and each hour (NumPy, hours x sensors).
    r = runCommand(std::string(HEMIRAD_BINARY) + " year " + sourcePath("scenes/cornell_box.obj") + " --up y --unit mm --weather " +
                   sourcePath("tests/data/weather/excerpt.epw") + " --sensors " + csv + " --sensor-output " +
                   (dir / "ys.csv").string() + " --sensor-hourly " + (dir / "ys.npy").string() + " -o " +
                   (dir / "ya.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(readText(dir / "ys.csv").rfind("sensor,name,sky_view_factor,direct_sun (Wh/m^2),direct_sky (Wh/m^2),reflected (Wh/m^2),total (Wh/m^2)\n0,floor middle,", 0) == 0);
    CHECK(readText(dir / "ys.npy").find(", 2), }") != std::string::npos);  // hours x 2 sensors
    const std::string year = std::string(HEMIRAD_BINARY) + " year " + sourcePath("scenes/cornell_box.obj") + " --weather " +
                             sourcePath("tests/data/weather/excerpt.epw") + " -o x.csv";
    CHECK(runCommand(year + " --sensors " + csv + " 2>&1").status == 2);  // where do their sums go?
    CHECK(runCommand(year + " --sensor-output s.csv 2>&1").status == 2);  // which sensors?
    // Under Perez's sky the sensors take their own daylight coefficients, and `sensors` gives a sky
    // model's hour too; --sky without --dni is a usage error there (no hour).
    r = runCommand(std::string(HEMIRAD_BINARY) + " year " + sourcePath("scenes/cornell_box.obj") + " --up y --unit mm --weather " +
                   sourcePath("tests/data/weather/excerpt.epw") + " --sensors " + csv + " --sensor-output " + (dir / "yp.csv").string() +
                   " --sky perez --sky-subdivision 1 -o " + (dir / "yap.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("sensors' sky: 145 cells x 1 direction(s)") != std::string::npos);
    r = runCommand(hemirad + " --sensors " + csv + " --sky cie-overcast --sky-subdivision 1 --dni 0 --dhi 100 --sun-direction 0,1,0 -o " +
                   (dir / "overcast.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(runCommand(hemirad + " --sensors " + csv + " --sky perez -o x.csv 2>&1").status == 2);
    // By rays, as asked; the report says so. A value that is no estimator is a usage error.
    r = runCommand(hemirad + " --sensors " + csv + " --sensor-estimator rays --sensor-rays 1000 -o " + (dir / "rays.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("sensor factors: rays (1000 stratified directions per sensor, 2000 rays)") != std::string::npos);
    CHECK(r.output.find("[rays, as asked]") != std::string::npos);
    r = runCommand(hemirad + " --sensors " + csv + " --sensor-estimator fast -o x.csv 2>&1");
    CHECK(r.status == 2);
    CHECK(r.output.find("'fast' is not one of auto, exact, rays") != std::string::npos);
    CHECK(runCommand(hemirad + " --sensors " + csv + " --sensor-rays 0 -o x.csv 2>&1").status == 2);
    // One source of sensors, a grid with its spacing, the sun and sky with --dni.
    for (const std::string& bad : {std::string(" -o x.csv"), " --sensors " + csv + " --grid floor --spacing 1 -o x.csv",
                                   std::string(" --grid floor -o x.csv"), " --sensors " + csv + " --spacing 2 -o x.csv",
                                   " --sensors " + csv + " --dhi 100 -o x.csv", " --sensors " + csv + " --dni 800 -o x.csv"}) {
        CAPTURE(bad);
        r = runCommand(hemirad + bad + " 2>&1");
        CHECK(r.status == 2);
    }
}
