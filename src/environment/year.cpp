// The year's hours in batches of right-hand sides on one F.
#include "environment/year.hpp"

#include "engine/error.hpp"
#include "environment/reflected_sun.hpp"
#include "environment/sensor_mirrors.hpp"
#include "environment/solar_position.hpp"
#include "environment/sunlit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>

namespace hemirad {

namespace {
constexpr double kDegree = kPi / 180.0;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Below this reflectance a patch's received light is summed over its row of F; from it on, it is
/// read from its row of the solved system (see received).
constexpr double kReadFromSolve = 0.05;

/// What each patch receives from the others, H = F J, for each solved band (an hour), interleaved:
/// H[i * bands + b]. A patch that reflects has it in its own row of J = S + R F J: H_i = (J_i -
/// S_i) / rho_i, exact to the solve's residual r_i over rho_i (at rho >= 0.05, at most 20 |r_i|,
/// where |r_i| <= ||r|| <= the tolerance x ||S||), and free: on street64k it took a pass over F,
/// 6.7 ms of an hour's 106. The others (mirrors, black patches) sum their rows of F; where they are
/// more than a tenth of the patches, one pass over F serves all.
std::vector<double> received(const FormFactors& F, const std::vector<double>& rho, const std::vector<Band>& bands,
                             const BandSolution& solved) {
    const std::size_t n = F.size(), width = bands.size();
    std::vector<double> H(n * width);
    if (width == 0) return H;
    std::vector<std::size_t> summed;
    for (std::size_t i = 0; i < n; ++i)
        if (!(rho[i] >= kReadFromSolve)) summed.push_back(i);
    if (summed.size() * 10 > n) {
        std::vector<double> Jt(n * width);
        for (std::size_t b = 0; b < width; ++b)
            for (std::size_t j = 0; j < n; ++j) Jt[j * width + b] = solved.X[b][j];
        multiplyInterleaved(F, width, Jt.data(), H);
        return H;
    }
    for (std::size_t b = 0; b < width; ++b)
        for (std::size_t i = 0; i < n; ++i)
            if (rho[i] >= kReadFromSolve) H[i * width + b] = (solved.X[b][i] - bands[b].source[i]) / rho[i];
#pragma omp parallel for schedule(dynamic, 16)
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(summed.size()); ++k) {
        const std::size_t i = summed[std::size_t(k)];
        for (std::size_t b = 0; b < width; ++b) {
            double sum = 0.0;
            for (std::uint64_t e = F.rowBegin(i); e < F.rowEnd(i); ++e) sum += double(F.values()[e]) * solved.X[b][F.columns()[e]];
            H[i * width + b] = sum;
        }
    }
    return H;
}
}  // namespace

YearResult solveYear(const Scene& scene, const FormFactors& F, const std::vector<double>& skyView, const Weather& weather,
                     const YearOptions& options, const SolverOptions& solver) {
    const std::size_t n = scene.size();
    const SkyCoefficients* model = options.sky;
    if ((!model && skyView.size() != n) || F.size() != n) throw Error("year: the sky view factors and F need one entry per patch");
    if (model && (std::size_t(model->direct.rows()) != n || (scene.hasMirrors() && std::size_t(model->mirrored.rows()) != n)))
        throw Error("year: the sky's coefficients are not this scene's");
    if (model && options.sensors &&
        (!options.sensorSky || std::size_t(options.sensorSky->direct.rows()) != options.sensors->size() ||
         options.sensorSky->direct.cols() != model->direct.cols() ||
         (options.sensorSky->mirrored.size() > 0 && (options.sensorSky->mirrored.rows() != options.sensorSky->direct.rows() ||
                                                     options.sensorSky->mirrored.cols() != model->direct.cols()))))
        throw Error("year: sensors under the " + options.skyModel.name() +
                    " sky need their daylight coefficients for the sky's cells (sensorSkyCoefficients)");
    for (std::size_t i = 0; i < n; ++i)
        if (!F.rowComputed(i)) throw Error("year: row " + std::to_string(i) + " of F was not computed (compute every row)");
    YearResult out;
    out.directSun.assign(n, 0.0);
    out.directSky.assign(n, 0.0);
    out.reflected.assign(n, 0.0);
    out.sum.assign(n, 0.0);
    out.absorbed.assign(n, 0.0);
    std::vector<double> rho(n), absorptance(n), landedFrom(n, 0.0), area(n);
    const double m2 = options.metresPerUnit * options.metresPerUnit;
    for (std::size_t i = 0; i < n; ++i) {
        rho[i] = std::clamp(scene.patches[i].rho.mean(), 0.0, 1.0 - scene.patches[i].specular);
        absorptance[i] = std::max(0.0, 1.0 - rho[i] - scene.patches[i].specular);
        area[i] = scene.patches[i].area * m2;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const double w = area[i] * (1.0 - scene.patches[i].specular);
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) landedFrom[F.columns()[k]] += w * double(F.values()[k]);
    }
    out.hours = solvedHours(weather);
    const bool keep = !options.hourly;  // else each hour goes to the callback as it is solved
    if (keep) out.total.assign(out.hours.size() * n, 0.0);
    const std::size_t sensors = options.sensors ? options.sensors->size() : 0;
    if (options.sensors && (!options.sensorFactors || options.sensorFactors->skyView.size() != sensors ||
                            options.sensorFactors->patches != n))
        throw Error("year: the sensors need their factors against this scene (sensorFactors)");
    out.reflectedSun.assign(n, 0.0);
    out.reflectedSky.assign(n, 0.0);
    const bool mirrors = scene.hasMirrors();
    if (keep) out.sensorTotal.assign(out.hours.size() * sensors, 0.0);
    std::vector<double> hourTotal(keep ? 0 : n), hourSensors(keep ? 0 : sensors);
    out.sensorDirectSun.assign(sensors, 0.0);
    out.sensorDirectSky.assign(sensors, 0.0);
    out.sensorReflected.assign(sensors, 0.0);
    out.sensorSum.assign(sensors, 0.0);
    out.sensorReflectedSun.assign(sensors, 0.0);
    out.sensorReflectedSky.assign(sensors, 0.0);
    // The sun the mirrors reflect onto the sensors (their factors carry the rest of what mirrors show them).
    std::unique_ptr<SensorReflections> sensorMirrors;
    if (sensors && scene.hasMirrors()) {
        sensorMirrors = std::make_unique<SensorReflections>(scene);
        if (!sensorMirrors->active()) sensorMirrors.reset();
    }

    const BeamShadows shadows(scene);  // set up once for every hour's sun
    // Radiosity is linear in its sources. The isotropic sky has one shape, DHI x the sky view
    // factors: its radiosity per unit DHI is solved once and scaled. A sky model's hour is a sum
    // over its cells, radiance x the cell's coefficients (direct and through mirrors): the
    // radiosity per unit radiance of each cell (the daylight coefficients carried through the
    // inter-reflection) is solved once, and an hour's sky is one product with it. Each hour then
    // solves for its sun alone, and an hour without sun solves nothing. Where a model has more
    // cells than the weather has hours with sky (a day's file, a fine subdivision), each hour
    // solves its own sky instead: fewer solves, and no N x cells matrices.
    using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMatrix skyJ, skyH;  // per patch, per unit of the sky (DHI, or each cell's radiance): J and F J
    std::size_t skyHours = 0;
    for (const std::size_t h : out.hours) skyHours += weather.hours[h].dhi > 0.0;
    const std::size_t columns = model ? model->grid.size() : 1;
    const bool skyOnce = columns <= std::max<std::size_t>(skyHours, 1);
    if (skyOnce) {
        const auto solving = Clock::now();
        skyJ = RowMatrix::Zero(Eigen::Index(n), Eigen::Index(columns));
        SolverOptions each = solver;  // the hour sums the columns: each to its share of the tolerance
        each.tolerance = solver.tolerance / std::sqrt(double(columns));
        for (std::size_t first = 0; first < columns; first += options.batch) {
            const std::size_t last = std::min(columns, first + options.batch);
            std::vector<Band> units(last - first);
            for (std::size_t k = first; k < last; ++k) {
                Band& unit = units[k - first];
                unit.name = model ? "sky cell " + std::to_string(k + 1) : "the isotropic sky";
                unit.rho = rho;
                unit.source.resize(n);
                for (std::size_t i = 0; i < n; ++i) {
                    const double arriving = model ? model->direct(Eigen::Index(i), Eigen::Index(k)) +
                                                        (mirrors ? model->mirrored(Eigen::Index(i), Eigen::Index(k)) : 0.0)
                                                  : skyView[i];
                    unit.source[i] = rho[i] * arriving;
                }
            }
            const BandSolution solved = solveBands(scene, F, units, each);
            for (std::size_t k = first; k < last; ++k)
                for (std::size_t i = 0; i < n; ++i) skyJ(Eigen::Index(i), Eigen::Index(k)) = solved.X[k - first][i];
        }
        std::vector<double> FJ;
        multiplyInterleaved(F, columns, skyJ.data(), FJ);
        skyH = Eigen::Map<const RowMatrix>(FJ.data(), Eigen::Index(n), Eigen::Index(columns));
        out.solveSeconds += since(solving);
    }
    std::vector<std::vector<double>> sun, sky, bounced, skyBounced, sensorLit, sensorGlare;
    std::vector<Vec3> toSuns;
    std::vector<double> J(n);
    for (std::size_t first = 0; first < out.hours.size(); first += options.batch) {
        const std::size_t last = std::min(out.hours.size(), first + options.batch);
        std::vector<Band> bands;
        std::vector<std::size_t> bandOf(last - first, SIZE_MAX);  // the band an hour solves, if any
        bands.reserve(last - first);
        sun.assign(last - first, {});
        sky.assign(last - first, {});
        bounced.assign(last - first, std::vector<double>(n, 0.0));
        skyBounced.assign(last - first, std::vector<double>(n, 0.0));
        // A sky model's hours: each hour's cell radiances, then all of the batch's direct (and
        // mirrored) sky in one matrix product with the coefficients.
        Eigen::MatrixXd radiance;
        if (model) radiance = Eigen::MatrixXd::Zero(Eigen::Index(model->grid.size()), Eigen::Index(last - first));
        sensorLit.assign(last - first, std::vector<double>(sensors, 0.0));
        sensorGlare.assign(last - first, std::vector<double>(sensorMirrors ? sensors : 0, 0.0));
        toSuns.assign(last - first, Vec3(0, 0, 1));
        for (std::size_t b = first; b < last; ++b) {
            const WeatherHour& hour = weather.hours[out.hours[b]];
            std::vector<double>& direct = sun[b - first];
            direct.assign(n, 0.0);
            const SolarPosition p = solarPosition(middleOfHourUtc(hour, weather.timeZone), weather.latitude, weather.longitude);
            if (p.elevation > 0.0 && hour.dni > 0.0) {
                const auto sunStart = Clock::now();
                const Vec3 toSun = sunDirection(p, options.up, options.north);
                direct = directIrradiance(scene, toSun, hour.dni, shadows.sunlitFractions(toSun));
                toSuns[b - first] = toSun;
                if (mirrors) bounced[b - first] = reflectedSun(shadows, toSun, hour.dni).irradiance;
                if (sensors) sensorLit[b - first] = sensorSunlit(shadows, *options.sensors, toSun);
                if (sensorMirrors) sensorGlare[b - first] = sensorMirrors->sun(shadows, *options.sensors, toSun, hour.dni);
                out.sunSeconds += since(sunStart);
            }
            if (model && hour.dhi > 0.0) {
                const auto skyStart = Clock::now();
                SkyConditions c;
                c.toSun = skyDirection(p.elevation * kDegree, p.azimuth * kDegree);
                c.dni = hour.dni;
                c.dhi = hour.dhi;
                c.dayOfYear = dayOfYear(hour);
                if (options.skyModel.kind == SkyModel::Kind::Perez && perezParameters(c).clamped) ++out.skyClampedHours;
                std::vector<double> L;
                try {
                    bool uniform = false;
                    L = skyRadiance(model->grid, model->samples, options.skyModel, c, &uniform);
                    out.skyUniformHours += uniform;
                } catch (const Error& e) {
                    throw Error(std::string(e.what()) + " (the weather's line " + std::to_string(hour.line) + ": DNI " +
                                std::to_string(hour.dni) + ", DHI " + std::to_string(hour.dhi) + ")");
                }
                radiance.col(Eigen::Index(b - first)) = Eigen::Map<const Eigen::VectorXd>(L.data(), Eigen::Index(L.size()));
                out.skySeconds += since(skyStart);
            }
        }
        // The batch's sky: each hour's units of sky (its DHI, or its cells' radiances), then the
        // direct sky, the sky through mirrors, and the sky's radiosity and F J in matrix products.
        const auto skyStart = Clock::now();
        Eigen::MatrixXd skyDirect, skyMirrored, sensorSkyDirect, sensorSkyMirrored;
        if (model) {
            skyDirect = model->direct * radiance;
            if (mirrors) skyMirrored = model->mirrored * radiance;
            if (sensors) {
                sensorSkyDirect = options.sensorSky->direct * radiance;
                if (options.sensorSky->mirrored.size() > 0) sensorSkyMirrored = options.sensorSky->mirrored * radiance;
            }
        }
        Eigen::MatrixXd skyRadiosity = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(last - first)), skyReceived = skyRadiosity;
        if (skyOnce) {
            Eigen::MatrixXd units(skyJ.cols(), Eigen::Index(last - first));
            for (std::size_t b = first; b < last; ++b)
                units.col(Eigen::Index(b - first)) = model ? Eigen::VectorXd(radiance.col(Eigen::Index(b - first)))
                                                           : Eigen::VectorXd::Constant(1, weather.hours[out.hours[b]].dhi);
            skyRadiosity = skyJ * units;
            skyReceived = skyH * units;
        }
        out.skySeconds += since(skyStart);
        for (std::size_t b = first; b < last; ++b) {
            const WeatherHour& hour = weather.hours[out.hours[b]];
            const std::vector<double>& direct = sun[b - first];
            std::vector<double>& diffuse = sky[b - first];
            diffuse.resize(n);
            Band band;
            band.name = "hour " + std::to_string(hour.line);
            band.rho = rho;
            band.source.resize(n);
            bool source = false;
            for (std::size_t i = 0; i < n; ++i) {
                diffuse[i] = model ? skyDirect(Eigen::Index(i), Eigen::Index(b - first)) : hour.dhi * skyView[i];
                if (model && mirrors) skyBounced[b - first][i] = skyMirrored(Eigen::Index(i), Eigen::Index(b - first));
                // The sky comes in through skyJ, or with the hour's own solve.
                band.source[i] = rho[i] * (direct[i] + bounced[b - first][i] + (skyOnce ? 0.0 : diffuse[i] + skyBounced[b - first][i]));
                source = source || band.source[i] != 0.0;
            }
            if (source) {
                bandOf[b - first] = bands.size();
                bands.push_back(std::move(band));
            }
        }
        const auto solving = Clock::now();
        const BandSolution solved = bands.empty() ? BandSolution{} : solveBands(scene, F, bands, solver);
        out.solveSeconds += since(solving);
        const auto tallying = Clock::now();
        const std::size_t width = bands.size();
        const std::vector<double> Hb = received(F, rho, bands, solved);
        for (std::size_t b = first; b < last; ++b) {
            const std::size_t own = bandOf[b - first];
            const Eigen::Index column = Eigen::Index(b - first);
            for (std::size_t i = 0; i < n; ++i) J[i] = (own == SIZE_MAX ? 0.0 : solved.X[own][i]) + skyRadiosity(Eigen::Index(i), column);
            double incident = 0.0, absorbed = 0.0, escaped = 0.0;
            for (std::size_t i = 0; i < n; ++i) {
                const double H = (own == SIZE_MAX ? 0.0 : Hb[i * width + own]) + skyReceived(Eigen::Index(i), column);
                // The sun (and sky) reflected by mirrors arrives first too; it came in as the direct sun
                // (and sky) on them.
                const double outside = sun[b - first][i] + sky[b - first][i];
                const double reflectedSun = bounced[b - first][i], reflectedSky = skyBounced[b - first][i];
                const double firstArrival = outside + reflectedSun + reflectedSky, total = firstArrival + H;
                (keep ? out.total[b * n + i] : hourTotal[i]) = total;
                out.directSun[i] += sun[b - first][i];
                out.directSky[i] += sky[b - first][i];
                out.reflectedSun[i] += reflectedSun;
                out.reflectedSky[i] += reflectedSky;
                out.reflected[i] += H;
                out.sum[i] += total;
                out.absorbed[i] += absorptance[i] * total;
                incident += area[i] * outside;
                absorbed += area[i] * absorptance[i] * total;
                escaped += area[i] * scene.patches[i].specular * firstArrival + J[i] * (area[i] - landedFrom[i]) -
                           area[i] * (reflectedSun + reflectedSky);  // the mirrors' reflection that landed did not leave
            }
            if (sensors) {
                const WeatherHour& hour = weather.hours[out.hours[b]];
                SensorSky modelSky;
                if (model) {
                    const Eigen::Index column = Eigen::Index(b - first);
                    modelSky.direct.resize(sensors);
                    for (std::size_t s = 0; s < sensors; ++s) modelSky.direct[s] = sensorSkyDirect(Eigen::Index(s), column);
                    if (sensorSkyMirrored.size() > 0) {
                        modelSky.mirrored.resize(sensors);
                        for (std::size_t s = 0; s < sensors; ++s) modelSky.mirrored[s] = sensorSkyMirrored(Eigen::Index(s), column);
                    }
                }
                const SensorIrradiance at = sensorIrradiance(*options.sensors, *options.sensorFactors, sensorLit[b - first],
                                                             toSuns[b - first], hour.dni, hour.dhi, J, sensorGlare[b - first],
                                                             model ? &modelSky : nullptr);
                for (std::size_t s = 0; s < sensors; ++s) {
                    (keep ? out.sensorTotal[b * sensors + s] : hourSensors[s]) = at.total[s];
                    out.sensorDirectSun[s] += at.directSun[s];
                    out.sensorDirectSky[s] += at.directSky[s];
                    out.sensorReflected[s] += at.reflected[s];
                    out.sensorSum[s] += at.total[s];
                    out.sensorReflectedSun[s] += at.reflectedSun[s];
                    out.sensorReflectedSky[s] += at.reflectedSky[s];
                }
            }
            if (!keep) options.hourly(hourTotal.data(), sensors ? hourSensors.data() : nullptr);
            out.incidentWh += incident;
            out.absorbedWh += absorbed;
            if (incident > 0.0) out.worstBalance = std::max(out.worstBalance, std::abs(incident - absorbed - escaped) / incident);
        }
        out.tallySeconds += since(tallying);
    }
    return out;
}

std::vector<std::size_t> solvedHours(const Weather& weather) {
    std::vector<std::size_t> hours;
    for (std::size_t h = 0; h < weather.hours.size(); ++h)
        if (weather.hours[h].dni > 0.0 || weather.hours[h].dhi > 0.0) hours.push_back(h);
    return hours;
}

NpyWriter::NpyWriter(const std::string& path, std::size_t rows, std::size_t columns)
    : m_file(path, true), m_rows(rows), m_columns(columns) {
    std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", " +
                         std::to_string(columns) + "), }";
    // Magic (6) + version (2) + length (2) + header, padded with spaces to a multiple of 64, ending in \n.
    const std::size_t total = 10 + header.size() + 1;
    header.append((64 - total % 64) % 64, ' ');
    header += '\n';
    std::ostream& out = m_file.stream();
    out.write("\x93NUMPY\x01\x00", 8);
    const std::uint16_t length = std::uint16_t(header.size());
    const char lengthBytes[2] = {char(length & 0xff), char(length >> 8)};
    out.write(lengthBytes, 2);
    out.write(header.data(), std::streamsize(header.size()));
}

void NpyWriter::append(const double* row) {
    if (m_written == m_rows) throw Error("npy: more than the " + std::to_string(m_rows) + " rows declared");
    m_file.stream().write(reinterpret_cast<const char*>(row), std::streamsize(m_columns * sizeof(double)));
    ++m_written;
}

void NpyWriter::commit() {
    if (m_written != m_rows)
        throw Error("npy: " + std::to_string(m_written) + " of the " + std::to_string(m_rows) + " rows declared were written");
    m_file.commit();
}

void writeNpy(const std::string& path, const std::vector<double>& values, std::size_t rows, std::size_t columns) {
    if (values.size() != rows * columns) throw Error("npy: " + std::to_string(values.size()) + " values are not " +
                                                     std::to_string(rows) + " x " + std::to_string(columns));
    NpyWriter file(path, rows, columns);
    for (std::size_t r = 0; r < rows; ++r) file.append(values.data() + r * columns);
    file.commit();
}

}  // namespace hemirad
