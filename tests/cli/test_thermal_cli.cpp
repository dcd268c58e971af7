// `hemirad thermal` from the command line: the bundled example, its outputs, and bad input named
// by file and line with nothing written.
#include "support.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>

using namespace hemirad::test;

namespace {

CommandResult thermal(const std::string& arguments) {
    return runCommand(std::string(HEMIRAD_BINARY) + " thermal " + arguments + " 2>&1");
}

std::string example(const std::string& name) { return "'" + sourcePath("examples/thermal/" + name) + "'"; }

}  // namespace

TEST_CASE("hemirad thermal on the bundled radiator: the radiator gives off its 250 W and the balance holds") {
    const auto dir = tempDir("thermal-cli");
    const std::string T = (dir / "T.csv").string(), O = (dir / "O.csv").string(), GR = (dir / "gr.sinda").string(),
                      Q = (dir / "Q.csv").string();
    const CommandResult r = thermal(example("radiator.obj") + " --properties " + example("radiator_properties.toml") +
                                    " --bc " + example("radiator_bc.toml") + " --subdivide 0.25 -o " + T + " --objects " + O +
                                    " --conductors " + GR + " --exchange " + Q);
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("isothermal 'radiator': T = ") != std::string::npos);
    CHECK(r.output.find("energy balance: |sum Q + Q_env| / max |Q| = ") != std::string::npos);
    const std::string objects = readText(O);
    CHECK(objects.find("object,patches,area (m^2),T_mean (K)") == 0);
    CHECK(objects.find("\nradiator,16,1") != std::string::npos);
    const std::size_t row = objects.find("\nradiator,");
    REQUIRE(row != std::string::npos);
    const std::string line = objects.substr(row + 1, objects.find('\n', row + 1) - row - 1);
    CHECK(std::stod(line.substr(line.rfind(',') + 1)) == doctest::Approx(250.0).epsilon(1e-9));  // its Q
    CHECK(readText(T).find("patch,object,area (m^2),emissivity,specular,condition,T (K)") == 0);
    CHECK(readText(GR).find("HEADER CONDUCTOR DATA, MAIN\n-1, 1, 2, ") != std::string::npos);
    CHECK(readText(Q).find("Q from \\ to (W),radiator,shield,baffle,environment,total") == 0);
}

TEST_CASE("hemirad thermal with specular reflectances per IR band: each band whose mirrors differ gets its own F, shared by equal bands") {
    const auto dir = tempDir("thermal-cli-bands");
    const std::string properties = (dir / "bands.toml").string(), T = (dir / "T.csv").string();
    // Aluminium: a mirror below 4 um, less of one beyond; bands 2 and 3 reflect alike.
    writeFile(properties, "[bands]\nlimits_um = [4.0, 8.0]\n[materials.white_paint]\nemissivity = 0.88\n"
                          "[materials.aluminium]\nemissivity = [0.05, 0.2, 0.2]\nspecular = [0.9, 0.6, 0.6]\n"
                          "[materials.black_paint]\nemissivity = 0.9\n");
    const CommandResult r = thermal(example("radiator.obj") + " --properties '" + properties + "' --bc " +
                                    example("radiator_bc.toml") + " --subdivide 0.25 -o '" + T + "'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("IR bands: 3 split at 4, 8 um") != std::string::npos);
    CHECK(r.output.find("IR band 1: its specular reflectances differ from the scene's") != std::string::npos);
    CHECK(r.output.find("IR band 2: its specular reflectances differ from the scene's") != std::string::npos);
    CHECK(r.output.find("IR band 3:") == std::string::npos);  // band 2's F serves it
    CHECK(r.output.find("so it has its own F") != std::string::npos);
    const std::size_t at = r.output.find("energy balance: |sum Q + Q_env| / max |Q| = ");
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(r.output.substr(at + 44)) <= 1e-9);
    CHECK(readText(T).find("patch,object,area (m^2),emissivity,specular,condition,T (K)") == 0);
}

TEST_CASE("hemirad thermal refuses bad input before any work: file and line named, exit 1 or 2, nothing written") {
    const auto dir = tempDir("thermal-cli-errors");
    const std::string out = (dir / "T.csv").string();
    const std::string scene = example("radiator.obj");
    {
        const CommandResult r = thermal(scene + " -o " + out);
        CHECK(r.status == 2);
        CHECK(r.output.find("'thermal' needs --bc CONDITIONS.toml") != std::string::npos);
    }
    {
        const std::string props = writeFile(dir / "p.toml", "[materials.aluminium]\nemissivity = 0.2\nspecular = 0.9\n");
        const CommandResult r = thermal(scene + " --properties " + props + " --bc " + example("radiator_bc.toml") + " -o " + out);
        CHECK(r.status == 1);
        CHECK(r.output.find(props + ":1: [materials.aluminium]: emissivity 0.2 + specular 0.9 = 1.1 > 1") != std::string::npos);
    }
    {
        const std::string bc = writeFile(dir / "bc.toml", "[default]\nadiabatic = true\n\n[objects.radiatr]\npower_W = 10\n");
        const CommandResult r = thermal(scene + " --bc " + bc + " -o " + out);
        CHECK(r.status == 1);
        CHECK(r.output.find(bc + ":4: [objects.radiatr] names no object with patches") != std::string::npos);
    }
    {
        const std::string bc = writeFile(dir / "cold.toml", "[default]\ntemperature_K = -1\n");
        const CommandResult r = thermal(scene + " --bc " + bc + " -o " + out);
        CHECK(r.status == 1);
        CHECK(r.output.find("below absolute zero") != std::string::npos);
    }
    {
        const CommandResult r = thermal(scene + " --bc " + example("radiator_bc.toml") + " --conductors " +
                                        (dir / "gr.txt").string());
        CHECK(r.status == 2);
        CHECK(r.output.find("give --conductor-format") != std::string::npos);
    }
    CHECK(!std::filesystem::exists(out));
}

TEST_CASE("hemirad sky-view writes each patch's sky view factor, direct and through mirrors") {
    const auto dir = tempDir("sky-view-cli");
    const std::string out = (dir / "svf.csv").string();
    const CommandResult r = runCommand(std::string(HEMIRAD_BINARY) + " sky-view " + example("radiator.obj") + " -o " + out + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("sky view factor (hemisphere") != std::string::npos);
    const std::string csv = readText(out);
    CHECK(csv.find("patch,object,area (m^2),sky_view_factor,direct,through_mirrors,x,y,z,nx,ny,nz\n0,radiator,") == 0);
    const CommandResult missing = runCommand(std::string(HEMIRAD_BINARY) + " sky-view " + example("radiator.obj") + " 2>&1");
    CHECK(missing.status == 2);
    CHECK(missing.output.find("'sky-view' needs -o OUTPUT") != std::string::npos);
}

TEST_CASE("hemirad sun takes a given direction or a time and place, and writes the sunlit fraction and direct irradiance per patch") {
    const auto dir = tempDir("sun-cli");
    const std::string out = (dir / "sun.csv").string();
    // The radiator example is z up: straight overhead the radiator (facing +z) is lit where the baffle
    // does not shade it.
    CommandResult r = runCommand(std::string(HEMIRAD_BINARY) + " sun " + example("radiator.obj") +
                                 " --sun-direction 0,0,1 --dni 1000 -o " + out + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const std::string csv = readText(out);
    // The radiator example has a mirror (its aluminium shield, illum 3): the sun it reflects is a column too.
    CHECK(csv.find("patch,object,area (m^2),cos_incidence,sunlit_fraction,direct_irradiance (W/m^2),reflected_sun (W/m^2)\n0,radiator,1,1,") == 0);
    r = runCommand(std::string(HEMIRAD_BINARY) + " sun " + example("radiator.obj") +
                   " --sun-time 2026-06-21T13:15+02:00 --latitude 48.1 --longitude 11.6 -o " + out + " 2>&1");
    CHECK(r.status == 0);
    CHECK(r.output.find("sun: elevation 65.3") != std::string::npos);  // Munich at midsummer solar noon: 90 - 48.1 + 23.44
    r = runCommand(std::string(HEMIRAD_BINARY) + " sun " + example("radiator.obj") + " --sun-time 2026-06-21T12:00 -o " + out + " 2>&1");
    CHECK(r.status == 2);
    CHECK(r.output.find("'sun' needs --sun-direction x,y,z, or --sun-time T --latitude LAT --longitude LON") != std::string::npos);
}

TEST_CASE("hemirad sun and irradiance at night: the sun below the horizon lights nothing, the sky still does") {
    // Munich at midnight in June: the sun is 18 degrees down. Before, the patches facing its
    // direction were lit through the ground.
    const auto dir = tempDir("sun-night");
    const std::string at = " --sun-time 2026-06-21T00:00+02:00 --latitude 48.1 --longitude 11.6 --dni 800";
    CommandResult r = runCommand(std::string(HEMIRAD_BINARY) + " sun " + example("radiator.obj") + at + " -o " +
                                 (dir / "sun.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("sun: below the horizon at 2026-06-21T00:00+02:00: no patch is sunlit") != std::string::npos);
    CHECK(r.output.find("sunlit: 0 of the area") != std::string::npos);
    r = runCommand(std::string(HEMIRAD_BINARY) + " irradiance " + example("radiator.obj") + at + " --dhi 20 -o " +
                   (dir / "e.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("no direct sun (the sky alone)") != std::string::npos);
    const std::string csv = readText(dir / "e.csv");
    std::istringstream rows(csv);
    std::string line;
    std::getline(rows, line);
    double sun = 0.0, sky = 0.0;
    while (std::getline(rows, line)) {
        std::vector<std::string> f;
        std::stringstream fields(line);
        for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
        sun += std::stod(f[2]) + std::stod(f.back());  // direct_sun and reflected_sun
        sky += std::stod(f[3]);
    }
    CHECK(sun == 0.0);
    CHECK(sky > 0.0);
    // Sensors at night: no direct sun at any of them.
    r = runCommand(std::string(HEMIRAD_BINARY) + " sensors " + example("radiator.obj") + at + " --dhi 20 --grid radiator --spacing 0.5 -o " +
                   (dir / "s.csv").string() + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find(" 0 of ") != std::string::npos);  // "0 of N sensors in the sun"
    std::istringstream sensorRows(readText(dir / "s.csv"));
    std::getline(sensorRows, line);
    // The radiator has a mirror: the header names the sky's two parts, then the sun's columns.
    auto columnOf = [&](const std::string& name) {
        std::stringstream fields(line);
        std::size_t k = 0;
        for (std::string x; std::getline(fields, x, ','); ++k)
            if (x == name) return k;
        return std::size_t(-1);
    };
    const std::size_t directSun = columnOf("direct_sun (W/m^2)"), reflectedSun = columnOf("reflected_sun (W/m^2)");
    REQUIRE(directSun != std::size_t(-1));
    REQUIRE(reflectedSun != std::size_t(-1));
    std::size_t sensors = 0;
    while (std::getline(sensorRows, line)) {
        std::vector<std::string> f;
        std::stringstream fields(line);
        for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
        CHECK(std::stod(f[directSun]) == 0.0);
        CHECK(std::stod(f[reflectedSun]) == 0.0);
        ++sensors;
    }
    CHECK(sensors > 0);
}

TEST_CASE("hemirad irradiance writes the direct sun, sky, reflected, total and absorbed irradiance, balanced") {
    const auto dir = tempDir("irradiance-cli");
    const std::string out = (dir / "E.csv").string();
    const CommandResult r = runCommand(std::string(HEMIRAD_BINARY) + " irradiance " + example("radiator.obj") +
                                       " --sun-direction 0.3,-0.4,0.9 --dni 850 --dhi 110 -o " + out + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(readText(out).find("patch,object,direct_sun (W/m^2),direct_sky (W/m^2),reflected (W/m^2),total (W/m^2),absorbed (W/m^2),"
                             "reflected_sun (W/m^2)\n0,radiator,") == 0);  // the radiator has a mirror
    const std::size_t at = r.output.find("; balance ");
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(r.output.substr(at + 10)) <= 1e-9);
    const CommandResult noDni = runCommand(std::string(HEMIRAD_BINARY) + " irradiance " + example("radiator.obj") +
                                           " --sun-direction 0,0,1 -o " + out + " 2>&1");
    CHECK(noDni.status == 2);
    CHECK(noDni.output.find("'irradiance' needs --dni W") != std::string::npos);
}

TEST_CASE("hemirad year solves a weather file's hours against one F: annual sums and each hour's totals") {
    const auto dir = tempDir("year-cli");
    const std::string out = (dir / "annual.csv").string(), hourly = (dir / "total.npy").string();
    const CommandResult r = runCommand(std::string(HEMIRAD_BINARY) + " year " + example("radiator.obj") + " --weather '" +
                                       sourcePath("tests/data/weather/excerpt.epw") + "' -o " + out + " --hourly " + hourly + " 2>&1");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("weather: Munich Test, BY, DEU, latitude 48.13, longitude 11.7, UTC+1; 48 hours") != std::string::npos);
    CHECK(readText(out).find("patch,object,direct_sun (Wh/m^2),direct_sky (Wh/m^2),reflected (Wh/m^2),total (Wh/m^2),absorbed (Wh/m^2),"
                             "reflected_sun (Wh/m^2)\n0,radiator,") == 0);  // the radiator has a mirror
    CHECK(readText(hourly).find("'shape': (32, 3)") != std::string::npos);
    const CommandResult bad = runCommand(std::string(HEMIRAD_BINARY) + " year " + example("radiator.obj") + " -o " + out + " 2>&1");
    CHECK(bad.status == 2);
    CHECK(bad.output.find("'year' needs --weather FILE.epw") != std::string::npos);
}

TEST_CASE("hemirad year --svf FILE: the sky view factors computed and stored once, read by the next run to the same result") {
    const auto dir = tempDir("year-sky-view");
    const std::string svf = (dir / "svf.csv").string();
    const std::string year = std::string(HEMIRAD_BINARY) + " year " + example("radiator.obj") + " --weather '" +
                             sourcePath("tests/data/weather/excerpt.epw") + "' --svf " + svf;
    const CommandResult first = runCommand(year + " -o " + (dir / "a.csv").string() + " 2>&1");
    INFO(first.output);
    REQUIRE(first.status == 0);
    CHECK(first.output.find("stored in " + svf + " for the next run") != std::string::npos);
    const CommandResult second = runCommand(year + " -o " + (dir / "b.csv").string() + " 2>&1");
    INFO(second.output);
    REQUIRE(second.status == 0);
    CHECK(second.output.find("sky view factors: read from " + svf) != std::string::npos);
    CHECK(second.output.find("\nsky view factors  ") == std::string::npos);  // not computed again (a stage of its own)
    CHECK(first.output.find("\nsky view factors  ") != std::string::npos);
    CHECK(readText(dir / "a.csv") == readText(dir / "b.csv"));
    // hemirad sky-view writes the same file; another scene is refused; a sky model takes none.
    const CommandResult written = runCommand(std::string(HEMIRAD_BINARY) + " sky-view " + example("radiator.obj") + " -o " +
                                             (dir / "svf2.csv").string() + " 2>&1");
    REQUIRE(written.status == 0);
    CHECK(readText(dir / "svf2.csv") == readText(svf));
    const CommandResult other = runCommand(std::string(HEMIRAD_BINARY) + " year " + sourcePath("scenes/cornell_mirror.obj") +
                                           " --up y --unit mm --weather '" + sourcePath("tests/data/weather/excerpt.epw") +
                                           "' --svf " + svf + " -o " + (dir / "c.csv").string() + " 2>&1");
    CHECK(other.status == 1);
    CHECK(other.output.find(svf + ":") != std::string::npos);
    CHECK(other.output.find("computed for other geometry") != std::string::npos);
    const CommandResult model = runCommand(year + " --sky perez -o " + (dir / "d.csv").string() + " 2>&1");
    CHECK(model.status == 2);
    CHECK(model.output.find("--svf stores the isotropic sky's view factors") != std::string::npos);
}
