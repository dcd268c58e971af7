"""The Python module against the command line and closed forms (run by ctest: make test)."""

import glob
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
import scipy.io
import scipy.sparse

import hemirad

SOURCE = os.environ.get("HEMIRAD_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BINARY = os.environ["HEMIRAD_BINARY"]


def scene_path(name):
    return os.path.join(SOURCE, "scenes", name)


def cli(*arguments, cwd):
    run = subprocess.run([BINARY, *arguments, "--quiet"], cwd=cwd, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return run


def csv_radiosity(path):
    return np.loadtxt(path, delimiter=",", skiprows=1)[:, 9:12]


@pytest.fixture(scope="module")
def cornell():
    """The Cornell box subdivided to 344 patches, and F as the CLI computes it."""
    return hemirad.load(scene_path("cornell_box.obj"), subdivide=100)


def test_form_factors_equal_the_cli_entry_by_entry(cornell, tmp_path):
    for options, flags in [({"samples": 256}, ["--samples", "256"]),
                           ({"estimator": "rays", "samples": 512, "origins": 2},
                            ["--estimator", "rays", "--samples", "512", "--origins", "2"])]:
        cli("formfactors", scene_path("cornell_box.obj"), "--subdivide", "100", "--threads", "1", *flags,
            "-o", "F.mtx", cwd=tmp_path)
        expected = scipy.sparse.csr_array(scipy.io.mmread(str(tmp_path / "F.mtx")))
        F, report = hemirad.form_factors(cornell, threads=1, **options)
        assert isinstance(F, scipy.sparse.csr_array) and F.dtype == np.float64
        assert F.shape == (len(cornell), len(cornell)) and F.nnz == expected.nnz > 10000
        assert np.array_equal(F.indptr, expected.indptr) and np.array_equal(F.indices, expected.indices)
        assert np.array_equal(F.data, expected.data)  # shortest round-trip text: the doubles exactly
        assert report["rows_computed"] == len(cornell) and report["computed"].all()
        assert 0.18 < report["lost_fraction"] < 0.2  # the open box
        assert report["rays"] > 0 and report["rays_per_s"] > 0 and report["seconds"]["compute"] > 0
        assert report["row_sum_max"] <= 1.001 and report["nonzeros"] == F.nnz


def test_closed_forms_unit_cube_and_plates():
    # No method named: the registry's default (the hemisphere in a build with Embree), as on the CLI.
    assert [name for name, entry in hemirad.methods().items() if entry["default"]] == ["hemisphere"]
    cube = hemirad.load(scene_path("unit_cube.obj"))
    F, report = hemirad.form_factors(cube)
    assert report["provenance"]["method"] == "hemisphere"
    dense = F.toarray()
    opposite, adjacent = 0.1998248957, 0.2000437761
    for i in range(6):
        others = np.sort(np.delete(dense[i], i))  # one opposite face, four adjacent ones
        assert abs(others[0] - opposite) < 1e-6 and np.all(np.abs(others[1:] - adjacent) < 1e-6)
    plates = hemirad.load(scene_path("parallel_plates.obj"))
    F, _ = hemirad.form_factors(plates)
    assert abs(F[0, 1] - 0.199825) < 1e-5 and abs(F[1, 0] - 0.199825) < 1e-5
    perpendicular = hemirad.load(scene_path("perpendicular_plates.obj"))
    F, _ = hemirad.form_factors(perpendicular, origins=16)
    assert abs(F[0, 1] - 0.232853) < 2e-4 and abs(F[1, 0] - 0.116426) < 1e-4


def test_solve_matches_the_cli_csv_and_takes_any_sparse_matrix(cornell, tmp_path):
    cli("solve", scene_path("cornell_box.obj"), "--subdivide", "100", "--samples", "256", "--threads", "1",
        "-o", "B.csv", cwd=tmp_path)
    expected = csv_radiosity(tmp_path / "B.csv")
    F, _ = hemirad.form_factors(cornell, samples=256, threads=1)
    B, report = hemirad.solve(cornell, F)
    assert B.shape == (len(cornell), 3) and B.dtype == np.float64
    assert np.max(np.abs(B - expected) / np.maximum(np.abs(expected), 1e-6)) < 1e-8  # the CSV's 9 digits
    assert all(r["converged"] for r in report["channels"])
    # Post-processed by the user in float64 COO, solved by an iterative solver.
    B2, _ = hemirad.solve(cornell, scipy.sparse.coo_matrix(F.astype(np.float64)), solver="bicgstab", tolerance=1e-12)
    assert np.max(np.abs(B2 - expected) / np.maximum(np.abs(expected), 1e-6)) < 1e-7


def test_file_round_trips_and_scene_hash_checks(cornell, tmp_path):
    F, report = hemirad.form_factors(cornell, samples=256)
    for name in ("F.hff", "F.mtx"):
        path = tmp_path / name
        hemirad.write_form_factors(path, F, cornell, provenance=report["provenance"])
        G, info = hemirad.read_form_factors(path, cornell, info=True)
        assert (G != F).nnz == 0 and G.dtype == np.float64
        assert info["method"] == "hemisphere" and info["scene_hash"] == cornell.scene_hash
    # The CLI reads what Python wrote.
    assert subprocess.run([BINARY, "info", str(tmp_path / "F.hff")], capture_output=True).returncode == 0
    # A scene whose mirrors changed is another scene for F.
    edited = hemirad.load(scene_path("cornell_box.obj"), subdivide=100)
    edited.set_rho([0], [0.0, 0.0, 0.0])
    edited.set_specular([0], 0.9)
    assert edited.scene_hash != cornell.scene_hash
    with pytest.raises(hemirad.Error, match="computed for another scene"):
        hemirad.read_form_factors(tmp_path / "F.hff", edited)
    (tmp_path / "bad.hff").write_bytes((tmp_path / "F.hff").read_bytes()[:-9])
    with pytest.raises(hemirad.Error, match="bad.hff: truncated"):
        hemirad.read_form_factors(tmp_path / "bad.hff")


def test_scene_arrays_edits_and_save(tmp_path):
    scene = hemirad.load(scene_path("cornell_box.obj"))
    assert len(scene) == 20 and scene.area.shape == (20,) and scene.normal.shape == (20, 3)
    assert np.allclose(np.linalg.norm(scene.normal, axis=1), 1)
    assert scene.emission.max() > 0 and scene.rho.shape == (20, 3) and scene.parent.tolist() == list(range(20))
    with pytest.raises(ValueError):
        scene.area[0] = 1  # read-only
    light = int(np.argmax(scene.emission[:, 0]))
    scene.set_emission([light], [1.0, 2.0, 3.0])
    scene.set_rho(np.arange(3), [[0.1, 0.2, 0.3]] * 3)
    scene.set_rho([5], [0.2, 0.2, 0.2])
    scene.set_specular([5], 0.5)
    assert scene.emission[light].tolist() == [1.0, 2.0, 3.0] and scene.rho[2].tolist() == [0.1, 0.2, 0.3]
    scene.save(tmp_path / "edited.obj")
    again = hemirad.load(tmp_path / "edited.obj")
    assert again.scene_hash == scene.scene_hash
    assert np.array_equal(again.rho, scene.rho) and np.array_equal(again.emission, scene.emission)
    sub = hemirad.load(scene_path("cornell_box.obj"), subdivide=100)
    assert len(sub) == 344 and set(sub.parent.tolist()) == set(range(20))


def test_stl_with_materials_by_object_name(tmp_path):
    # Two triangles facing each other (z = 0 up, z = 1 down), one ASCII solid each.
    def solid(name, normal, vertices):
        rows = "".join(f"      vertex {x} {y} {z}\n" for x, y, z in vertices)
        return (f"solid {name}\n  facet normal {normal}\n    outer loop\n{rows}    endloop\n  endfacet\n"
                f"endsolid {name}\n")
    (tmp_path / "pair.stl").write_text(solid("lamp", "0 0 1", [(0, 0, 0), (1, 0, 0), (0, 1, 0)]) +
                                       solid("plate", "0 0 -1", [(0, 0, 1), (0, 1, 1), (1, 0, 1)]))
    (tmp_path / "m.mtl").write_text("newmtl lamp\nKd 0\nKe 10 10 10\nnewmtl plaet\nKd 0.8\n")
    with pytest.warns(UserWarning) as caught:
        scene = hemirad.load(tmp_path / "pair.stl", materials=tmp_path / "m.mtl")
    messages = [str(w.message) for w in caught]
    assert any("name no object" in m and "'plaet'" in m for m in messages), messages
    assert any("match no material" in m and "'plate'" in m for m in messages), messages
    assert scene.object_names == ["lamp", "plate"] and scene.material_names == ["lamp", "hemirad_default"]
    assert scene.emission[0].tolist() == [10, 10, 10] and scene.rho[1].tolist() == [0.5, 0.5, 0.5]
    (tmp_path / "bad.mtl").write_text("newmtl lamp\nKe 1 x 1\n")
    with pytest.raises(hemirad.Error, match=r"bad\.mtl:2: Ke 'x' is not a number"):
        hemirad.load(tmp_path / "pair.stl", materials=tmp_path / "bad.mtl")
    with pytest.raises(hemirad.Error, match=r"pair\.ply: unknown scene file type '\.ply'"):
        hemirad.load(tmp_path / "pair.ply")


def test_bad_arguments_name_themselves(cornell):
    with pytest.raises(hemirad.Error, match=r"face_garbage_index\.obj:6: face vertex '3x' is not an index"):
        hemirad.load(os.path.join(SOURCE, "tests", "data", "malformed", "face_garbage_index.obj"))
    assert issubclass(hemirad.Error, ValueError)
    with pytest.raises(hemirad.Error, match="missing.obj"):
        hemirad.load("missing.obj")
    with pytest.raises(ValueError, match=r"F: expected shape \(344, 344\)"):
        hemirad.solve(cornell, scipy.sparse.eye(3))
    with pytest.raises(TypeError, match="F: expected a scipy sparse matrix"):
        hemirad.solve(cornell, [[1]])
    with pytest.raises(TypeError, match="takes no option 'resolution'"):
        hemirad.form_factors(cornell, resolution=64)
    with pytest.raises(TypeError, match="samples: expected an integer"):
        hemirad.form_factors(cornell, samples=3.5)
    with pytest.raises(hemirad.Error, match="--samples"):
        hemirad.form_factors(cornell, samples=0)
    with pytest.raises(ValueError, match="method: expected one of"):
        hemirad.form_factors(cornell, method="radiosity")
    with pytest.raises(ValueError, match=r"rgb: expected shape \(3,\)"):
        cornell.set_emission([0], [1, 2])
    with pytest.raises(TypeError, match="ids: expected patch indices"):
        cornell.set_emission([0.5], [1, 2, 3])
    with pytest.raises(IndexError, match="ids: patch 344 out of range"):
        cornell.set_rho([344], [0.5, 0.5, 0.5])
    with pytest.raises(ValueError, match="rho \\+ specular > 1"):
        cornell.set_specular([1, 0], [0.1, 0.9])  # rho 0.73 + 0.9 on patch 0
    assert cornell.specular[:2].tolist() == [0.0, 0.0]  # a refused edit changes nothing
    with pytest.raises(hemirad.Error, match="F: row 0"):
        hemirad.solve(cornell, scipy.sparse.csr_array(np.full((344, 344), 0.01)))  # rows sum to 3.44
    with pytest.raises(ValueError, match=r"B: expected shape \(344, 3\)"):
        hemirad.render(cornell, np.zeros(5), "x.png")


def test_the_gil_is_released_while_f_runs():
    scene = hemirad.load(scene_path("cornell_box.obj"), subdivide=40)  # 1,934 patches, ~1 s
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    thread = threading.Thread(target=count)
    thread.start()
    started = time.perf_counter()
    hemirad.form_factors(scene, threads=1)
    elapsed = time.perf_counter() - started
    stop.set()
    thread.join()
    during = [t for t in ticks if started <= t <= started + elapsed]
    assert elapsed > 0.2
    assert len(during) > 0.3 * elapsed / 0.005  # the other thread kept running


def test_progress_is_called_and_an_exception_in_it_stops_the_computation():
    scene = hemirad.load(scene_path("cornell_box.obj"), subdivide=40)
    calls = []
    F, _ = hemirad.form_factors(scene, threads=1, progress=lambda *a: calls.append((threading.get_ident(), a)))
    assert calls and all(ident == threading.get_ident() for ident, _ in calls)  # on the calling thread
    assert calls[-1][1][0] == calls[-1][1][1] == len(scene)

    seen = []

    def stop_early(done, total, seconds):
        seen.append(done)
        raise RuntimeError("enough")

    started = time.perf_counter()
    with pytest.raises(RuntimeError, match="enough"):
        hemirad.form_factors(scene, threads=1, progress=stop_early)
    assert len(seen) == 1 and seen[0] < len(scene)
    assert time.perf_counter() - started < 0.8 * (calls[-1][1][2] + 0.5)
    F2, _ = hemirad.form_factors(scene, threads=1)  # the module is still usable
    assert (F2 != F).nnz == 0


def test_ctrl_c_cancels_a_running_computation():
    # 4,855 patches: uninterrupted, F takes about 16 s on one thread of a 2-core machine. Stopping
    # within 3 s of the start shows the cancel without a tight clock that a loaded machine would miss.
    scene = hemirad.load(scene_path("cornell_box.obj"), subdivide=25)
    timer = threading.Timer(0.2, lambda: signal.pthread_kill(threading.main_thread().ident, signal.SIGINT))
    started = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        hemirad.form_factors(scene, threads=1)
    assert time.perf_counter() - started < 3.0
    timer.join()


def test_render_writes_a_png(cornell, tmp_path):
    F, _ = hemirad.form_factors(cornell, samples=256)
    B, _ = hemirad.solve(cornell, F)
    report = hemirad.render(cornell, B, tmp_path / "image.png", size=(48, 32))
    assert report["exposure"] > 0
    data = (tmp_path / "image.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and int.from_bytes(data[16:20], "big") == 48


def test_the_example_runs(tmp_path):
    example = os.path.join(SOURCE, "examples", "room_view_factors.py")
    run = subprocess.run([sys.executable, example, "--out", str(tmp_path), "--divisions", "4"],
                         capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg"))
    assert run.returncode == 0, run.stderr
    assert "floor -> ceiling" in run.stdout
    assert (tmp_path / "room_radiosity.png").read_bytes()[:4] == b"\x89PNG"


def test_drop_below_keeps_row_sums_and_reciprocity_with_fewer_nonzeros(cornell):
    F, _ = hemirad.form_factors(cornell, threads=1, estimator="analytic")
    G, report = hemirad.form_factors(cornell, threads=1, estimator="analytic", drop_below=1e-3)
    assert G.nnz < F.nnz
    assert report["provenance"]["parameters"]["sparsified"].startswith("pairs below 0.001 dropped")
    assert np.max(np.abs(np.asarray(G.sum(axis=1)).ravel() - np.asarray(F.sum(axis=1)).ravel())) < 1e-5
    AG = scipy.sparse.diags(np.asarray(cornell.area)) @ G.astype(np.float64)
    assert abs(AG - AG.T).max() <= 1e-6 * AG.max()
    with pytest.raises(hemirad.Error, match="drop_below"):
        hemirad.form_factors(cornell, threads=1, drop_below=-1.0)


def test_a_black_scene_needs_no_rows_and_solves_to_its_emission(tmp_path):
    # issue 35 #6 and #18: F of 0 x 0 for a scene of black patches, and scipy's "index pointer size".
    scene = hemirad.load(os.path.join(SOURCE, "tests", "data", "black", "black_pair.obj"))
    F, report = hemirad.form_factors(scene, threads=1)
    assert F.shape == (2, 2) and F.nnz == 0
    assert len(report["computed"]) == 2 and not report["computed"].any()
    assert report["provenance"]["scene_hash"] != "0000000000000000"
    B, _ = hemirad.solve(scene, F)
    assert np.array_equal(B, [[1, 2, 3], [0, 0, 0]])
    hemirad.write_form_factors(tmp_path / "F.hff", F, scene)
    assert hemirad.read_form_factors(tmp_path / "F.hff", scene).shape == (2, 2)
    G, _ = hemirad.form_factors(scene, threads=1, all_rows=True)
    assert G.shape == (2, 2) and G[0, 1] > 0.19


@pytest.mark.parametrize("model", sorted(glob.glob(os.path.join(SOURCE, "tests", "data", "black", "*.obj"))))
def test_every_model_of_the_black_corpus_solves_to_its_emission(model):
    # issue 35 #6: black bodies (a mirror without Kd, glossy illum 2, relative indices, groups).
    scene = hemirad.load(model)
    n = len(scene.area)
    F, report = hemirad.form_factors(scene, threads=1)
    assert F.shape == (n, n) and F.nnz == 0 and not report["computed"].any()
    B, _ = hemirad.solve(scene, F)
    assert np.array_equal(B, scene.emission) and scene.emission.any()


def run_python(script):
    """Runs `script` in a fresh interpreter (a crash there fails the test instead of killing pytest)."""
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env=dict(os.environ, HEMIRAD_SOURCE_DIR=SOURCE))


def test_a_matrix_sharing_f_arrays_but_not_its_row_pointers_is_solved_and_written_as_given(tmp_path):
    # Issue 35 #5: G shares F's data and indices (the library's own memory) but not its row pointers:
    # the last entry of row 4 moves to row 5, a black patch whose row is empty. G is canonical and
    # differs from F in 2 entries; it must be solved and written as G, not as F.
    scene = hemirad.load(scene_path("cornell_box.obj"))
    scene.set_rho([5], [0.0, 0.0, 0.0])
    F, _ = hemirad.form_factors(scene, samples=256, threads=1)
    assert F.indptr[5] == F.indptr[6] and F.indptr[5] > F.indptr[4]  # row 5 empty, row 4 not
    indptr = F.indptr.copy()
    indptr[5] -= 1
    G = scipy.sparse.csr_array((F.data, F.indices, indptr), shape=F.shape)
    assert G.has_canonical_format and (G != F).nnz == 2
    copy = scipy.sparse.csr_array((F.data.copy(), F.indices.copy(), indptr.copy()), shape=F.shape)
    B_F, _ = hemirad.solve(scene, F)
    B_G, _ = hemirad.solve(scene, G)
    B_copy, _ = hemirad.solve(scene, copy)
    assert np.max(np.abs(B_F - B_copy)) > 1e-6  # the two matrices give different radiosities
    assert np.array_equal(B_G, B_copy)
    hemirad.write_form_factors(tmp_path / "G.hff", G, scene)
    assert (hemirad.read_form_factors(tmp_path / "G.hff", scene) != G).nnz == 0
    # The library's own F, all three arrays as it made them, still goes through in place.
    hemirad.write_form_factors(tmp_path / "F.hff", F, scene)
    assert (hemirad.read_form_factors(tmp_path / "F.hff", scene) != F).nnz == 0


def test_the_library_arrays_of_f_cannot_be_made_writable():
    # F's columns and values are used in place when the arrays passed are the library's own: sound
    # only while nobody can change that memory from Python. (Row pointers are compared by value:
    # scipy keeps its own int32 copy of them.)
    F, _ = hemirad.form_factors(hemirad.load(scene_path("unit_cube.obj")))
    for array in (F.indices, F.data):
        with pytest.raises(ValueError):
            array.setflags(write=True)


def test_render_refuses_a_bad_camera_naming_the_value():
    # Issue 35 #7: a NaN eye aborted the interpreter (an Embree assertion), so each case runs in a
    # fresh interpreter; every one must raise hemirad.Error naming the value.
    script = f"""
import numpy as np, hemirad
scene = hemirad.load({scene_path("cornell_box.obj")!r})
B = np.zeros((len(scene), 3))
for camera in [(float("nan"), 0, 0, 0, 0, 0, 40), (278, 273, -800, 278, 273, 0, 0),
               (278, 273, -800, 278, 273, 0, 200), (1, 2, 3, 1, 2, 3, 40)]:
    try:
        hemirad.render(scene, B, "never.png", camera=camera, size=(8, 8))
        print("accepted", camera)
    except hemirad.Error as e:
        print("refused:", e)
"""
    run = run_python(script)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert len(lines) == 4, run.stdout
    assert "camera eye (nan, 0, 0) is not a finite point" in lines[0]
    assert "camera field of view 0 is outside (0, 180) degrees" in lines[1]
    assert "camera field of view 200 is outside (0, 180) degrees" in lines[2]
    assert "camera eye and target coincide at (1, 2, 3)" in lines[3]


def test_crafted_csr_arrays_are_refused_before_any_use():
    # Issue 35 #10: row pointers past nnz made the module read and write past its arrays (the checked
    # error came, then a crash). The arrays are views into longer buffers whose extra values are
    # valid columns, so that an unchecked overrun would run far. Each case runs in a fresh interpreter
    # through the module's entry points, which take raw arrays; each must raise hemirad.Error.
    script = f"""
import numpy as np, hemirad
from hemirad import _hemirad
scene = hemirad.load({scene_path("cornell_box.obj")!r}, subdivide=100)
n = len(scene)
columns = np.arange(n, dtype=np.int32)
values = np.full(n, 1e-3, dtype=np.float32)
def csr(indptr, nnz=3):
    return np.array(indptr, dtype=np.int64), columns[:nnz], values[:nnz]
cases = {{
    "row pointer past nnz": csr([0, n - 1] + [3] * (n - 1)),
    "decreasing row pointers": csr([0, 2, 1] + [3] * (n - 2)),
    "first row pointer not 0": csr([-2, 1] + [3] * (n - 1)),
    "last row pointer not nnz": csr([0, 1, 2] + [2] * (n - 2)),
    "row pointers of the wrong length": csr([0, 3, 3]),
    "column out of range": (np.array([0, 1] + [1] * (n - 1), dtype=np.int64), np.array([n], dtype=np.int32), values[:1]),
    "negative column": (np.array([0, 1] + [1] * (n - 1), dtype=np.int64), np.array([-1], dtype=np.int32), values[:1]),
    "columns out of order": (np.array([0, 2] + [2] * (n - 1), dtype=np.int64), np.array([5, 4], dtype=np.int32), values[:2]),
    "data and indices of different lengths": (np.array([0, 2] + [2] * (n - 1), dtype=np.int64), columns[:2], values[:1]),
}}
for name, (indptr, indices, data) in cases.items():
    for call in ("solve", "write"):
        try:
            if call == "solve":
                _hemirad._solve(scene, indptr, indices, data, "auto", 1e-6, 100, False, None)
            else:
                _hemirad._write_form_factors("never.hff", scene, indptr, indices, data, None)
            print("accepted", name, call)
        except hemirad.Error as e:
            print("refused", name, "|", e)
print("alive")
"""
    run = run_python(script)
    assert run.returncode == 0, run.stderr[-2000:]
    lines = run.stdout.splitlines()
    assert lines[-1] == "alive" and len(lines) == 19, run.stdout
    expected = {
        "row pointer past nnz": "F: row pointer 343 of row 0 lies past the 3 entries",
        "decreasing row pointers": "F: row pointers decrease at row 1 (2, then 1)",
        "first row pointer not 0": "F: indptr starts at -2, not 0",
        "last row pointer not nnz": "F: indptr ends at 2, not at the 3 entries",
        "row pointers of the wrong length": "F: indptr has 3 row pointers, expected 345 for 344 patches",
        "column out of range": "F: row 0 has a column out of range or out of order (344)",
        "negative column": "F: row 0 has a column out of range or out of order (-1)",
        "columns out of order": "F: row 0 has a column out of range or out of order (4)",
        "data and indices of different lengths": "F: 1 values for 2 column indices",
    }
    for line in lines[:-1]:  # each case twice: solve, then write
        name, message = line[len("refused "):].split(" | ")
        assert line.startswith("refused ") and message == expected[name], line


def test_crafted_scipy_matrices_are_refused_by_the_python_layer_too():
    # scipy takes these (its default check is O(1)); its own canonicalisation would then run past the
    # arrays, so hemirad.solve checks the structure first. In a fresh interpreter, as above.
    script = f"""
import numpy as np, scipy.sparse, hemirad
scene = hemirad.load({scene_path("cornell_box.obj")!r}, subdivide=100)
n = len(scene)
columns = np.arange(n, dtype=np.int32)
for indptr in ([0, n - 1] + [3] * (n - 1), [0, 2, 1] + [3] * (n - 2)):
    F = scipy.sparse.csr_array((np.full(3, 1e-3, dtype=np.float32), columns[:3], np.array(indptr)), shape=(n, n))
    try:
        hemirad.solve(scene, F)
        print("accepted")
    except ValueError as e:
        print("refused |", e)
"""
    run = run_python(script)
    assert run.returncode == 0, run.stderr[-2000:]
    lines = run.stdout.splitlines()
    assert len(lines) == 2 and all(line.startswith("refused | F: ") for line in lines), run.stdout


def test_thermal_three_surface_enclosure_and_gebhart():
    # The unit cube: floor at 600 K, ceiling at 300 K, the four walls adiabatic (reradiating): the
    # three-surface closed form of physics.md section 8.
    cube = hemirad.load(scene_path("unit_cube.obj"))
    F, _ = hemirad.form_factors(cube, all_rows=True)
    n = len(cube)
    up = cube.normal[:, 1]
    floor, ceiling = int(np.argmax(up)), int(np.argmin(up))
    eps = np.full(n, 0.3)
    eps[floor], eps[ceiling] = 0.7, 0.4
    T = np.full(n, np.nan)
    T[floor], T[ceiling] = 600.0, 300.0
    q = np.where(np.isnan(T), 0.0, np.nan)
    result = hemirad.thermal(cube, F, eps, temperature=T, flux=q)
    sigma, opp, adj = 5.670374419e-8, 0.1998248957, 0.2000437761
    R1, R2 = 0.3 / 0.7, 0.6 / 0.4
    expected = sigma * (600.0**4 - 300.0**4) / (R1 + 1 / (opp + 1 / (1 / (4 * adj) + 1 / (4 * adj))) + R2)
    assert abs(result["Q"][floor] - expected) < 1e-3 * expected
    assert result["balance"] < 1e-9
    assert np.all(np.abs(np.delete(result["q"], [floor, ceiling])) == 0.0)
    GR, B, nodes = hemirad.conductors(cube, F, eps)
    assert GR.shape == (n + 1, n + 1) and len(nodes) == n
    assert abs(GR - GR.T).max() == 0.0
    assert np.allclose(np.asarray(B[:n].sum(axis=1)).ravel(), 1.0, atol=1e-5)  # closed: nothing escapes
    # The two routes to the Gebhart factors give the same conductors.
    GR_columns, _, _ = hemirad.conductors(cube, F, eps, method="columns")
    GR_dense, _, _ = hemirad.conductors(cube, F, eps, method="dense")
    assert abs(GR_columns - GR_dense).max() <= 1e-9 * GR_dense.max()
    with pytest.raises(hemirad.Error, match="method: expected 'auto', 'columns' or 'dense'"):
        hemirad.conductors(cube, F, eps, method="fast")
    with pytest.raises(ValueError, match="give exactly one of temperature and flux"):
        hemirad.thermal(cube, F, eps, temperature=np.full(n, 300.0), flux=np.zeros(n))
    with pytest.raises(hemirad.Error, match="emissivity 0.7 \\+ specular reflectance 0.5"):
        hemirad.thermal(cube, F, eps, specular=np.where(np.arange(n) == floor, 0.5, 0.0), temperature=T, flux=q)
    # Two IR bands; the floor a mirror (s = 0.5) below 4 um only: that band on its own F.
    band_eps = np.vstack([eps, eps])
    band_eps[0, floor] = 0.3  # leaves room for the mirror (s = 0.5 here: the MTL reflects 0.5)
    band_s = np.zeros((2, n))
    plain = hemirad.thermal(cube, F, eps, temperature=T, flux=q, band_limits_um=[4.0], band_emissivity=band_eps)
    same = hemirad.thermal(cube, F, eps, temperature=T, flux=q, band_limits_um=[4.0], band_emissivity=band_eps,
                           band_specular=band_s)
    assert np.array_equal(same["T"], plain["T"], equal_nan=True)
    band_s[0, floor] = 0.5
    with pytest.raises(hemirad.Error, match="IR band 1's specular reflectances differ"):
        hemirad.thermal(cube, F, eps, temperature=T, flux=q, band_limits_um=[4.0], band_emissivity=band_eps,
                        band_specular=band_s)
    mirrored = hemirad.load(scene_path("unit_cube.obj"))
    mirrored.set_specular([floor], 0.5)
    F_mirror, _ = hemirad.form_factors(mirrored, all_rows=True)
    polished = hemirad.thermal(cube, F, eps, temperature=T, flux=q, band_limits_um=[4.0], band_emissivity=band_eps,
                               band_specular=band_s, band_F=[F_mirror, None])
    assert polished["balance"] < 1e-9
    walls = [i for i in range(n) if i not in (floor, ceiling)]
    assert np.all(np.abs(polished["T"][walls] - plain["T"][walls]) > 1e-3)  # the mirror is felt
    with pytest.raises(hemirad.Error, match="band_F: expected 2 matrices"):
        hemirad.thermal(cube, F, eps, temperature=T, flux=q, band_limits_um=[4.0], band_emissivity=band_eps,
                        band_specular=band_s, band_F=[F_mirror])


def test_thermal_sun_and_bands():
    # One plate alone in the sun (F = 0): eps sigma T^4 = absorbed + eps sigma T_env^4; with two bands of
    # equal emissivity the same temperature.
    plates = hemirad.load(scene_path("parallel_plates.obj"))
    n = len(plates)
    F = scipy.sparse.csr_matrix((n, n), dtype=np.float32)
    sigma = 5.670374419e-8
    result = hemirad.thermal(plates, F, 0.8, flux=np.zeros(n), environment=3.0, absorbed=np.full(n, 272.2))
    expected = (272.2 / (0.8 * sigma) + 3.0**4) ** 0.25
    assert np.allclose(result["T"], expected, rtol=1e-12)
    banded = hemirad.thermal(plates, F, 0.8, flux=np.zeros(n), environment=3.0, absorbed=np.full(n, 272.2),
                             band_limits_um=[5.0], band_emissivity=np.full((2, n), 0.8))
    assert np.allclose(banded["T"], expected, rtol=1e-11)
    with pytest.raises(hemirad.Error, match="band_emissivity: expected shape"):
        hemirad.thermal(plates, F, 0.8, flux=np.zeros(n), band_limits_um=[5.0], band_emissivity=np.full((3, n), 0.8))
    # Emissivity against temperature on every plate (a mask): eps(T) (sigma T^4 - sigma 3^4) = 272.2,
    # by bisection here.
    curve_T, curve_eps = [200.0, 400.0], [0.5, 0.9]
    curved = hemirad.thermal(plates, F, 0.8, flux=np.zeros(n), environment=3.0, absorbed=np.full(n, 272.2),
                             emissivity_curves=[(np.ones(n, dtype=bool), curve_T, curve_eps)])
    lo, hi = 3.0, 1000.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if np.interp(mid, curve_T, curve_eps) * sigma * (mid**4 - 3.0**4) < 272.2:
            lo = mid
        else:
            hi = mid
    assert np.allclose(curved["T"], 0.5 * (lo + hi), rtol=1e-10)
    with pytest.raises(ValueError, match="given two curves"):
        hemirad.thermal(plates, F, 0.8, flux=np.zeros(n), emissivity_curves=[([0], curve_T, curve_eps), ([0], curve_T, curve_eps)])
    with pytest.raises(hemirad.Error, match="emissivity curve 1"):
        hemirad.thermal(plates, F, 0.8, flux=np.zeros(n), emissivity_curves=[([0], [400.0, 200.0], curve_eps)])


def test_sensor_factors_under_a_plate():
    # A sensor at the middle of the bottom plate facing up sees the top plate (1 above, a unit
    # square) by the closed form for a point under a rectangle's corner, four times; the rest is sky.
    plates = hemirad.load(scene_path("parallel_plates.obj"))

    def corner(A):  # a point under the corner of an A x A square (in units of its distance)
        t = A / np.sqrt(1 + A * A)
        return 2 * t * np.arctan(t) / (2 * np.pi)

    positions, normals, names = hemirad.sensor_grid(plates, "bottom_plate", 0.5)
    assert positions.shape == (4, 3) and normals.shape == (4, 3) and len(names) == 4
    assert np.all(normals == [0, 0, 1]) and np.all(positions[:, 2] == 0)
    out = hemirad.sensor_factors(plates, [[0.5, 0.5, 0.0], [0.5, 0.5, 0.5]], [[0, 0, 1], [0, 0, -2]])
    F = out["F"]
    assert isinstance(F, scipy.sparse.csr_array) and F.shape == (2, 2) and F.dtype == np.float64
    assert F[0, 1] == pytest.approx(4 * corner(0.5), rel=1e-12)
    assert F[0, 0] == 0.0  # the plate it lies on
    assert out["sky_view_factor"][0] == pytest.approx(1 - 4 * corner(0.5), rel=1e-12)
    # Facing down, 0.5 above the bottom plate: it, and no sky below it.
    assert F[1, 0] == pytest.approx(4 * corner(1.0), rel=1e-12) and F[1, 1] == 0.0
    assert out["sky_view_factor"][1] == pytest.approx(1 - 4 * corner(1.0), rel=1e-12)
    with pytest.raises(ValueError):
        hemirad.sensor_factors(plates, [[0, 0, 0]], [[0, 0, 0]])
    with pytest.raises(ValueError):
        hemirad.sensor_factors(plates, [[0, 0, 0, 1]], [[0, 0, 1, 0]])
    with pytest.raises(hemirad.Error):
        hemirad.sensor_grid(plates, "roof", 0.5)
    assert out["estimator"] == "exact" and "within the budget" in out["why"]
    # By rays: within their error of the closed form; each row and its sky sum to 1 (no back seen).
    rays = hemirad.sensor_factors(plates, [[0.5, 0.5, 0.0]], [[0, 0, 1]], estimator="rays", rays=16384)
    assert rays["estimator"] == "rays" and rays["why"] == "rays, as asked"
    assert abs(rays["F"][0, 1] - 4 * corner(0.5)) < 2e-3
    assert rays["F"][0, 0] == 0.0
    assert rays["F"].sum() + rays["sky_view_factor"][0] == pytest.approx(1.0, abs=1e-14)
    with pytest.raises(ValueError):
        hemirad.sensor_factors(plates, [[0, 0, 0]], [[0, 0, 1]], estimator="fast")
    with pytest.raises(ValueError):
        hemirad.sensor_factors(plates, [[0, 0, 0]], [[0, 0, 1]], estimator="rays", rays=0)


def test_sensor_factors_through_a_mirror():
    # mirror_pair: P1 [0,1]^2 and P2 [1,2]x[0,1] on z = 0 facing up, under a mirror [0.5,1.5]x[0,1]
    # at z = 0.5 facing down (s = 0.9). A sensor at P1's middle facing up lies in both plates' plane
    # (no direct term) and sees the mirror; in it, its image (0.5, 0.5, 1) facing down sees P1's
    # part x in [0.5, 1] and all of P2 (the aperture's cone covers x in [0.5, 2.5], y in [-0.5, 1.5]
    # at z = 0); the rest of the cone is sky. Each by Howell's B-3 (a point under a rectangle's corner).
    scene = hemirad.load(scene_path("mirror_pair.obj"))

    def b3(a, b, c):
        A, B = a / c, b / c
        return (A / np.sqrt(1 + A * A) * np.arctan(B / np.sqrt(1 + A * A)) +
                B / np.sqrt(1 + B * B) * np.arctan(A / np.sqrt(1 + B * B))) / (2 * np.pi)

    s = 0.9
    mirror = 2 * b3(1.0, 0.5, 0.5)
    p1 = 2 * b3(0.5, 0.5, 1.0)
    p2 = 2 * (b3(1.5, 0.5, 1.0) - b3(0.5, 0.5, 1.0))
    out = hemirad.sensor_factors(scene, [[0.5, 0.5, 0.0]], [[0, 0, 1]])
    assert out["mirrors"].startswith("followed by images")
    F = out["F"]
    assert F[0, 2] == pytest.approx(mirror, rel=1e-12)
    assert F[0, 0] == pytest.approx(s * p1, rel=1e-10)
    assert F[0, 1] == pytest.approx(s * p2, rel=1e-10)
    assert out["direct"][0] == pytest.approx(1 - mirror, rel=1e-12)
    assert out["through_mirrors"][0] == pytest.approx(s * (mirror - p1 - p2), rel=1e-9)
    assert out["sky_view_factor"][0] == pytest.approx(out["direct"][0] + out["through_mirrors"][0], rel=1e-15)
    # No mirrors followed past depth 0: the mirror's own factor only, no sky in it.
    flat = hemirad.sensor_factors(scene, [[0.5, 0.5, 0.0]], [[0, 0, 1]], max_depth=0)
    assert flat["F"][0, 0] == 0.0 and flat["F"][0, 1] == 0.0
    assert flat["through_mirrors"][0] == pytest.approx(s * mirror, rel=1e-12)  # cut off: counted as sky
    flat_rays = hemirad.sensor_factors(scene, [[0.5, 0.5, 0.0]], [[0, 0, 1]], estimator="rays", rays=65536, max_depth=0)
    assert abs(flat_rays["through_mirrors"][0] - s * mirror) < 3e-3  # by rays too
    # By rays, reflected at the mirror: within their error.
    rays = hemirad.sensor_factors(scene, [[0.5, 0.5, 0.0]], [[0, 0, 1]], estimator="rays", rays=65536)
    assert rays["mirrors"].startswith("followed by rays")
    assert abs(rays["F"][0, 1] - s * p2) < 3e-3 and abs(rays["through_mirrors"][0] - s * (mirror - p1 - p2)) < 3e-3


def test_sensor_sky_coefficients():
    # Above everything and facing up: each cell's coefficient is its horizontal weight; under the
    # mirror of mirror_pair, a sensor sees cells in it (first reflections) and fewer straight.
    plates = hemirad.load(scene_path("parallel_plates.obj"))
    cells = hemirad.sky_coefficients(plates, 1, 2)["cells"]
    open_sky = hemirad.sensor_sky_coefficients(plates, [[0.5, 0.5, 5.0]], [[0, 0, 1]], 1, 2)
    assert open_sky["direct"].shape == (1, 145) and open_sky["mirrored"] is None
    assert np.allclose(open_sky["direct"][0], cells["horizontal"], rtol=0, atol=1e-15)
    mirrored = hemirad.load(scene_path("mirror_pair.obj"))
    under = hemirad.sensor_sky_coefficients(mirrored, [[1.0, 0.5, 0.25], [1.0, 0.5, 0.25]], [[0, 0, 1], [1, 0, 0]], 1, 2)
    assert under["mirrored"].shape == (2, 145)
    assert under["direct"][0].sum() < cells["horizontal"].sum()  # the mirror overhead hides the zenith
    with pytest.raises(ValueError):
        hemirad.sensor_sky_coefficients(plates, [[0, 0, 0]], [[0, 0, 0]])


def test_sun_and_one_hour_of_irradiance_as_the_command_line():
    # The solar position of the CLI's --sun-time, the sunlit fractions, and one hour's irradiance
    # equal to hemirad irradiance's CSV for the same scene, sun and sky.
    p = hemirad.solar_position("2024-06-21T12:00:00+02:00", 48.14, 11.58)
    assert 60.6 < p["elevation"] < 61.6 and 141.5 < p["azimuth"] < 142.6  # 10:00 UTC, before solar noon
    to_sun = hemirad.sun_direction(p)
    assert to_sun.shape == (3,) and abs(np.linalg.norm(to_sun) - 1) < 1e-12 and to_sun[2] > 0.8
    cornell = hemirad.load(scene_path("cornell_box.obj"))
    d = np.array([0.3, 1.0, 0.2])
    lit = hemirad.sunlit_fractions(cornell, d)
    assert lit.shape == (len(cornell),) and np.all((lit >= 0) & (lit <= 1))
    # Many suns at once (one shadow set-up): each row as the sun alone.
    suns = np.array([d, [0.1, 1.0, -0.3], [-0.5, 0.8, 0.4]])
    many = hemirad.sunlit_fractions(cornell, suns)
    assert many.shape == (3, len(cornell))
    for k in range(3):
        assert np.array_equal(many[k], hemirad.sunlit_fractions(cornell, suns[k]))
    with pytest.raises(ValueError):
        hemirad.sunlit_fractions(cornell, np.zeros((2, 3)))
    F, _ = hemirad.form_factors(cornell, all_rows=True)
    out = hemirad.irradiance(cornell, F, d, 800.0, 100.0)
    assert out["balance"] < 1e-9
    assert np.any(out["radiosity"] > 0)
    csv = os.path.join(os.environ.get("TMPDIR", "/tmp"), "hemirad-py-irradiance.csv")
    r = subprocess.run([os.environ["HEMIRAD_BINARY"], "irradiance", scene_path("cornell_box.obj"), "--sun-direction",
                        "0.3,1,0.2", "--dni", "800", "--dhi", "100", "-o", csv, "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    table = np.genfromtxt(csv, delimiter=",", skip_header=1, usecols=(2, 3, 4, 5, 6))
    for k, name in enumerate(["direct_sun", "direct_sky", "reflected", "total", "absorbed"]):
        assert np.allclose(out[name], table[:, k], rtol=1e-9, atol=1e-9), name
    # The mirror box: the reflected sun as the command line's --glare reports it, spots brightest first.
    mirror_box = hemirad.load(scene_path("cornell_mirror.obj"))
    glare = hemirad.reflected_sun(mirror_box, [1.0, 0.5, -1.0], 800.0)  # through the open front onto the mirror wall
    assert glare["irradiance"].shape == (len(mirror_box),)
    spots = glare["spots"]
    assert len(spots["mirror"]) == len(spots["receiver"]) == len(spots["peak"]) > 0
    assert np.all(np.diff(spots["irradiance"]) <= 0)
    for m, r, e in zip(spots["mirror"], spots["receiver"], spots["irradiance"]):
        assert mirror_box.specular[m] > 0 and e > 0
    # Many suns from one set-up: each as that sun alone (DNI per sun, or one for all).
    suns = np.array([[1.0, 0.5, -1.0], [0.8, 0.6, -1.2], [1.0, 0.5, -1.0]])
    many = hemirad.reflected_sun(mirror_box, suns, [800.0, 600.0, 400.0])
    assert isinstance(many, list) and len(many) == 3
    for k, dni in enumerate([800.0, 600.0, 400.0]):
        alone = hemirad.reflected_sun(mirror_box, suns[k], dni)
        assert np.array_equal(many[k]["irradiance"], alone["irradiance"])
        assert np.array_equal(many[k]["spots"]["peak"], alone["spots"]["peak"])
    assert np.allclose(many[2]["irradiance"], 0.5 * glare["irradiance"], rtol=1e-12, atol=0)
    assert len(hemirad.reflected_sun(mirror_box, suns, 800.0)) == 3
    with pytest.raises(ValueError, match="one per sun"):
        hemirad.reflected_sun(mirror_box, suns, [800.0, 600.0])
    with pytest.raises(ValueError, match=r"sun 1\) must be a finite"):
        hemirad.reflected_sun(mirror_box, suns, [800.0, -1.0, 400.0])
    # With the mirror: the reflected sun arrives first, as the command line's reflected_sun column.
    Fm, _ = hemirad.form_factors(mirror_box, all_rows=True)
    hour = hemirad.irradiance(mirror_box, Fm, [1.0, 0.5, -1.0], 800.0, 100.0)
    assert hour["balance"] < 1e-9 and np.any(hour["reflected_sun"] > 0)
    r = subprocess.run([os.environ["HEMIRAD_BINARY"], "irradiance", scene_path("cornell_mirror.obj"), "--sun-direction",
                        "1,0.5,-1", "--dni", "800", "--dhi", "100", "-o", csv, "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    table = np.genfromtxt(csv, delimiter=",", skip_header=1, usecols=(5, 7))
    assert np.allclose(hour["total"], table[:, 0], rtol=1e-9, atol=1e-9)
    assert np.allclose(hour["reflected_sun"], table[:, 1], rtol=1e-12, atol=0)
    with pytest.raises(ValueError):
        hemirad.sunlit_fractions(cornell, [0, 0, 0])
    with pytest.raises(hemirad.Error):
        hemirad.solar_position("2024-13-01T00:00", 0, 0)


def test_a_sky_model_through_the_daylight_coefficients_as_the_command_line():
    # Perez's sky on the mirror box (y up, the open front toward +z): the cells' radiance puts the DHI
    # on a horizontal plane, the direct sky is the coefficients times it, the sky through the mirror
    # lands, the power balances, and the hour equals hemirad irradiance --sky perez's CSV.
    box = hemirad.load(scene_path("cornell_mirror.obj"))
    up = (0, 1, 0)
    sky = hemirad.sky_coefficients(box, 1, 1, up=up)
    cells = sky["cells"]
    assert sky["direct"].shape == (len(box), 145) and sky["mirrored"].shape == (len(box), 145)
    assert abs(cells["solid_angle"].sum() - 2 * np.pi) < 1e-12 and cells["altitude_high"][-1] == 90.0
    to_sun = np.array([0.2, 1.0, 0.5])
    L = hemirad.sky_radiance("perez", to_sun, 700.0, 100.0, 1, 1, day_of_year=172, up=up)
    assert L.shape == (145,) and np.all(L >= 0) and abs(cells["horizontal"] @ L - 100.0) < 1e-10
    F, _ = hemirad.form_factors(box, all_rows=True)
    hour = hemirad.irradiance(box, F, to_sun, 700.0, 100.0, sky="perez", coefficients=sky, day_of_year=172, up=up)
    assert hour["balance"] < 1e-9
    assert np.allclose(hour["direct_sky"], sky["direct"] @ L, rtol=1e-12, atol=1e-12)
    assert np.any(hour["reflected_sky"] > 0)
    csv = os.path.join(os.environ.get("TMPDIR", "/tmp"), "hemirad-py-sky.csv")
    r = subprocess.run([os.environ["HEMIRAD_BINARY"], "irradiance", scene_path("cornell_mirror.obj"), "--up", "y",
                        "--sun-time", "2026-06-21T10:00Z", "--latitude", "48.1", "--longitude", "11.6", "--dni", "700",
                        "--dhi", "100", "--sky", "perez", "--sky-subdivision", "1", "-o", csv, "--quiet"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    table = np.genfromtxt(csv, delimiter=",", skip_header=1, usecols=(3, 5, 8))
    at = hemirad.sun_direction(hemirad.solar_position("2026-06-21T10:00Z", 48.1, 11.6), up=up)
    same = hemirad.irradiance(box, F, at, 700.0, 100.0, sky="perez", coefficients=sky, day_of_year=172, up=up)
    for k, name in enumerate(["direct_sky", "total", "reflected_sky"]):
        assert np.allclose(same[name], table[:, k], rtol=1e-9, atol=1e-9), name
    with pytest.raises(ValueError):
        hemirad.irradiance(box, F, to_sun, 700.0, 100.0, sky="perez", coefficients=sky, sky_view=np.zeros(len(box)))
    with pytest.raises(hemirad.Error):
        hemirad.sky_radiance("clear", to_sun, 700.0, 100.0)


def test_sky_view_factors_of_plates():
    # Two unit squares facing each other at distance 1: each sees the other (C-11, 0.199825) and the
    # rest is sky; the same as the command line's.
    plates = hemirad.load(scene_path("parallel_plates.obj"))
    sky = hemirad.sky_view_factors(plates)
    assert np.allclose(sky["sky_view_factor"], 1 - 0.1998248957, atol=1e-5)
    assert np.all(sky["through_mirrors"] == 0.0)
    with pytest.raises(TypeError):
        hemirad.sky_view_factors(plates, resolution=64)
