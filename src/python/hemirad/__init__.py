"""Hemirad from Python: form factors as scipy sparse matrices, radiosity as numpy arrays.

The same C++ library as the ``hemirad`` command (no second implementation)::

    import hemirad
    scene = hemirad.load("scenes/cornell_box.obj", subdivide=50)
    F, report = hemirad.form_factors(scene, samples=1024)   # scipy.sparse.csr_array, float64
    B, _ = hemirad.solve(scene, F)                          # (N, 3) numpy array, W/m^2
    hemirad.render(scene, B, "cornell.png")

Long computations release the GIL; ``progress(done, total, seconds)`` is called on the calling thread;
Ctrl-C (KeyboardInterrupt) or an exception raised by ``progress`` stops the computation. Errors of
the library (a malformed OBJ: ``file:line: message``) raise :class:`hemirad.Error`, a ValueError.
"""

import os as _os

import numpy as _np
import scipy.sparse as _sparse

from . import _hemirad
from ._hemirad import Error, Scene

__all__ = ["Error", "Scene", "load", "form_factors", "solve", "thermal", "conductors", "sky_view_factors", "sensor_factors", "sensor_grid", "sensor_sky_coefficients", "solar_position", "sun_direction", "sunlit_fractions",
           "reflected_sun", "irradiance", "sky_coefficients", "sky_radiance", "read_form_factors", "write_form_factors",
           "render", "methods", "solvers"]


def methods():
    """The form-factor back ends: {name: {"summary", "not_built", "default", "options"}}, where
    not_built is empty for a back end of this build (else how to get it), default is True for the one
    form_factors() uses when no method is named, and options maps each keyword form_factors() takes
    for that method to its help, kind, choices and default (the same settings as the command line's
    flags)."""
    return _hemirad._backends()


def solvers():
    """The names solve() takes ("auto" first)."""
    return _hemirad._solvers()


def load(path, subdivide=0.0, materials=None):
    """Loads a scene, a Wavefront OBJ (+MTL) or an STL (binary or ASCII); every face is a patch.

    subdivide: split patches until no edge exceeds this length (scene units; 0 = as modelled).
    materials: an MTL file whose materials go to the objects of their name (STL solids, OBJ o/g
    names; over an OBJ's own), ``default`` to the objects without one: the CLI's --materials.
    Returns a :class:`Scene`. Warnings of the loader (e.g. non-planar faces, objects left without
    a material) go to ``warnings.warn``. Raises :class:`Error` naming the file and the line (or
    the STL triangle) for a malformed file.
    """
    subdivide = float(subdivide)
    if not subdivide >= 0 or subdivide != subdivide or subdivide == float("inf"):
        raise ValueError(f"subdivide: expected a finite length >= 0, got {subdivide!r}")
    materials = "" if materials is None else _os.fspath(materials)
    if not isinstance(materials, str):
        raise TypeError(f"materials: expected a path, got {type(materials).__name__}")
    scene, messages = _hemirad._load(_os.fspath(path), subdivide, materials)
    if messages:
        import warnings
        for message in messages:
            warnings.warn(message, stacklevel=2)
    return scene


def _ids(scene, ids):
    array = _np.asarray(ids)
    if array.dtype == bool or not (_np.issubdtype(array.dtype, _np.integer) or array.size == 0):
        raise TypeError(f"ids: expected patch indices (integers), got dtype {array.dtype}")
    return _np.ascontiguousarray(array.reshape(-1), dtype=_np.int64)


def _values(name, values, count, width, low, high):
    array = _np.asarray(values, dtype=float) if not isinstance(values, str) else None
    if array is None or array.dtype == object:
        raise TypeError(f"{name}: expected numbers, got {type(values).__name__}")
    shape = (width,) if width > 1 else ()
    if array.shape == shape:
        array = _np.broadcast_to(array, (count,) + shape)
    if array.shape != (count,) + shape:
        raise ValueError(f"{name}: expected shape {shape or '()'} or {(count,) + shape}, got {array.shape}")
    if not _np.all(_np.isfinite(array)) or _np.any(array < low) or _np.any(array > high):
        raise ValueError(f"{name}: values must lie in [{low}, {high}]")
    return _np.ascontiguousarray(array, dtype=float)


def _set_emission(self, ids, rgb):
    """Sets the emission E (W/m^2, RGB >= 0) of patches ``ids`` (one RGB for all, or one per id)."""
    ids = _ids(self, ids)
    self._set("emission", ids, _values("rgb", rgb, len(ids), 3, 0.0, float("inf")))


def _set_rho(self, ids, rgb):
    """Sets the diffuse reflectance rho (RGB in [0, 1]) of patches ``ids``; rho + specular <= 1."""
    ids = _ids(self, ids)
    self._set("rho", ids, _values("rgb", rgb, len(ids), 3, 0.0, 1.0))


def _set_specular(self, ids, s):
    """Sets the mirror reflectance s (in [0, 1]) of patches ``ids``; rho + s <= 1. F depends on it:
    an F computed before no longer belongs to the scene (its scene hash changes)."""
    ids = _ids(self, ids)
    self._set("specular", ids, _values("s", s, len(ids), 1, 0.0, 1.0))


def _save(self, path):
    """Writes the scene as OBJ + MTL (same stem, .mtl), edits included, atomically."""
    self._save(_os.fspath(path))


Scene.set_emission = _set_emission
Scene.set_rho = _set_rho
Scene.set_specular = _set_specular
Scene.save = _save
Scene.__repr__ = lambda self: f"<hemirad.Scene {self.path!r}: {len(self)} patches>"


def _option_text(method, name, value):
    options = methods()[method]["options"]
    if name not in options:
        known = ", ".join(sorted(options)) or "none"
        raise TypeError(f"form_factors(): method {method!r} takes no option {name!r} (it takes {known})")
    kind = options[name]["kind"]
    if kind == "switch":
        if not isinstance(value, (bool, _np.bool_)):
            raise TypeError(f"{name}: expected True or False, got {value!r}")
        return "yes" if value else "no"
    if kind == "integer":
        if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
            raise TypeError(f"{name}: expected an integer, got {value!r}")
        return str(int(value))
    if not isinstance(value, str):
        raise TypeError(f"{name}: expected one of {options[name]['choices']}, got {value!r}")
    return value


def _csr(arrays, n):
    indptr, indices, data = arrays[:3]
    return _sparse.csr_array((data, indices, indptr), shape=(n, n), copy=False)


def _check_scene(scene, name="scene"):
    if not isinstance(scene, Scene):
        raise TypeError(f"{name}: expected a hemirad.Scene (from hemirad.load), got {type(scene).__name__}")


def _method_flags(method, options):
    """The back end (None: the default) checked, and its keyword options as command-line flags."""
    if method is None:
        method = next(name for name, entry in methods().items() if entry["default"])
    if method not in methods():
        raise ValueError(f"method: expected one of {sorted(methods())}, got {method!r}")
    return method, {"--" + name.replace("_", "-"): _option_text(method, name, value) for name, value in options.items()}


def form_factors(scene, method=None, *, max_depth=8, threads=0, all_rows=False,
                 enforce_reciprocity=False, normalize_rows=False, drop_below=0.0, memory_check=True,
                 progress=None, **options):
    """Computes the form-factor matrix F of ``scene``.

    method: a back end of :func:`methods` ("hemisphere", "hemicube"; None: the default, the
    hemisphere, or the hemicube in a build without Embree). Its own options are keywords
    named as its command-line flags: hemisphere ``samples=3072, origins=1, estimator="auto", ...``,
    hemicube ``resolution=256, ...``; an option the method does not take raises TypeError.
    max_depth: mirror reflections followed; threads: worker threads (0: all cores);
    all_rows: also rows of black patches (skipped by default: their B is their E);
    enforce_reciprocity, normalize_rows, drop_below: as the command line's flags (drop_below=0: keep
    every pair); memory_check: refuse an F
    that would not fit in memory; progress: ``progress(rows_done, rows_total, seconds)``.

    Returns ``(F, report)``: F a ``scipy.sparse.csr_array`` of float64 (row i = emitter, F[i, j] the
    fraction of i's power reaching j), sharing the library's memory (no copy); report a dict of the
    diagnostics the command line prints (row sums, reciprocity, lost power, rays and rays/s,
    seconds) plus ``computed`` (rows computed) and ``provenance`` (for write_form_factors).
    """
    _check_scene(scene)
    method, flags = _method_flags(method, options)
    if progress is not None and not callable(progress):
        raise TypeError("progress: expected a callable progress(done, total, seconds)")
    arrays, report = _hemirad._form_factors(scene, method, flags, int(max_depth), int(threads), bool(all_rows),
                                            bool(enforce_reciprocity), bool(normalize_rows), float(drop_below),
                                            bool(memory_check),
                                            progress)
    report["computed"] = arrays[3]
    return _csr(arrays, len(scene)), report


def _check_structure(F, n, name):
    """Raises ValueError unless F's CSR arrays are consistent: scipy checks only their lengths by
    default, and its canonicalisation (and the library) would then read and write past them."""
    indptr, indices, data = F.indptr, F.indices, F.data
    if indptr.shape != (n + 1,) or indices.ndim != 1 or data.shape != indices.shape:
        raise ValueError(f"{name}: inconsistent CSR arrays (indptr {indptr.shape}, indices {indices.shape}, "
                         f"data {data.shape} for {n} rows)")
    steps = _np.diff(indptr)
    if indptr[0] != 0 or indptr[-1] != len(indices) or (len(steps) and steps.min() < 0):
        raise ValueError(f"{name}: row pointers (indptr) must rise from 0 to the {len(indices)} entries, "
                         f"never decreasing")
    if len(indices) and (indices.min() < 0 or indices.max() >= n):
        raise ValueError(f"{name}: column indices must lie in [0, {n})")


def _canonical(F, n, name="F"):
    """F as CSR arrays the library takes: int64 row pointers, int32 sorted unique columns, float64."""
    if not (_sparse.issparse(F) or isinstance(F, _np.ndarray)):
        raise TypeError(f"{name}: expected a scipy sparse matrix or a numpy array, got {type(F).__name__}")
    if F.shape != (n, n):
        raise ValueError(f"{name}: expected shape ({n}, {n}) for a scene of {n} patches, got {F.shape}")
    F = _sparse.csr_array(F)
    _check_structure(F, n, name)
    if not F.has_canonical_format:
        F = F.copy()
        F.sum_duplicates()
    return (_np.ascontiguousarray(F.indptr, dtype=_np.int64), _np.ascontiguousarray(F.indices, dtype=_np.int32),
            _np.ascontiguousarray(F.data, dtype=_np.float64))


def solve(scene, F, solver="auto", tolerance=1e-6, *, max_iterations=100000, allow_unconverged=False,
          progress=None):
    """Solves the radiosity system B = E + rho F B per RGB channel.

    F: any scipy sparse matrix (or numpy array) of shape (N, N), e.g. form_factors()'s, post-processed
    as you like; values must be finite, >= 0, and rows sum to at most 1 (1 / (1 - s_max) with mirrors).
    F as form_factors() returned it is used in place; any other matrix is copied once. Rows of
    patches that were black when F was computed are empty unless it was computed with all_rows=True.
    solver: one of :func:`solvers` ("auto": LU up to 2000 patches, else an iterative solver).
    progress: ``progress(sweep, max_iterations, seconds)`` for the iterative solvers.
    Returns ``(B, report)``: B an (N, 3) float64 array in W/m^2; report["channels"] per solve.
    Raises :class:`Error` when the solve does not converge (unless allow_unconverged).
    """
    _check_scene(scene)
    if solver not in solvers():
        raise ValueError(f"solver: expected one of {solvers()}, got {solver!r}")
    if not 0 < float(tolerance) < 1:
        raise ValueError(f"tolerance: expected a number in (0, 1), got {tolerance!r}")
    indptr, indices, data = _canonical(F, len(scene))
    return _hemirad._solve(scene, indptr, indices, data, solver, float(tolerance), int(max_iterations),
                           bool(allow_unconverged), progress)


def read_form_factors(path, scene=None, *, info=False):
    """Reads F from an .hff file (checked: checksum, structure, values; a shard manifest too) or a
    Matrix Market .mtx. With ``scene``, F must have been computed for it (scene hash), else
    :class:`Error`. Returns F (csr_array, float64; with ``info=True``, ``(F, provenance)``)."""
    if scene is not None:
        _check_scene(scene)
    arrays, provenance = _hemirad._read_form_factors(_os.fspath(path), scene)
    F = _csr(arrays, len(arrays[3]))
    return (F, provenance) if info else F


def write_form_factors(path, F, scene, *, provenance=None):
    """Writes F for ``scene`` atomically as .hff (checked binary) or .mtx (Matrix Market), by the
    extension; "-" is standard output. The file records the scene's hash, so that reading it with
    another scene fails. ``provenance``: form_factors()'s report["provenance"], to record how F was
    computed."""
    _check_scene(scene)
    indptr, indices, data = _canonical(F, len(scene))
    if provenance is not None and not isinstance(provenance, dict):
        raise TypeError("provenance: expected the dict form_factors() reported")
    _hemirad._write_form_factors(_os.fspath(path), scene, indptr, indices, data, provenance)


def render(scene, B, path, *, camera=None, size=(640, 640), spp=4, exposure=0.0, flat=False, crease=45.0,
           threads=0):
    """Renders the solved ``scene`` to a PNG with camera rays: Gouraud radiosity (vertex values
    averaged over patches within ``crease`` degrees), mirrors showing what they reflect.

    camera: (eye_x, eye_y, eye_z, target_x, target_y, target_z, fov_degrees), default the scene's
    own or one that frames it; size: (width, height); exposure: 0 = automatic.
    Returns a dict with the exposure used.
    """
    _check_scene(scene)
    B = _np.asarray(B, dtype=float)
    if B.shape != (len(scene), 3):
        raise ValueError(f"B: expected shape ({len(scene)}, 3), got {B.shape}")
    if camera is not None:
        camera = [float(v) for v in camera]
        if len(camera) != 7:
            raise ValueError("camera: expected 7 numbers (eye, target, vertical field of view in degrees)")
    width, height = (int(v) for v in size)
    if not (0 < width <= 16384 and 0 < height <= 16384):
        raise ValueError(f"size: expected (width, height) in 1..16384, got {size!r}")
    if int(spp) < 1:
        raise ValueError(f"spp: expected >= 1, got {spp!r}")
    return _hemirad._render(scene, _np.ascontiguousarray(B), _os.fspath(path), camera, width, height, int(spp),
                            float(exposure), bool(flat), float(crease), int(threads))


def _patch_values(name, values, n, default=None):
    if values is None:
        if default is None:
            raise ValueError(f"{name}: expected one value per patch ({n})")
        return default
    a = _np.ascontiguousarray(_np.broadcast_to(_np.asarray(values, dtype=_np.float64), (n,)))
    return a


def thermal(scene, F, emissivity, specular=None, temperature=None, flux=None, environment=None, *,
            absorbed=None, band_limits_um=None, band_emissivity=None, band_specular=None, band_F=None,
            emissivity_curves=None, solver="auto", tolerance=1e-10):
    """Gray radiative exchange on F (docs/thermal.md): the net-radiation method with mirrors.

    emissivity, specular: per patch (or one value for all); specular None takes the scene's (F was
    computed with it). temperature (K) and flux (W/m^2, net leaving; 0 = adiabatic): per patch, NaN
    where not given; each patch needs exactly one. environment: the temperature (K) that receives what
    leaves an open scene, or None for a closed scene. Lengths are the scene's unit in metres (metres
    when it states none). absorbed: heat absorbed per patch from outside the IR (W/m^2, e.g. the sun).
    band_limits_um (K increasing wavelengths) with band_emissivity of shape (K + 1, N): non-gray IR, each
    band's emission by the blackbody fractions (emissivity then only starts the iteration).
    band_specular, shape (K + 1, N): each band's specular reflectances; band_F: a list of K + 1 sparse
    matrices, each band's extended F for its reflectances (None where F serves: the band's
    reflectances are the scene's).
    emissivity_curves: a list of (patches, temperatures_K, emissivities), patches an index array or a
    boolean mask: those patches' emissivity against their temperature, piecewise linear (constant
    beyond the ends); the solve iterates on the unknown temperatures (gray model only).
    Returns a dict of per-patch arrays T (K), J, H, q (W/m^2, net leaving), Q (W), and environment_power
    (W, what the environment gives), balance (|sum Q + Q_env| / max |Q|), solver, residual.
    """
    _check_scene(scene)
    n = len(scene)
    nan = _np.full(n, _np.nan)
    eps = _patch_values("emissivity", emissivity, n)
    s = _patch_values("specular", specular, n, _np.ascontiguousarray(scene.specular, dtype=_np.float64))
    T = _patch_values("temperature", temperature, n, nan)
    q = _patch_values("flux", flux, n, nan)
    indptr, indices, data = _canonical(F, n)
    env = None if environment is None else float(environment)
    gained = _np.zeros(0) if absorbed is None else _patch_values("absorbed", absorbed, n)
    limits = [] if band_limits_um is None else [float(x) for x in band_limits_um]
    bands = _np.zeros((0, 0)) if band_emissivity is None else _np.ascontiguousarray(band_emissivity, dtype=_np.float64)
    if bool(limits) != (band_emissivity is not None):
        raise ValueError("band_limits_um and band_emissivity go together")
    band_s = _np.zeros((0, 0)) if band_specular is None else _np.ascontiguousarray(band_specular, dtype=_np.float64)
    band_matrices = [None if Fk is None else _canonical(Fk, n, "band_F[%d]" % k) for k, Fk in enumerate(band_F or [])]
    curves = []
    for patches, temperatures, values in (emissivity_curves or []):
        patches = _np.asarray(patches)
        if patches.dtype == bool:
            if patches.shape != (n,):
                raise ValueError("emissivity_curves: a mask needs one entry per patch (%d)" % n)
            patches = _np.flatnonzero(patches)
        curves.append(([int(p) for p in patches.ravel()], [float(t) for t in temperatures], [float(e) for e in values]))
    return _hemirad._thermal(scene, indptr, indices, data, eps, s, T, q, env, gained, limits, bands, band_s,
                             band_matrices, curves, solver, float(tolerance))


def conductors(scene, F, emissivity, specular=None, *, lump="patches", threshold=0.0, method="auto"):
    """Gebhart factors and radiative conductors: (GR, B, nodes).

    GR: a symmetric scipy sparse matrix of shape (K + 1, K + 1), GR_IJ = sum eps_i A_i B_ij in m^2
    between the K nodes (each patch, or each object with lump="objects") and the environment (the last
    node; no self terms). B: the Gebhart factors B_IJ = GR_IJ / (eps A)_I with the self terms B_II (rows
    of nodes that emit; each row sums to 1 with its environment column). nodes: names.
    threshold: couplings whose Gebhart factors both ways are below it are dropped.
    method: "columns" (a column solve per node over F), "dense" (one Cholesky inverse over every
    patch pair: n^3 flops, 8 n^2 bytes) or "auto" (the faster that fits in memory).
    """
    _check_scene(scene)
    n = len(scene)
    eps = _patch_values("emissivity", emissivity, n)
    s = _patch_values("specular", specular, n, _np.ascontiguousarray(scene.specular, dtype=_np.float64))
    indptr, indices, data = _canonical(F, n)
    r = _hemirad._conductors(scene, indptr, indices, data, eps, s, lump, float(threshold), str(method))
    k = len(r["nodes"]) + 1
    a, b, gr = r["a"], r["b"], r["GR"]
    GR = _sparse.coo_matrix((_np.concatenate([gr, gr]), (_np.concatenate([a, b]), _np.concatenate([b, a]))),
                           shape=(k, k)).tocsr()
    area = _np.append(r["emitting_area"], 0.0)
    scale = _np.divide(1.0, area, out=_np.zeros_like(area), where=area > 0)
    absorbed = GR + _sparse.diags(_np.append(r["self"], 0.0))  # a node absorbs some of its own emission too
    B = _sparse.diags(scale) @ absorbed
    return GR, B.tocsr(), list(r["nodes"])


def solar_position(time, latitude, longitude):
    """The sun's place at ``time`` ("YYYY-MM-DDTHH:MM[:SS]", optionally "Z", "+HH:MM" or "-HH:MM"; UTC
    without one) seen from latitude and longitude in degrees (north and east positive): a dict of
    ``elevation`` (degrees, refraction included) and ``azimuth`` (degrees clockwise from north).
    Michalsky 1988, within 0.01 degrees for 1950-2050, as the command line's --sun-time."""
    return _hemirad._solar_position(str(time), float(latitude), float(longitude))


def sun_direction(position, up=(0, 0, 1), north=None):
    """The unit vector toward the sun (a :func:`solar_position` dict) in a scene whose up and north
    are given (north defaults to +y for z up, -z for y up; east = north x up)."""
    up, north = _frame(up, north)
    return _hemirad._sun_direction(float(position["elevation"]), float(position["azimuth"]), up, north)


def sunlit_fractions(scene, to_sun):
    """Per patch, the fraction of its area the sun reaches (exact shadow polygons; every patch, front
    or back, blocks it; 0 where it faces away). to_sun: the direction toward the sun (any length), or
    k directions as a k x 3 array: then a k x patches array, the scene's shadow set-up made once for
    all of them (a year's suns)."""
    _check_scene(scene)
    return _hemirad._sunlit(scene, _np.asarray(to_sun, dtype=_np.float64))


def reflected_sun(scene, to_sun, dni):
    """The sun's first reflections by the scene's mirrors (s > 0): exact footprints of each mirror's
    sunlit part on the patches facing its beam, past the patches between (as ``hemirad sun --dni
    --glare``). Returns a dict: ``irradiance`` per patch (W/m^2, averaged over it) and ``spots``, a
    dict of arrays per (mirror, receiver) pair, brightest first: ``mirror``, ``receiver``,
    ``irradiance``, ``peak`` (s DNI cos, W/m^2) and ``lit_area`` (the footprint, scene units^2).
    Many suns at once: ``to_sun`` of shape (k, 3) and ``dni`` one value or k; a list of k such dicts,
    the scene's shadow trees set up once for all of them (an hour loop's cost)."""
    _check_scene(scene)
    dni = [float(x) for x in _np.atleast_1d(_np.asarray(dni, dtype=_np.float64))]
    return _hemirad._reflected_sun(scene, _np.asarray(to_sun, dtype=_np.float64), dni)


def _frame(up, north):
    up = _np.asarray(up, dtype=_np.float64)
    if north is None:
        north = (0, 0, -1) if abs(up[1]) > abs(up[2]) else (0, 1, 0)
    return up, _np.asarray(north, dtype=_np.float64)


def sky_coefficients(scene, subdivision=2, samples=1, *, up=(0, 0, 1), north=None):
    """Daylight coefficients: per patch and sky cell, the irradiance (W/m^2) a cell of unit radiance
    (W/(m^2 sr)) gives the patch past the scene's shadows, and through its mirrors (first
    reflections), as ``hemirad irradiance --sky MODEL`` computes them: ``samples`` x ``samples``
    directions per cell of Reinhart's subdivision (1: Tregenza's 145 cells; 2: 577), each an exact
    shadow pass. Below the horizon nothing comes: model the ground.

    Returns a dict: ``direct`` and ``mirrored`` (arrays patches x cells; ``mirrored`` None without
    mirrors), ``cells`` (arrays ``altitude_low``, ``altitude_high``, ``azimuth_low``, ``azimuth_high``
    in degrees, azimuth clockwise from north; ``direction`` cells x 3 in the scene's frame;
    ``solid_angle`` and ``horizontal``, sr), ``subdivision`` and ``samples``. A sky's irradiance on the
    patches is then ``direct @ sky_radiance(...)``.
    """
    _check_scene(scene)
    up, north = _frame(up, north)
    return _hemirad._sky_coefficients(scene, int(subdivision), int(samples), up, north)


def sensor_sky_coefficients(scene, positions, normals, subdivision=2, samples=1, *, up=(0, 0, 1), north=None):
    """Daylight coefficients at sensor points (positions, normals: arrays (S, 3)): per sensor and
    sky cell, the irradiance (W/m^2) a cell of unit radiance gives the point past the scene's
    shadows, and through its mirrors (first reflections), by the same directions as
    :func:`sky_coefficients` (one ray from each sensor along each). Returns a dict: ``direct`` and
    ``mirrored`` (arrays sensors x cells; ``mirrored`` None without mirrors). A sky's irradiance at the
    sensors is ``direct @ sky_radiance(...)``.
    """
    _check_scene(scene)
    up, north = _frame(up, north)
    return _hemirad._sensor_sky_coefficients(scene, _np.asarray(positions, dtype=_np.float64), _np.asarray(normals, dtype=_np.float64),
                                             int(subdivision), int(samples), up, north)


def sky_radiance(model, to_sun, dni, dhi, subdivision=2, samples=1, *, day_of_year=0, up=(0, 0, 1), north=None):
    """Each sky cell's radiance, W/(m^2 sr), under ``model``: "uniform", "cie-overcast" (Moon &
    Spencer's 1 + 2 sin(altitude)), "cie:1" .. "cie:15" (ISO 15469 / CIE S 011 general skies) or
    "perez" (Perez, Seals & Michalsky 1993, from the DNI, the DHI and the sun), averaged over each
    cell's ``samples`` x ``samples`` directions and scaled so that an unobstructed horizontal plane
    receives the DHI. to_sun: toward the sun in the scene's frame (up and north orient the sky);
    day_of_year (1..366) sets Perez's extraterrestrial irradiance (0: the mean Sun-Earth distance).
    """
    up, north = _frame(up, north)
    return _hemirad._sky_radiance(str(model), _np.asarray(to_sun, dtype=_np.float64), float(dni), float(dhi),
                                  int(subdivision), int(samples), int(day_of_year), up, north)


def irradiance(scene, F, to_sun, dni, dhi=0.0, *, sky_view=None, sky="isotropic", coefficients=None, day_of_year=0,
               up=(0, 0, 1), north=None, unit=None, solver="auto", tolerance=1e-10):
    """One hour of sun and sky on ``scene``, inter-reflected through F (every row computed), as the
    command line's ``irradiance``: the direct sun DNI cos x the sunlit fraction, the sun reflected by
    mirrors (:func:`reflected_sun`), and the direct sky: for ``sky="isotropic"`` DHI x the direct sky
    view factor (``sky_view``: per patch; None computes it), else a model's (:func:`sky_radiance`)
    through the daylight coefficients (``coefficients`` from :func:`sky_coefficients`; None computes
    them with its defaults, up and north), with the sky seen through mirrors. Each patch's mean Kd is
    its reflectance. unit: metres per scene unit for the powers (None: the scene's, else 1).

    Returns a dict of per-patch arrays (W/m^2) ``direct_sun``, ``direct_sky``, ``reflected``,
    ``total``, ``absorbed``, ``reflected_sun``, ``reflected_sky`` (a model's sky through mirrors) and
    ``radiosity`` (the diffuse J leaving each patch, what :func:`sensor_factors`' F turns into a
    sensor's reflected irradiance), and ``incident_power``, ``absorbed_power``, ``escaped_power`` (W),
    ``balance``, ``solver``.
    """
    _check_scene(scene)
    n = len(scene)
    to_sun = _np.asarray(to_sun, dtype=_np.float64)
    direct = _np.asarray(sunlit_fractions(scene, to_sun)) * float(dni) * _np.maximum(
        0.0, _np.asarray(scene.normal) @ (to_sun / _np.linalg.norm(to_sun)))
    model_sky, model_reflected, sky_values = _np.zeros(0), _np.zeros(0), _np.zeros(0)
    if sky == "isotropic":
        if sky_view is None:
            sky_view = sky_view_factors(scene)["direct"]
        sky_values = _patch_values("sky_view", sky_view, n)
    else:
        if sky_view is not None:
            raise ValueError("irradiance: sky_view is the isotropic sky's; a sky model uses the daylight coefficients")
        if coefficients is None:
            coefficients = sky_coefficients(scene, up=up, north=north)
        if coefficients["direct"].shape[0] != n:
            raise ValueError("irradiance: the coefficients have %d rows for %d patches" % (coefficients["direct"].shape[0], n))
        radiance = sky_radiance(sky, to_sun, dni, dhi, coefficients["subdivision"], coefficients["samples"],
                                day_of_year=day_of_year, up=up, north=north)
        model_sky = _np.ascontiguousarray(coefficients["direct"] @ radiance)
        if coefficients["mirrored"] is not None:
            model_reflected = _np.ascontiguousarray(coefficients["mirrored"] @ radiance)
    indptr, indices, data = _canonical(F, n)
    metres = 0.0 if unit is None else float(unit)
    mirrored = _np.zeros(0)
    if _np.any(_np.asarray(scene.specular) > 0):
        mirrored = reflected_sun(scene, to_sun, dni)["irradiance"]
    return _hemirad._irradiance(scene, indptr, indices, data, _np.ascontiguousarray(direct), sky_values, float(dhi), mirrored,
                                model_sky, model_reflected, metres, str(solver), float(tolerance))


def sensor_factors(scene, positions, normals, *, threads=0, estimator="auto", rays=4096, max_depth=8):
    """Sensor points: each point's factors to the patches and its sky view factor.

    positions, normals: arrays of shape (S, 3) (normals need not be unit); threads: 0 for every core.
    A sensor sees the scene without being part of it.
    ``estimator="exact"``: each factor is Lambert's to the part of a patch's front the point sees
    past every other patch (shadow polygons; a term per sensor and patch), and the sky view factor
    is 1 less the factors to every patch seen, front or back. ``"rays"``: ``rays`` stratified
    directions per sensor (Beckers cells of equal projected solid angle), each factor the share that
    meets the patch's front first, the sky view factor the share that meets nothing (about 1e-3 rms
    at 4096 rays, falling about as rays^-3/4). ``"auto"``: exact while sensors x patches <= 2.5e7.
    Mirrors (patches with s > 0) are followed to ``max_depth`` reflections: what a sensor sees in
    them is added to F weighted by the s met (by images for "exact", by reflected rays for "rays"),
    and the sky seen in them is ``through_mirrors``.

    Returns a dict: ``F`` a ``scipy.sparse.csr_array`` of shape (S, N), float64,
    ``sky_view_factor`` (``direct`` + ``through_mirrors``), ``direct`` and ``through_mirrors``,
    arrays of S, ``mirrors`` (how mirrors were treated: empty without them, else "followed ..." or
    "not followed: " and why), ``estimator`` ("exact" or "rays") and ``why`` (auto's reason).
    """
    _check_scene(scene)
    out = _hemirad._sensor_factors(scene, _np.asarray(positions, dtype=_np.float64),
                                   _np.asarray(normals, dtype=_np.float64), int(threads), str(estimator), int(rays),
                                   int(max_depth))
    F = _sparse.csr_array((out["data"], out["indices"], out["indptr"]), shape=(len(out["indptr"]) - 1, out["patches"]))
    direct, mirrored = out["sky_view_factor"], out["sky_view_mirrored"]
    return {"F": F, "sky_view_factor": direct + mirrored, "direct": direct, "through_mirrors": mirrored,
            "mirrors": out["mirrors"], "estimator": out["estimator"], "why": out["why"]}


def sensor_grid(scene, object, spacing, height=0.0):
    """A grid of sensors over an object's faces: the points of a square lattice of ``spacing`` on
    each of its patches, lifted ``height`` along the normal. Returns ``(positions, normals, names)``:
    arrays of shape (S, 3) and a list of names OBJECT:PATCH:K (for :func:`sensor_factors`)."""
    _check_scene(scene)
    return _hemirad._sensor_grid(scene, str(object), float(spacing), float(height))


def sky_view_factors(scene, method=None, *, max_depth=8, threads=0, **options):
    """The sky view factor of every patch: the cosine-weighted part of its hemisphere through which the
    sky is seen, directly (every surface blocks it, front or back) and through mirrors (weighted by s).

    method and options as :func:`form_factors`. Returns a dict of per-patch arrays ``sky_view_factor``
    (direct + through_mirrors), ``direct`` and ``through_mirrors``, and ``method``.
    """
    _check_scene(scene)
    method, flags = _method_flags(method, options)
    return _hemirad._sky_view(scene, method, flags, int(max_depth), int(threads))
