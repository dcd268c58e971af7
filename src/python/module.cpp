// hemirad._hemirad: the C++ library seen from Python. A thin layer over the pipeline, the back-end and
// solver registries and the F files; hemirad/__init__.py turns its arrays into scipy/numpy objects.
#include "engine/error.hpp"
#include "environment/irradiance.hpp"
#include "environment/reflected_sun.hpp"
#include "environment/sensor_sky.hpp"
#include "environment/sensors.hpp"
#include "environment/sky_coefficients.hpp"
#include "environment/sky_view.hpp"
#include "environment/solar_position.hpp"
#include "environment/sunlit.hpp"
#include "engine/form_factor_file.hpp"
#include "engine/obj_writer.hpp"
#include "engine/result_writer.hpp"
#include "engine/vertex_radiosity.hpp"
#include "pipeline/radiosity_pipeline.hpp"
#include "python/release_gil.hpp"
#include "rays/ray_scene.hpp"
#include "render/raytracer.hpp"
#include "solve/solver_registry.hpp"
#include "thermal/gebhart.hpp"
#include "thermal/thermal_solver.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <tuple>

namespace py = pybind11;

namespace hemirad::python {
namespace {

using ScenePtr = std::shared_ptr<Scene>;

/// A read-only numpy array of `rows` x `columns` doubles (columns 0: one dimension) filled by `value`.
template <class T, class Value>
py::array_t<T> patchArray(const Scene& scene, int columns, Value value) {
    std::vector<py::ssize_t> shape = {py::ssize_t(scene.size())};
    if (columns > 0) shape.push_back(columns);
    py::array_t<T> array(shape);
    T* out = array.mutable_data();
    const int width = std::max(columns, 1);
    for (std::size_t i = 0; i < scene.size(); ++i)
        for (int c = 0; c < width; ++c) out[i * width + c] = value(scene.patches[i], c);
    array.attr("setflags")(py::arg("write") = false);
    return array;
}

constexpr const char* kOwnerName = "hemirad.FormFactors";

/// F's CSR arrays handed to numpy without a copy: the FormFactors lives as long as any array does.
py::tuple csrArrays(FormFactors&& F) {
    auto* owner = new FormFactors(std::move(F));
    py::capsule base(owner, kOwnerName, [](PyObject* capsule) {
        delete static_cast<FormFactors*>(PyCapsule_GetPointer(capsule, kOwnerName));
    });
    const py::ssize_t n = py::ssize_t(owner->size()), nnz = py::ssize_t(owner->nonZeros());
    // Columns are below 2^28 (the patch cap), so uint32 reads as int32, which scipy takes.
    py::array indptr(py::dtype::of<std::int64_t>(), {n + 1}, {}, owner->rowStarts().data(), base);
    py::array indices(py::dtype::of<std::int32_t>(), {nnz}, {}, owner->columns(), base);
    py::array data(py::dtype::of<double>(), {nnz}, {}, owner->values(), base);
    py::array computed(py::dtype::of<bool>(), {n}, {}, owner->computedFlags().data(), base);
    for (py::array* a : {&indptr, &indices, &data, &computed}) a->attr("setflags")(py::arg("write") = false);
    return py::make_tuple(indptr, indices, data, computed);
}

/// The largest row sum physics allows on `scene`: 1, or 1 / (1 - s_max) with mirrors.
double physicalRowSumBound(const Scene& scene) {
    double s = 0;
    for (const Patch& p : scene.patches) s = std::max(s, p.specular);
    return s > 0 ? 1.0 / (1.0 - std::min(s, 0.999999)) : 1.0;
}

/// A FormFactors from canonical CSR arrays (copied once), checked like a file: structure, values, row
/// sums against `rowSumBound`. The row pointers are checked in full (start 0, never decrease, never
/// past nnz, end at nnz) before any entry is read through them. Throws hemirad::Error naming `argument`.
FormFactors fromArrays(py::array_t<std::int64_t, py::array::c_style> indptr,
                       py::array_t<std::int32_t, py::array::c_style> indices,
                       py::array_t<double, py::array::c_style> data, std::size_t n, const std::string& argument) {
    if (indptr.ndim() != 1 || indices.ndim() != 1 || data.ndim() != 1)
        throw Error(argument + ": indptr, indices and data must be one-dimensional arrays");
    if (std::size_t(indptr.size()) != n + 1)
        throw Error(argument + ": indptr has " + std::to_string(indptr.size()) + " row pointers, expected " +
                    std::to_string(n + 1) + " for " + std::to_string(n) + " patches");
    if (data.size() != indices.size())
        throw Error(argument + ": " + std::to_string(data.size()) + " values for " + std::to_string(indices.size()) +
                    " column indices");
    const std::int64_t* rowStart = indptr.data();
    const std::int64_t nnz = std::int64_t(indices.size());
    if (rowStart[0] != 0) throw Error(argument + ": indptr starts at " + std::to_string(rowStart[0]) + ", not 0");
    for (std::size_t i = 0; i < n; ++i) {
        if (rowStart[i + 1] < rowStart[i])
            throw Error(argument + ": row pointers decrease at row " + std::to_string(i) + " (" +
                        std::to_string(rowStart[i]) + ", then " + std::to_string(rowStart[i + 1]) + ")");
        if (rowStart[i + 1] > nnz)
            throw Error(argument + ": row pointer " + std::to_string(rowStart[i + 1]) + " of row " + std::to_string(i) +
                        " lies past the " + std::to_string(nnz) + " entries");
    }
    if (rowStart[n] != nnz)
        throw Error(argument + ": indptr ends at " + std::to_string(rowStart[n]) + ", not at the " + std::to_string(nnz) +
                    " entries");
    std::vector<std::uint64_t> starts(rowStart, rowStart + n + 1);
    std::vector<std::uint32_t> columns(static_cast<std::size_t>(nnz));
    const std::int32_t* column = indices.data();  // raw pointers: array_t::data() is not free per entry
    for (std::size_t i = 0; i < n; ++i)
        for (std::int64_t k = rowStart[i]; k < rowStart[i + 1]; ++k) {
            const std::int32_t j = column[k];
            if (j < 0 || std::size_t(j) >= n || (k > rowStart[i] && j <= column[k - 1]))
                throw Error(argument + ": row " + std::to_string(i) + " has a column out of range or out of order (" +
                            std::to_string(j) + ")");
            columns[std::size_t(k)] = std::uint32_t(j);
        }
    const double* value = data.data();
    std::vector<double> values(value, value + nnz);
    return FormFactors::fromCsr(std::move(starts), std::move(columns), std::move(values), std::vector<std::uint8_t>(n, 1));
}

/// The FormFactors behind an array that csrArrays() made (numpy views of it included), or null.
const FormFactors* ownerOf(const py::array& array) {
    py::object base = array.base();
    for (int depth = 0; depth < 8 && base && !base.is_none(); ++depth) {
        if (PyCapsule_IsValid(base.ptr(), kOwnerName))
            return static_cast<const FormFactors*>(PyCapsule_GetPointer(base.ptr(), kOwnerName));
        if (!py::isinstance<py::array>(base)) return nullptr;
        base = base.cast<py::array>().base();
    }
    return nullptr;
}

/// The library's own F when the arrays passed are exactly it, for `scene`; else null. Columns and values
/// must be its own memory (read-only: csrArrays() made them so, and numpy refuses to make them writable
/// again, since their base is a capsule); the row pointers are compared by value, O(N), as scipy keeps
/// its own (int32) copy of them. Any other matrix, however much memory it shares with F, is not F.
const FormFactors* sharedFormFactors(const Scene& scene, const py::array_t<std::int64_t, py::array::c_style>& indptr,
                                     const py::array& indices, const py::array& data) {
    const FormFactors* F = ownerOf(data);
    const bool sameEntries = F && F->size() == scene.size() && F->sceneHash == scene.geometryHash() &&
                             data.data() == F->values() && std::size_t(data.size()) == F->nonZeros() &&
                             indices.data() == static_cast<const void*>(F->columns()) &&
                             std::size_t(indices.size()) == F->nonZeros();
    if (!sameEntries || indptr.ndim() != 1 || std::size_t(indptr.size()) != F->size() + 1) return nullptr;
    const std::vector<std::uint64_t>& starts = F->rowStarts();
    const std::int64_t* given = indptr.data();
    for (std::size_t i = 0; i < starts.size(); ++i)
        if (given[i] < 0 || std::uint64_t(given[i]) != starts[i]) return nullptr;
    return F;
}

/// Every F handed in from Python: the library's own when the arrays are (no copy), else a checked
/// copy with the scene's hash, provenance unknown, bounded by physics.
struct GivenFormFactors {
    const FormFactors* shared = nullptr;
    FormFactors copy;
    const FormFactors& get() const { return shared ? *shared : copy; }
};

GivenFormFactors formFactorsFor(const Scene& scene, py::array_t<std::int64_t, py::array::c_style> indptr,
                                py::array_t<std::int32_t, py::array::c_style> indices,
                                py::array_t<double, py::array::c_style> data, const std::string& argument) {
    GivenFormFactors given;
    given.shared = sharedFormFactors(scene, indptr, indices, data);
    if (given.shared) return given;
    FormFactors& F = given.copy;
    F = fromArrays(indptr, indices, data, scene.size(), argument);
    F.sceneHash = scene.geometryHash();
    F.provenance.rowSumBound = physicalRowSumBound(scene);
    validateFormFactors(F, scene.size(), argument, rowSumBound(F));
    return given;
}

py::dict statsDict(const FormFactorStats& s) {
    py::dict d;
    d["computed_rows"] = s.computedRows;
    d["nonzeros"] = s.nonZeros;
    d["row_sum_min"] = s.rowSumMin;
    d["row_sum_mean"] = s.rowSumMean;
    d["row_sum_max"] = s.rowSumMax;
    d["reciprocity_max"] = s.reciprocityMax;
    d["reciprocity_mean"] = s.reciprocityMean;
    d["self_factors"] = s.selfFactors;
    return d;
}

/// What the CLI prints about a computation, as numbers.
py::dict runDict(const FormFactorRun& run, const Scene& scene, const MethodSettings& method) {
    const BackendDescriptor& backend = findBackend(method.method);
    const RunDescription description = backend.describe(scene, method);
    const RayCounts& c = run.counts;
    const double rows = double(std::max<std::size_t>(run.rowsComputed, 1));
    py::dict d;
    d["method"] = backend.name;
    d["settings"] = description.settings;
    for (const auto& [key, value] : description.record) d[py::str(key)] = value;
    d["rows_computed"] = run.rowsComputed;
    d["rows_skipped"] = run.rowsSkipped;
    d[py::str(backend.workUnit)] = c.rays;
    d[py::str(backend.workUnit + "_per_s")] = run.computeSeconds > 0 ? double(c.rays) / run.computeSeconds : 0.0;
    d["lost_fraction"] = c.lostFraction();  // area-weighted over the computed rows
    d["misses"] = c.misses;
    d["back_faces"] = c.backfaces;
    d["mirror_bounces"] = c.bounces;
    d["cutoff_fraction"] = c.cutoffWeight / rows;
    d["rescaled_rows"] = c.rescaledRows;
    d["shadow_terms"] = c.shadowTerms;
    d["shadow_probes"] = c.shadowProbes;
    d["cut_pairs"] = c.cutPairs;
    d["cut_whole_pairs"] = c.cutWholePairs;
    py::dict seconds;
    seconds["prepare"] = run.prepareSeconds;
    seconds["compute"] = run.computeSeconds;
    seconds["assemble"] = run.assembleSeconds;
    seconds["statistics"] = run.statsSeconds;
    d["seconds"] = seconds;
    return d;
}

py::dict provenanceDict(const FormFactors& F) {
    py::dict d;
    d["method"] = F.provenance.method;
    d["estimator"] = F.provenance.estimator;
    d["row_sum_bound"] = F.provenance.rowSumBound;
    d["scene_hash"] = F.provenance.sceneHashKnown ? hexHash(F.sceneHash) : std::string();
    d["parameters"] = F.parameters;
    return d;
}

py::tuple formFactors(const ScenePtr& scene, const std::string& method, const std::map<std::string, std::string>& options,
                      std::uint32_t maxDepth, int threads, bool allRows, bool enforceReciprocity, bool normalizeRows,
                      double dropBelow, bool memoryCheck, const py::object& progress) {
    if (!(dropBelow >= 0.0 && dropBelow <= 0.5))
        throw Error("drop_below: expected 0 (keep every pair) or a threshold in (0, 0.5], got " + std::to_string(dropBelow));
    FormFactorPolicy policy;
    policy.backend = defaultSettings(method);
    for (const auto& [flag, value] : options) setBackendOption(policy.backend, flag, value);
    policy.backend.common.maxDepth = maxDepth;
    policy.backend.common.threads = threads;
    policy.allRows = allRows;
    policy.enforceReciprocity = enforceReciprocity;
    policy.normalizeRows = normalizeRows;
    policy.dropBelow = dropBelow;
    policy.memoryCheck = memoryCheck;
    policy.statistics = true;
    WorkerLink link;
    py::dict report;
    py::list messages;
    std::optional<FormFactorRun> computed;  // its F moved out: counts and times only
    PipelineEvents events;
    events.cancel = link.cancelFlag();
    events.progress = [&link](const std::string&, double, const std::string&) { return link.progress(); };
    events.formFactorsComputed = [&](const FormFactorRun& run, const Scene&, const MethodSettings&) {
        computed.emplace();
        computed->counts = run.counts;
        computed->prepareSeconds = run.prepareSeconds;
        computed->computeSeconds = run.computeSeconds;
        computed->assembleSeconds = run.assembleSeconds;
        computed->statsSeconds = run.statsSeconds;
        computed->rowsComputed = run.rowsComputed;
        computed->rowsSkipped = run.rowsSkipped;
    };
    std::vector<std::string> lines;
    events.message = [&lines](const std::string& text) { lines.push_back(text); };
    const RadiosityPipeline pipeline(policy, std::move(events));
    FormFactorUpdate update =
        link.run<FormFactorUpdate>([&] { return pipeline.updateFormFactors(*scene, FormFactors{}); }, progress);
    if (computed) report = runDict(*computed, *scene, policy.backend);
    if (update.stats) report.attr("update")(statsDict(*update.stats));
    report["provenance"] = provenanceDict(update.F);
    report["memory_bytes"] = update.F.memoryBytes();
    for (const std::string& line : lines) messages.append(line);
    report["messages"] = messages;
    return py::make_tuple(csrArrays(std::move(update.F)), report);
}

py::tuple solve(const ScenePtr& scene, py::array_t<std::int64_t, py::array::c_style> indptr,
                py::array_t<std::int32_t, py::array::c_style> indices, py::array_t<double, py::array::c_style> data,
                const std::string& solverName, double tolerance, int maxIterations, bool allowUnconverged,
                const py::object& progress) {
    const GivenFormFactors given = formFactorsFor(*scene, indptr, indices, data, "F");
    const FormFactors& F = given.get();
    SolverOptions options;
    options.solver = solverName;
    options.tolerance = tolerance;
    options.maxIterations = maxIterations;
    options.allowUnconverged = allowUnconverged;
    WorkerLink link;
    const auto started = std::chrono::steady_clock::now();
    options.progress = [&link, &options, started](int sweep, const std::vector<Rgb>&) {
        if (link.cancelled()) throw Error("solve: cancelled");
        link.progress()(std::size_t(sweep), std::size_t(options.maxIterations),
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    };
    const RadiosityPipeline pipeline(FormFactorPolicy{}, PipelineEvents{});
    const Radiosity result = link.run<Radiosity>([&] { return pipeline.solve(*scene, F, options); }, progress);
    py::array_t<double> B({py::ssize_t(scene->size()), py::ssize_t(3)});
    for (std::size_t i = 0; i < scene->size(); ++i)
        for (int c = 0; c < 3; ++c) B.mutable_at(i, c) = result.B[i][c];
    py::list reports;
    for (const SolveReport& r : result.reports) {
        py::dict d;
        d["solver"] = r.solver;
        d["channels"] = r.channels;
        d["converged"] = r.converged;
        d["iterations"] = r.iterations;
        d["residual"] = r.residual;
        d["residual_original"] = r.residualOriginal;
        d["seconds"] = r.seconds;
        d["note"] = r.note;
        reports.append(d);
    }
    py::dict report;
    report["channels"] = reports;
    return py::make_tuple(B, report);
}

py::tuple readFormFactors(const std::string& path, const py::object& scene) {
    const ScenePtr given = scene.is_none() ? nullptr : scene.cast<ScenePtr>();
    FormFactors F = [&] {
        py::gil_scoped_release release;
        return loadFormFactors(path, given ? given->size() : 0);
    }();
    if (given) checkFormFactorsMatch(F, given->geometryHash(), given->size(), path);
    py::dict info = provenanceDict(F);
    return py::make_tuple(csrArrays(std::move(F)), info);
}

void writeFormFactors(const std::string& path, const ScenePtr& scene, py::array_t<std::int64_t, py::array::c_style> indptr,
                      py::array_t<std::int32_t, py::array::c_style> indices, py::array_t<double, py::array::c_style> data,
                      const py::object& provenance) {
    GivenFormFactors given = formFactorsFor(*scene, indptr, indices, data, "F");
    if (given.shared) {  // the library's own F: its file says how it was made
        py::gil_scoped_release release;
        saveFormFactors(*given.shared, path);
        return;
    }
    FormFactors& F = given.copy;
    if (!provenance.is_none()) {  // as form_factors() reported it: the file says how F was made
        const py::dict d = provenance.cast<py::dict>();
        F.provenance.method = d["method"].cast<std::string>();
        F.provenance.estimator = d["estimator"].cast<std::string>();
        F.provenance.rowSumBound = std::max(1.0, d["row_sum_bound"].cast<double>());
        F.parameters = d["parameters"].cast<std::map<std::string, std::string>>();
        validateFormFactors(F, scene->size(), "F", rowSumBound(F));
    } else {
        F.parameters["written_by"] = "the hemirad Python module (F given as a matrix: how it was made is unknown)";
    }
    py::gil_scoped_release release;
    saveFormFactors(F, path);
}

py::dict render(const ScenePtr& scene, py::array_t<double, py::array::c_style | py::array::forcecast> B,
                const std::string& path, const std::optional<std::vector<double>>& camera, int width, int height,
                int samplesPerPixel, double exposure, bool flat, double crease, int threads) {
    const std::size_t n = scene->size();
    if (B.ndim() != 2 || std::size_t(B.shape(0)) != n || B.shape(1) != 3)
        throw py::value_error("B: expected shape (" + std::to_string(n) + ", 3), got another");
    std::vector<Rgb> radiosity(n);
    for (std::size_t i = 0; i < n; ++i) radiosity[i] = Rgb(B.at(i, 0), B.at(i, 1), B.at(i, 2));
    requireFinite(radiosity, "B");
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.samplesPerPixel = samplesPerPixel;
    options.flat = flat;
    options.camera = defaultCamera(*scene);
    if (camera) {
        const std::vector<double>& c = *camera;
        options.camera.eye = Vec3(c[0], c[1], c[2]);
        options.camera.target = Vec3(c[3], c[4], c[5]);
        options.camera.fovY = c[6];
        checkCamera(options.camera);  // as the CLI and the OBJ loader check theirs
    }
    double scale = 0;
    {
        py::gil_scoped_release release;
        const std::vector<Rgb> corner = cornerRadiosity(*scene, radiosity, crease);
        const RayScene rays(*scene, threads);
        const RadianceImage image = renderRadiance(*scene, rays, radiosity, corner, options);
        writePng(path, image.width, image.height, toneMap(image, exposure, scale));
    }
    py::dict report;
    report["exposure"] = scale;
    report["size"] = py::make_tuple(width, height);
    return report;
}

/// ids (int64) and values (k x 3 or k) already checked by the Python side: shapes and ranges.
void setPatchValues(Scene& scene, const std::string& what, py::array_t<std::int64_t, py::array::c_style> ids,
                    py::array_t<double, py::array::c_style> values) {
    const std::size_t k = std::size_t(ids.size());
    const int width = what == "specular" ? 1 : 3;
    if (std::size_t(values.size()) != k * std::size_t(width)) throw py::value_error(what + ": one value per id expected");
    // Checked in full before anything changes: a refused edit leaves the scene as it was.
    std::vector<Patch> edited;
    for (std::size_t m = 0; m < k; ++m) {
        const std::int64_t id = ids.data()[m];
        if (id < 0 || std::size_t(id) >= scene.size())
            throw py::index_error("ids: patch " + std::to_string(id) + " out of range [0, " + std::to_string(scene.size()) + ")");
        Patch p = scene.patches[std::size_t(id)];
        const double* v = values.data() + m * std::size_t(width);
        if (what == "emission") p.emission = Rgb(v[0], v[1], v[2]);
        else if (what == "rho") p.rho = Rgb(v[0], v[1], v[2]);
        else p.specular = v[0];
        if ((p.rho + Rgb::Constant(p.specular) > 1.0 + 1e-12).any())
            throw py::value_error(what + ": patch " + std::to_string(id) +
                                  " would reflect more than it receives (rho + specular > 1 in a channel)");
        edited.push_back(p);
    }
    for (std::size_t m = 0; m < k; ++m) scene.patches[std::size_t(ids.data()[m])] = edited[m];
}

/// The thermal model from per-patch arrays: exactly one of temperature (K) and flux (W/m^2) finite per
/// patch (NaN: not given); specular must equal the scene's (F depends on it).
thermal::ThermalModel thermalModel(const Scene& scene, py::array_t<double, py::array::c_style> emissivity,
                                   py::array_t<double, py::array::c_style> specular,
                                   py::array_t<double, py::array::c_style> temperature,
                                   py::array_t<double, py::array::c_style> flux, py::object environment) {
    const std::size_t n = scene.size();
    for (const auto& [name, a] : {std::pair<const char*, py::array_t<double, py::array::c_style>*>{"emissivity", &emissivity},
                                  {"specular", &specular}, {"temperature", &temperature}, {"flux", &flux}})
        if (a->ndim() != 1 || std::size_t(a->size()) != n)
            throw Error(std::string(name) + ": expected one value per patch (" + std::to_string(n) + "), got shape of " +
                        std::to_string(a->size()) + " values");
    thermal::ThermalModel model;
    model.metresPerUnit = scene.unit.empty() ? 1.0 : metresPerUnit(scene.unit);
    model.surface.resize(n);
    model.condition.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        model.surface[i] = {emissivity.at(i), specular.at(i)};
        const bool hasT = !std::isnan(temperature.at(i)), hasQ = !std::isnan(flux.at(i));
        if (hasT == hasQ)
            throw Error("patch " + std::to_string(i) + ": give exactly one of temperature and flux (the other NaN); got " +
                        (hasT ? "both" : "neither"));
        model.condition[i] = hasT ? thermal::Condition{thermal::Condition::Kind::Temperature, temperature.at(i), 0}
                                  : thermal::Condition{thermal::Condition::Kind::Flux, flux.at(i), 0};
    }
    if (!environment.is_none()) model.environment = environment.cast<double>();
    return model;
}

py::array_t<double> numpyVector(const std::vector<double>& v) {
    py::array_t<double> a(py::ssize_t(v.size()));
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

py::dict thermalSolve(const ScenePtr& scene, py::array_t<std::int64_t, py::array::c_style> indptr,
                      py::array_t<std::int32_t, py::array::c_style> indices, py::array_t<double, py::array::c_style> data,
                      py::array_t<double, py::array::c_style> emissivity, py::array_t<double, py::array::c_style> specular,
                      py::array_t<double, py::array::c_style> temperature, py::array_t<double, py::array::c_style> flux,
                      py::object environment, py::array_t<double, py::array::c_style> absorbed,
                      std::vector<double> bandLimits, py::array_t<double, py::array::c_style> bandEmissivity,
                      py::array_t<double, py::array::c_style> bandSpecular, const py::list& bandF,
                      const std::vector<std::tuple<std::vector<std::int64_t>, std::vector<double>, std::vector<double>>>& curves,
                      const std::string& solverName, double tolerance) {
    const GivenFormFactors given = formFactorsFor(*scene, indptr, indices, data, "F");
    thermal::ThermalModel model = thermalModel(*scene, emissivity, specular, temperature, flux, environment);
    const std::size_t n = scene->size();
    if (absorbed.size() > 0) {
        if (absorbed.ndim() != 1 || std::size_t(absorbed.size()) != n) throw Error("absorbed: expected one value per patch");
        model.absorbedExternal.assign(absorbed.data(), absorbed.data() + n);
    }
    if (!bandLimits.empty()) {
        if (bandEmissivity.ndim() != 2 || std::size_t(bandEmissivity.shape(0)) != bandLimits.size() + 1 ||
            std::size_t(bandEmissivity.shape(1)) != n)
            throw Error("band_emissivity: expected shape (" + std::to_string(bandLimits.size() + 1) + ", " + std::to_string(n) +
                        ") for " + std::to_string(bandLimits.size()) + " band limits");
        model.bandLimitsUm = bandLimits;
        model.bandEmissivity.assign(bandLimits.size() + 1, std::vector<double>(n));
        for (std::size_t k = 0; k <= bandLimits.size(); ++k)
            for (std::size_t i = 0; i < n; ++i) model.bandEmissivity[k][i] = bandEmissivity.at(k, i);
    }
    // Per-band specular reflectances, each band on its own F where given (None: F).
    std::vector<GivenFormFactors> ownF;
    std::vector<const FormFactors*> bandFormFactors;
    if (bandSpecular.size() > 0) {
        const std::size_t K = bandLimits.size() + 1;
        if (bandLimits.empty()) throw Error("band_specular: needs band_limits_um and band_emissivity");
        if (bandSpecular.ndim() != 2 || std::size_t(bandSpecular.shape(0)) != K || std::size_t(bandSpecular.shape(1)) != n)
            throw Error("band_specular: expected shape (" + std::to_string(K) + ", " + std::to_string(n) + ")");
        model.bandSpecular.assign(K, std::vector<double>(n));
        for (std::size_t k = 0; k < K; ++k)
            for (std::size_t i = 0; i < n; ++i) model.bandSpecular[k][i] = bandSpecular.at(k, i);
        if (!bandF.empty() && bandF.size() != K)
            throw Error("band_F: expected " + std::to_string(K) + " matrices (or None), got " + std::to_string(bandF.size()));
        ownF.reserve(bandF.size());
        for (std::size_t k = 0; k < bandF.size(); ++k) {
            if (bandF[k].is_none()) {
                bandFormFactors.push_back(nullptr);
                continue;
            }
            // Checked against the bound of the band's own mirrors.
            Scene bandScene = *scene;
            for (std::size_t i = 0; i < n; ++i) bandScene.patches[i].specular = model.bandSpecular[k][i];
            const auto arrays = bandF[k].cast<py::tuple>();
            ownF.push_back(formFactorsFor(bandScene, arrays[0].cast<py::array_t<std::int64_t, py::array::c_style>>(),
                                          arrays[1].cast<py::array_t<std::int32_t, py::array::c_style>>(),
                                          arrays[2].cast<py::array_t<double, py::array::c_style>>(),
                                          "band_F[" + std::to_string(k) + "]"));
            bandFormFactors.push_back(&ownF.back().get());
        }
    } else if (!bandF.empty()) {
        throw Error("band_F: goes with band_specular");
    }
    if (!curves.empty()) {
        // Emissivity against temperature: each curve on its patches (the rest keep `emissivity`).
        model.curveOf.assign(n, -1);
        for (const auto& [patches, temperatures, values] : curves) {
            const auto c = std::int32_t(model.emissivityCurves.size());
            model.emissivityCurves.push_back({temperatures, values});
            for (const std::int64_t p : patches) {
                if (p < 0 || std::size_t(p) >= n)
                    throw py::value_error("emissivity_curves: patch " + std::to_string(p) + " is not in the scene");
                if (model.curveOf[std::size_t(p)] >= 0)
                    throw py::value_error("emissivity_curves: patch " + std::to_string(p) + " is given two curves");
                model.curveOf[std::size_t(p)] = c;
            }
        }
    }
    SolverOptions options;
    options.solver = solverName;
    options.tolerance = tolerance;
    thermal::ThermalSolution sol;
    {
        py::gil_scoped_release release;
        sol = thermal::solveThermal(*scene, given.get(), model, options, bandFormFactors);
    }
    py::dict out;
    out["T"] = numpyVector(sol.T);
    out["J"] = numpyVector(sol.J);
    out["H"] = numpyVector(sol.H);
    out["q"] = numpyVector(sol.q);
    out["Q"] = numpyVector(sol.Q);
    out["environment_power"] = sol.environmentPower;
    out["balance"] = sol.balance;
    out["solver"] = sol.report.solver;
    out["residual"] = sol.report.residualOriginal;
    return out;
}

py::dict skyView(const ScenePtr& scene, const std::string& method, const std::map<std::string, std::string>& options,
                 std::uint32_t maxDepth, int threads) {
    MethodSettings settings = defaultSettings(method);
    for (const auto& [flag, value] : options) setBackendOption(settings, flag, value);
    settings.common.maxDepth = maxDepth;
    settings.common.threads = threads;
    SkyView sky;
    {
        py::gil_scoped_release release;
        sky = skyViewFactors(*scene, settings);
    }
    py::dict out;
    out["sky_view_factor"] = numpyVector(sky.total());
    out["direct"] = numpyVector(sky.direct);
    out["through_mirrors"] = numpyVector(sky.mirrored.empty() ? std::vector<double>(scene->size(), 0.0) : sky.mirrored);
    out["method"] = sky.method;
    return out;
}

/// Sensors from (S, 3) positions and normals (`what` names the caller in errors).
Sensors sensorsOf(py::array_t<double, py::array::c_style | py::array::forcecast> positions,
                  py::array_t<double, py::array::c_style | py::array::forcecast> normals, const std::string& what) {
    if (positions.ndim() != 2 || positions.shape(1) != 3 || normals.ndim() != 2 || normals.shape(1) != 3 ||
        normals.shape(0) != positions.shape(0))
        throw py::value_error(what + ": positions and normals must be arrays of shape (S, 3), the same S");
    Sensors sensors;
    const double* x = positions.data();
    const double* n = normals.data();
    for (py::ssize_t s = 0; s < positions.shape(0); ++s) {
        const Vec3 p(x[3 * s], x[3 * s + 1], x[3 * s + 2]), d(n[3 * s], n[3 * s + 1], n[3 * s + 2]);
        if (!p.allFinite()) throw py::value_error(what + ": position " + std::to_string(s) + " is not finite");
        if (!d.allFinite() || !(d.norm() > 0.0)) throw py::value_error(what + ": normal " + std::to_string(s) + " is not a direction");
        sensors.position.push_back(p);
        sensors.normal.push_back(d.normalized());
        sensors.name.push_back(std::to_string(s));
    }
    return sensors;
}

/// Sensors from (S, 3) positions and normals: their factors (CSR arrays for scipy) and sky view factors.
py::dict sensorFactorsOf(const ScenePtr& scene, py::array_t<double, py::array::c_style | py::array::forcecast> positions,
                         py::array_t<double, py::array::c_style | py::array::forcecast> normals, int threads,
                         const std::string& estimator, long long rays, int maxDepth) {
    const Sensors sensors = sensorsOf(positions, normals, "sensor_factors");
    SensorOptions options;
    if (estimator == "auto" || estimator == "exact" || estimator == "rays")
        options.estimator = parseSensorEstimator(estimator);
    else
        throw py::value_error("sensor_factors: estimator '" + estimator + "' is not one of auto, exact, rays");
    if (rays < 1 || rays > (1 << 24))
        throw py::value_error("sensor_factors: rays must be 1 .. 16777216, not " + std::to_string(rays));
    options.rays = std::uint32_t(rays);
    options.threads = threads;
    if (maxDepth < 0 || maxDepth > 1000) throw py::value_error("sensor_factors: max_depth must be 0 .. 1000, not " + std::to_string(maxDepth));
    options.limits.maxDepth = std::uint32_t(maxDepth);
    SensorFactors f;
    std::string why;
    {
        py::gil_scoped_release release;
        f = sensorFactors(*scene, sensors, options, &why);
    }
    py::array_t<std::int64_t> indptr(py::ssize_t(f.rowStart.size()));
    std::copy(f.rowStart.begin(), f.rowStart.end(), indptr.mutable_data());
    py::array_t<std::int32_t> indices(py::ssize_t(f.columns.size()));
    std::copy(f.columns.begin(), f.columns.end(), indices.mutable_data());
    py::dict out;
    out["indptr"] = indptr;
    out["indices"] = indices;
    out["data"] = numpyVector(f.values);
    out["sky_view_factor"] = numpyVector(f.skyView);
    // The sky seen in mirrors (zeros where the scene has none, or they were not followed: `mirrors` says).
    out["sky_view_mirrored"] = numpyVector(f.skyMirrored.empty() ? std::vector<double>(f.skyView.size(), 0.0) : f.skyMirrored);
    out["mirrors"] = f.mirrors;
    out["patches"] = f.patches;
    out["estimator"] = chooseSensorEstimator(options, sensors.size(), scene->size(), why) == SensorEstimator::Rays ? "rays" : "exact";
    out["why"] = why;
    return out;
}

Vec3 vectorOf(py::array_t<double, py::array::c_style | py::array::forcecast> v, const std::string& name) {
    if (v.ndim() != 1 || v.shape(0) != 3) throw py::value_error(name + ": expected 3 values");
    const Vec3 x(v.data()[0], v.data()[1], v.data()[2]);
    if (!x.allFinite() || !(x.norm() > 0.0)) throw py::value_error(name + ": expected a finite non-zero vector");
    return x;
}

py::dict solarPositionOf(const std::string& time, double latitude, double longitude) {
    const SolarPosition p = solarPosition(time, latitude, longitude);
    py::dict out;
    out["elevation"] = p.elevation;
    out["azimuth"] = p.azimuth;
    return out;
}

py::array_t<double> sunDirectionOf(double elevation, double azimuth, py::array_t<double, py::array::c_style | py::array::forcecast> up,
                                   py::array_t<double, py::array::c_style | py::array::forcecast> north) {
    SolarPosition p;
    p.elevation = elevation;
    p.azimuth = azimuth;
    const Vec3 d = sunDirection(p, vectorOf(up, "up"), vectorOf(north, "north"));
    return numpyVector({d.x(), d.y(), d.z()});
}

/// The suns of `toSun`: one direction (3 values) or k rows of 3, each a finite non-zero vector.
std::vector<Vec3> sunsOf(const py::array_t<double, py::array::c_style | py::array::forcecast>& toSun) {
    if (toSun.ndim() != 2) return {vectorOf(toSun, "to_sun")};
    if (toSun.shape(1) != 3) throw py::value_error("to_sun: expected 3 values per row (k x 3)");
    std::vector<Vec3> directions(std::size_t(toSun.shape(0)));
    for (std::size_t r = 0; r < directions.size(); ++r) {
        const double* v = toSun.data() + 3 * r;
        directions[r] = Vec3(v[0], v[1], v[2]);
        if (!directions[r].allFinite() || !(directions[r].norm() > 0.0))
            throw py::value_error("to_sun: row " + std::to_string(r) + " is not a finite non-zero vector");
    }
    return directions;
}

py::array_t<double> sunlitOf(const ScenePtr& scene, py::array_t<double, py::array::c_style | py::array::forcecast> toSun) {
    if (toSun.ndim() != 2) {
        const Vec3 d = vectorOf(toSun, "to_sun");
        std::vector<double> f;
        {
            py::gil_scoped_release release;
            f = sunlitFractions(*scene, d);
        }
        return numpyVector(f);
    }
    // Many suns (k x 3): one shadow set-up for all of them, a row of fractions each.
    const std::vector<Vec3> directions = sunsOf(toSun);
    const std::size_t k = directions.size(), n = scene->size();
    py::array_t<double> out({py::ssize_t(k), py::ssize_t(n)});
    double* p = out.mutable_data();
    {
        py::gil_scoped_release release;
        const BeamShadows shadows(*scene);
        for (std::size_t r = 0; r < k; ++r) {
            const std::vector<double> f = shadows.sunlitFractions(directions[r]);
            std::copy(f.begin(), f.end(), p + r * n);
        }
    }
    return out;
}

py::dict irradianceOf(const ScenePtr& scene, py::array_t<std::int64_t, py::array::c_style> indptr,
                      py::array_t<std::int32_t, py::array::c_style> indices, py::array_t<double, py::array::c_style> data,
                      py::array_t<double, py::array::c_style | py::array::forcecast> directSun,
                      py::array_t<double, py::array::c_style | py::array::forcecast> skyView, double dhi,
                      py::array_t<double, py::array::c_style | py::array::forcecast> reflected,
                      py::array_t<double, py::array::c_style | py::array::forcecast> modelSky,
                      py::array_t<double, py::array::c_style | py::array::forcecast> modelSkyReflected, double metres,
                      const std::string& solverName, double tolerance) {
    const GivenFormFactors given = formFactorsFor(*scene, indptr, indices, data, "F");
    const std::size_t n = scene->size();
    const auto perPatch = [n](const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
        return a.ndim() == 1 && std::size_t(a.size()) == n;
    };
    if (!perPatch(directSun) || (modelSky.size() == 0 && !perPatch(skyView)) || (modelSky.size() > 0 && !perPatch(modelSky)) ||
        (modelSkyReflected.size() > 0 && !perPatch(modelSkyReflected)))
        throw py::value_error("irradiance: direct_sun and sky_view (or a sky model's sky) need one value per patch");
    IrradianceInputs in;
    in.directSun.assign(directSun.data(), directSun.data() + n);
    if (modelSky.size() > 0) {
        in.directSky.assign(modelSky.data(), modelSky.data() + n);
        if (modelSkyReflected.size() > 0) in.reflectedSky.assign(modelSkyReflected.data(), modelSkyReflected.data() + n);
    } else {
        in.skyView.assign(skyView.data(), skyView.data() + n);
    }
    in.dhi = dhi;
    if (reflected.size() > 0) {
        if (reflected.ndim() != 1 || std::size_t(reflected.size()) != n) throw py::value_error("irradiance: reflected sun needs one value per patch");
        in.reflectedSun.assign(reflected.data(), reflected.data() + n);
    }
    SolverOptions options;
    options.solver = solverName;
    options.tolerance = tolerance;
    if (!(metres > 0.0)) metres = scene->unit.empty() ? 1.0 : metresPerUnit(scene->unit);  // the scene's unit, else metres
    IrradianceResult r;
    {
        py::gil_scoped_release release;
        r = solarIrradiance(*scene, given.get(), in, metres, options);
    }
    py::dict out;
    out["direct_sun"] = numpyVector(r.directSun);
    out["direct_sky"] = numpyVector(r.directSky);
    out["reflected"] = numpyVector(r.reflected);
    out["total"] = numpyVector(r.total);
    out["absorbed"] = numpyVector(r.absorbed);
    out["radiosity"] = numpyVector(r.radiosity);
    out["reflected_sun"] = numpyVector(r.reflectedSun);
    out["reflected_sky"] = numpyVector(r.reflectedSky);
    out["incident_power"] = r.incidentPower;
    out["absorbed_power"] = r.absorbedPower;
    out["escaped_power"] = r.escapedPower;
    out["balance"] = r.balance;
    out["solver"] = r.report.solver;
    return out;
}

/// A patches x cells matrix as a C-ordered NumPy array.
py::array_t<double> numpyMatrix(const Eigen::MatrixXd& m) {
    py::array_t<double> out({py::ssize_t(m.rows()), py::ssize_t(m.cols())});
    double* p = out.mutable_data();
    for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index k = 0; k < m.cols(); ++k) *p++ = m(i, k);
    return out;
}

/// Sensors' daylight coefficients (sensors x cells) for the cells skyCoefficients lays.
py::dict sensorSkyCoefficientsOf(const ScenePtr& scene, py::array_t<double, py::array::c_style | py::array::forcecast> positions,
                                 py::array_t<double, py::array::c_style | py::array::forcecast> normals, int subdivision, int samples,
                                 py::array_t<double, py::array::c_style | py::array::forcecast> up,
                                 py::array_t<double, py::array::c_style | py::array::forcecast> north) {
    const Sensors sensors = sensorsOf(positions, normals, "sensor_sky_coefficients");
    const Vec3 u = vectorOf(up, "up"), no = vectorOf(north, "north");
    SensorSkyCoefficients c;
    {
        py::gil_scoped_release release;
        c = sensorSkyCoefficients(*scene, sensors, skyGrid(subdivision), samples, u, no);
    }
    py::dict out;
    out["direct"] = numpyMatrix(c.direct);
    out["mirrored"] = c.mirrored.size() > 0 ? py::object(numpyMatrix(c.mirrored)) : py::object(py::none());
    return out;
}

py::dict skyCoefficientsOf(const ScenePtr& scene, int subdivision, int samples, py::array_t<double, py::array::c_style | py::array::forcecast> up,
                           py::array_t<double, py::array::c_style | py::array::forcecast> north) {
    const Vec3 u = vectorOf(up, "up"), no = vectorOf(north, "north");
    SkyCoefficients c;
    {
        py::gil_scoped_release release;
        c = skyCoefficients(*scene, subdivision, samples, u, no);
    }
    std::vector<double> low, high, west, east;
    py::array_t<double> directions({py::ssize_t(c.grid.size()), py::ssize_t(3)});
    constexpr double kDegrees = 180.0 / kPi;
    for (std::size_t k = 0; k < c.grid.size(); ++k) {
        const SkyGrid::Cell& cell = c.grid.cells[k];
        low.push_back(cell.altitudeLow * kDegrees);
        high.push_back(cell.altitudeHigh * kDegrees);
        west.push_back(cell.azimuthLow * kDegrees);
        east.push_back(cell.azimuthHigh * kDegrees);
        const Vec3 d = skyToScene(k + 1 == c.grid.size() ? Vec3(0, 0, 1)
                                                         : skyDirection((cell.altitudeLow + cell.altitudeHigh) / 2, (cell.azimuthLow + cell.azimuthHigh) / 2),
                                  u, no);
        for (int a = 0; a < 3; ++a) directions.mutable_data()[3 * k + std::size_t(a)] = d[a];
    }
    py::dict cells;
    cells["altitude_low"] = numpyVector(low);
    cells["altitude_high"] = numpyVector(high);
    cells["azimuth_low"] = numpyVector(west);
    cells["azimuth_high"] = numpyVector(east);
    cells["direction"] = directions;
    std::vector<double> omega;
    for (const SkyGrid::Cell& cell : c.grid.cells) omega.push_back(cell.solidAngle());
    cells["solid_angle"] = numpyVector(omega);
    cells["horizontal"] = numpyVector(c.horizontal);
    py::dict out;
    out["direct"] = numpyMatrix(c.direct);
    out["mirrored"] = c.mirrored.size() > 0 ? py::object(numpyMatrix(c.mirrored)) : py::object(py::none());
    out["cells"] = cells;
    out["subdivision"] = subdivision;
    out["samples"] = samples;
    return out;
}

py::array_t<double> skyRadianceOf(const std::string& model, py::array_t<double, py::array::c_style | py::array::forcecast> toSun,
                                  double dni, double dhi, int subdivision, int samples, int dayOfYear,
                                  py::array_t<double, py::array::c_style | py::array::forcecast> up,
                                  py::array_t<double, py::array::c_style | py::array::forcecast> north) {
    if (dayOfYear < 0 || dayOfYear > 366) throw py::value_error("sky_radiance: day_of_year must be 1..366 (or 0: the mean distance)");
    SkyConditions c;
    c.toSun = sceneToSky(vectorOf(toSun, "to_sun"), vectorOf(up, "up"), vectorOf(north, "north"));
    c.dni = dni;
    c.dhi = dhi;
    c.dayOfYear = dayOfYear;
    return numpyVector(skyRadiance(skyGrid(subdivision), samples, parseSkyModel(model), c));
}

py::dict reflectedSunDict(const ReflectedSun& r) {
    py::array_t<std::int64_t> mirror(py::ssize_t(r.spots.size())), receiver(py::ssize_t(r.spots.size()));
    std::vector<double> mean, peak, area;
    for (std::size_t k = 0; k < r.spots.size(); ++k) {
        mirror.mutable_data()[k] = r.spots[k].mirror;
        receiver.mutable_data()[k] = r.spots[k].receiver;
        mean.push_back(r.spots[k].irradiance);
        peak.push_back(r.spots[k].peak);
        area.push_back(r.spots[k].litArea);
    }
    py::dict spots;
    spots["mirror"] = mirror;
    spots["receiver"] = receiver;
    spots["irradiance"] = numpyVector(mean);
    spots["peak"] = numpyVector(peak);
    spots["lit_area"] = numpyVector(area);
    py::dict out;
    out["irradiance"] = numpyVector(r.irradiance);
    out["spots"] = spots;
    return out;
}

/// One sun: a dict; k suns (k x 3, with k DNIs or one): a list of k dicts from one set-up of the
/// shadow trees.
py::object reflectedSunOf(const ScenePtr& scene, py::array_t<double, py::array::c_style | py::array::forcecast> toSun,
                          std::vector<double> dni) {
    const std::vector<Vec3> suns = sunsOf(toSun);
    if (dni.size() == 1) dni.assign(suns.size(), dni.front());
    if (dni.size() != suns.size())
        throw py::value_error("dni: one value, or one per sun (" + std::to_string(suns.size()) + "), not " + std::to_string(dni.size()));
    for (std::size_t r = 0; r < dni.size(); ++r)
        if (!std::isfinite(dni[r]) || dni[r] < 0.0)
            throw py::value_error("dni: " + std::to_string(dni[r]) + " (sun " + std::to_string(r) +
                                  ") must be a finite direct-normal irradiance >= 0 (W/m^2)");
    std::vector<ReflectedSun> results(suns.size());
    {
        py::gil_scoped_release release;
        const BeamShadows shadows(*scene);
        for (std::size_t r = 0; r < suns.size(); ++r) results[r] = reflectedSun(shadows, suns[r], dni[r]);
    }
    if (toSun.ndim() != 2) return reflectedSunDict(results.front());
    py::list out;
    for (const ReflectedSun& r : results) out.append(reflectedSunDict(r));
    return out;
}

/// A grid over an object's faces: (positions, normals, names).
py::tuple sensorGridOf(const ScenePtr& scene, const std::string& object, double spacing, double height) {
    const Sensors g = sensorGrid(*scene, object, spacing, height);
    py::array_t<double> positions({py::ssize_t(g.size()), py::ssize_t(3)}), normals({py::ssize_t(g.size()), py::ssize_t(3)});
    for (std::size_t s = 0; s < g.size(); ++s)
        for (int a = 0; a < 3; ++a) {
            positions.mutable_data()[3 * s + std::size_t(a)] = g.position[s][a];
            normals.mutable_data()[3 * s + std::size_t(a)] = g.normal[s][a];
        }
    return py::make_tuple(positions, normals, g.name);
}

py::dict conductors(const ScenePtr& scene, py::array_t<std::int64_t, py::array::c_style> indptr,
                    py::array_t<std::int32_t, py::array::c_style> indices, py::array_t<double, py::array::c_style> data,
                    py::array_t<double, py::array::c_style> emissivity, py::array_t<double, py::array::c_style> specular,
                    const std::string& lump, double threshold, const std::string& method) {
    const GivenFormFactors given = formFactorsFor(*scene, indptr, indices, data, "F");
    const std::size_t n = scene->size();
    py::array_t<double> T{py::ssize_t(n)}, q{py::ssize_t(n)};  // conductors depend on no condition
    std::fill(T.mutable_data(), T.mutable_data() + n, 300.0);
    std::fill(q.mutable_data(), q.mutable_data() + n, std::nan(""));
    const thermal::ThermalModel model = thermalModel(*scene, emissivity, specular, T, q, py::none());
    if (lump != "patches" && lump != "objects") throw Error("lump: expected 'patches' or 'objects', got '" + lump + "'");
    thermal::GebhartOptions g;
    g.lumping = lump == "patches" ? thermal::Lumping::Patches : thermal::Lumping::Objects;
    g.threshold = threshold;
    if (method != "auto" && method != "columns" && method != "dense")
        throw Error("method: expected 'auto', 'columns' or 'dense', got '" + method + "'");
    g.method = method == "dense" ? thermal::GebhartMethod::Dense
               : method == "columns" ? thermal::GebhartMethod::Columns
                                     : thermal::GebhartMethod::Auto;
    thermal::Conductors c;
    {
        py::gil_scoped_release release;
        c = thermal::computeConductors(*scene, given.get(), model, g, SolverOptions{});
    }
    py::array_t<std::int64_t> a(py::ssize_t(c.couplings.size())), b(py::ssize_t(c.couplings.size()));
    py::array_t<double> gr(py::ssize_t(c.couplings.size()));
    for (std::size_t k = 0; k < c.couplings.size(); ++k) {
        a.mutable_at(k) = c.couplings[k].a;
        b.mutable_at(k) = c.couplings[k].b;
        gr.mutable_at(k) = c.couplings[k].gr;
    }
    py::dict out;
    out["nodes"] = c.nodes;
    out["a"] = a;
    out["b"] = b;
    out["GR"] = gr;
    out["emitting_area"] = numpyVector(c.emittingArea);
    out["self"] = numpyVector(c.self);
    out["asymmetry"] = c.asymmetry;
    out["dropped"] = c.dropped;
    out["dropped_sum"] = c.droppedSum;
    out["method"] = c.method == thermal::GebhartMethod::Dense ? "dense" : "columns";
    return out;
}

}  // namespace
}  // namespace hemirad::python

PYBIND11_MODULE(_hemirad, m) {
    using namespace hemirad;
    using namespace hemirad::python;
    m.doc() = "Hemirad's C++ library (use the hemirad package, which wraps it)";
    static py::exception<Error> error(m, "Error", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {
            PyErr_SetString(error.ptr(), e.what());
        }
    });

    py::class_<Scene, ScenePtr>(m, "Scene")
        .def_property_readonly("path", [](const Scene& s) { return s.path; })
        .def("__len__", &Scene::size)
        .def_property_readonly("area", [](const Scene& s) { return patchArray<double>(s, 0, [](const Patch& p, int) { return p.area; }); })
        .def_property_readonly("normal", [](const Scene& s) { return patchArray<double>(s, 3, [](const Patch& p, int c) { return p.normal[c]; }); })
        .def_property_readonly("centroid", [](const Scene& s) { return patchArray<double>(s, 3, [](const Patch& p, int c) { return p.centroid[c]; }); })
        .def_property_readonly("rho", [](const Scene& s) { return patchArray<double>(s, 3, [](const Patch& p, int c) { return p.rho[c]; }); })
        .def_property_readonly("emission", [](const Scene& s) { return patchArray<double>(s, 3, [](const Patch& p, int c) { return p.emission[c]; }); })
        .def_property_readonly("specular", [](const Scene& s) { return patchArray<double>(s, 0, [](const Patch& p, int) { return p.specular; }); })
        .def_property_readonly("parent", [](const Scene& s) {
            return patchArray<std::int64_t>(s, 0, [&s](const Patch& p, int) { return std::int64_t(s.parents[p.parent].sourcePatch); });
        })
        .def_property_readonly("object", [](const Scene& s) { return patchArray<std::int64_t>(s, 0, [](const Patch& p, int) { return std::int64_t(p.object); }); })
        .def_property_readonly("object_names", [](const Scene& s) { return s.objects; })
        .def_property_readonly("material_names", [](const Scene& s) {
            std::vector<std::string> names;
            for (const Patch& p : s.patches) names.push_back(p.material < s.materials.size() ? s.materials[p.material].name : "");
            return names;
        })
        .def_property_readonly("scene_hash", [](const Scene& s) { return hexHash(s.geometryHash()); })
        .def_property_readonly("has_mirrors", &Scene::hasMirrors)
        .def("polygon", [](const Scene& s, std::size_t id) {
            if (id >= s.size()) throw py::index_error("id: patch " + std::to_string(id) + " out of range");
            const std::vector<Vec3> corners = s.polygon(PatchId(id));
            py::array_t<double> out({py::ssize_t(corners.size()), py::ssize_t(3)});
            for (std::size_t k = 0; k < corners.size(); ++k)
                for (int c = 0; c < 3; ++c) out.mutable_at(k, c) = corners[k][c];
            return out;
        })
        .def("_set", &setPatchValues)
        .def("_save", [](const Scene& s, const std::string& path) { saveObj(s, path); });

    m.def("_load", [](const std::string& path, double subdivide, const std::string& materials) {
        std::vector<std::string> warnings;
        Warnings sink([&warnings](const std::string& text) { warnings.push_back(text); });
        ScenePtr scene;
        {
            py::gil_scoped_release release;
            const RadiosityPipeline pipeline(FormFactorPolicy{}, PipelineEvents{});
            scene = std::make_shared<Scene>(pipeline.load(path, subdivide, sink, {materials}));
        }
        return py::make_tuple(scene, warnings);
    });
    m.def("_form_factors", &formFactors);
    m.def("_solve", &solve);
    m.def("_thermal", &thermalSolve);
    m.def("_conductors", &conductors);
    m.def("_sky_view", &skyView);
    m.def("_sensor_factors", &sensorFactorsOf);
    m.def("_sensor_sky_coefficients", &sensorSkyCoefficientsOf);
    m.def("_solar_position", &solarPositionOf);
    m.def("_sun_direction", &sunDirectionOf);
    m.def("_sunlit", &sunlitOf);
    m.def("_reflected_sun", &reflectedSunOf);
    m.def("_irradiance", &irradianceOf);
    m.def("_sky_coefficients", &skyCoefficientsOf);
    m.def("_sky_radiance", &skyRadianceOf);
    m.def("_sensor_grid", &sensorGridOf);
    m.def("_read_form_factors", &readFormFactors);
    m.def("_write_form_factors", &writeFormFactors);
    m.def("_render", &render);
    m.def("_backends", [] {
        py::dict out;
        for (const BackendDescriptor* d : formFactorBackends()) {
            py::dict entry;
            entry["summary"] = d->summary;
            entry["not_built"] = d->notBuilt;
            entry["default"] = d == &defaultBackend();
            py::dict options;
            const MethodSettings defaults = d->notBuilt.empty() ? defaultSettings(d->name) : MethodSettings{};
            for (const BackendOption& o : d->options) {
                py::dict option;
                option["flag"] = o.flag;
                option["help"] = o.help;
                option["kind"] = o.kind == OptionKind::Switch ? "switch" : o.kind == OptionKind::Integer ? "integer" : "choice";
                option["choices"] = o.choices;
                option["default"] = d->notBuilt.empty() ? py::cast(o.get(defaults)) : py::none();
                std::string name = o.flag.substr(2);  // --fixed-directions: fixed_directions=
                std::replace(name.begin(), name.end(), '-', '_');
                options[py::str(name)] = option;
            }
            entry["options"] = options;
            out[py::str(d->name)] = entry;
        }
        return out;
    });
    m.def("_solvers", [] {
        std::vector<std::string> names = {"auto"};
        for (const SolverDescriptor* d : solverRegistry()) names.push_back(d->name);
        return names;
    });
}
