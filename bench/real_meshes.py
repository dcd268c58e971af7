#!/usr/bin/env python3
"""Form factors on meshes users bring (issue 34): time against error on non-conforming districts.

Cases, each a whole `hemirad formfactors ... --threads 1` process (wall time, its own peak RSS by
GNU time), on scenes from scenes/generators/district.py (ground cut around the footprints: T-
junctions, corners on edges, slivers; walls in strips; flush roofs):
- district1k (1,001 triangles, open): the default, --pairs whole and --pair-digits 4 --origins 16
  against a converged reference (--pairs whole --pair-digits 4: every pair by its contour integral
  less its hidden part to 1e-6, on 2 threads): the largest entry error, the row sums' (1 - sky view factor) largest and
  area-weighted error, reciprocity (largest |A_i F_ij - A_j F_ji| / max over pairs);
- district1k_closed (the same inside an inward box): every row of F should sum to 1;
- district25k (25,379 triangles): the default's time, memory and estimator (the report's note);
- two concentric faceted spheres (an icosphere of 1,280 triangles inside one of radius 2, a
  closed enclosure with an occluder): the outer sphere's rows should sum to 1.

Usage: bench/real_meshes.py BUILD_DIR [CASES...]   (cases: district1k closed1k district25k spheres;
default all). Prints Markdown (make bench writes it to results/real_meshes.md).
"""

import os
import subprocess
import sys
import tempfile

import numpy as np

from formfactor_process import timed

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REFERENCE = ["--pairs", "whole", "--pair-digits", "4"]


def areas(obj):
    vertices, result = [], []
    for line in open(obj):
        parts = line.split()
        if parts and parts[0] == "v":
            vertices.append([float(v) for v in parts[1:4]])
        elif parts and parts[0] == "f":
            p = np.array([vertices[int(t.split("/")[0]) - 1] for t in parts[1:]])
            n = sum(np.cross(p[k], p[(k + 1) % len(p)]) for k in range(len(p)))
            result.append(0.5 * np.linalg.norm(n))
    return np.array(result)


def reciprocity(F, A):
    S = (F.multiply(A[:, None])).tocsr()
    D = abs(S - S.T).tocoo()
    M = abs(S).maximum(abs(S.T)).tocsr()
    worst = 0.0
    for i, j, d in zip(D.row, D.col, D.data):
        if d > 0:
            worst = max(worst, d / M[i, j])
    return worst


def row_sums(F):
    return np.asarray(F.sum(axis=1)).ravel()


def note_of(report):
    for line in report.splitlines():
        if "estimator auto" in line:
            return line.split("form factors: ", 1)[-1]
    return ""


def icosphere(subdivisions, radius, inward):
    """Triangles of an icosphere (20 x 4^subdivisions), wound outward or inward."""
    t = (1 + 5 ** 0.5) / 2
    v = [np.array(p, float) for p in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
                                      (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7),
         (9, 8, 1)]
    v = [p / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        cache, out = {}, []

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = v[a] + v[b]
                v.append(m / np.linalg.norm(m))
                cache[key] = len(v) - 1
            return cache[key]
        for a, b, c in f:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = out
    tris = [[radius * v[a], radius * v[b], radius * v[c]] for a, b, c in f]
    return [[t[0], t[2], t[1]] for t in tris] if inward else tris


def write_spheres(folder):
    path = os.path.join(folder, "spheres.obj")
    with open(os.path.join(folder, "spheres.mtl"), "w") as m:
        m.write("newmtl grey\nKd 0.5 0.5 0.5\n")
    with open(path, "w") as out:
        out.write("mtllib spheres.mtl\nusemtl grey\n")
        k = 1
        for name, tris in (("inner", icosphere(3, 1.0, False)), ("outer", icosphere(3, 2.0, True))):
            out.write("o %s\n" % name)
            for t in tris:
                for p in t:
                    out.write("v %.17g %.17g %.17g\n" % tuple(p))
                out.write("f %d %d %d\n" % (k, k + 1, k + 2))
                k += 3
    return path


def fmt(x):
    return "%.2g" % x if x else "0"


def main():
    global hemirad
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    cases = sys.argv[2:] or ["district1k", "closed1k", "district25k", "spheres"]
    exe = os.path.join(build, "hemirad")
    sys.path.insert(0, os.path.join(build, "python"))
    import hemirad
    work = tempfile.mkdtemp(prefix="real_meshes_")
    generator = os.path.join(ROOT, "scenes", "generators", "district.py")
    print("# Form factors on meshes users bring (issue 34)\n")
    print("`hemirad formfactors SCENE -o F.hff --threads 1` per row, a whole process each (load, F, write):\n")
    print("| scene | settings | seconds | peak MiB | nonzeros | largest entry error | row sums: largest / area-weighted error | reciprocity (largest) |")
    print("|---|---|---|---|---|---|---|---|")
    notes = []
    if "district1k" in cases:
        subprocess.run(["/usr/bin/python3", generator, work, "--preset", "1k"], check=True, stdout=subprocess.DEVNULL)
        scene = os.path.join(work, "district1k.obj")
        A = areas(scene)
        ref_path = os.path.join(work, "ref.hff")
        ref_seconds, ref_peak, _ = timed(exe, scene, ref_path, REFERENCE, threads=2)
        R = hemirad.read_form_factors(ref_path).astype(np.float64).tocsr()
        print("| district1k | %s (the reference, 2 threads) | %.1f | %.0f | %d | | | %s |" % (
            " ".join(REFERENCE), ref_seconds, ref_peak, R.nnz, fmt(reciprocity(R, A))))
        for label, extra in (("default", []), ("--pairs whole", ["--pairs", "whole"]),
                             ("--pair-digits 4 --origins 16", ["--pair-digits", "4", "--origins", "16"])):
            out = os.path.join(work, "d.hff")
            seconds, peak, report = timed(exe, scene, out, extra)
            F = hemirad.read_form_factors(out).astype(np.float64).tocsr()
            entry = abs(F - R).max()
            d = abs(row_sums(F) - row_sums(R))
            print("| district1k | %s | %.1f | %.0f | %d | %s | %s / %s | %s |" % (
                label, seconds, peak, F.nnz, fmt(entry), fmt(d.max()), fmt((A * d).sum() / A.sum()),
                fmt(reciprocity(F, A))))
            if label == "default":
                notes.append("district1k: " + note_of(report))
    if "closed1k" in cases:
        subprocess.run(["/usr/bin/python3", generator, work, "--preset", "1k", "--closed"], check=True,
                       stdout=subprocess.DEVNULL)
        scene = os.path.join(work, "district1k_closed.obj")
        A = areas(scene)
        out = os.path.join(work, "c.hff")
        seconds, peak, _ = timed(exe, scene, out, [])
        F = hemirad.read_form_factors(out).astype(np.float64).tocsr()
        d = abs(row_sums(F) - 1)
        print("| district1k_closed | default | %.1f | %.0f | %d | (closure) | %s / %s (against 1) | %s |" % (
            seconds, peak, F.nnz, fmt(d.max()), fmt((A * d).sum() / A.sum()), fmt(reciprocity(F, A))))
    if "district25k" in cases:
        subprocess.run(["/usr/bin/python3", generator, work, "--preset", "25k"], check=True, stdout=subprocess.DEVNULL)
        scene = os.path.join(work, "district25k.obj")
        out = os.path.join(work, "d25.hff")
        seconds, peak, report = timed(exe, scene, out, [])
        F = hemirad.read_form_factors(out).astype(np.float64).tocsr()
        print("| district25k | default | %.1f | %.0f | %d | | | |" % (seconds, peak, F.nnz))
        notes.append("district25k: " + note_of(report))
    if "spheres" in cases:
        scene = write_spheres(work)
        out = os.path.join(work, "s.hff")
        seconds, peak, _ = timed(exe, scene, out, [])
        F = hemirad.read_form_factors(out).astype(np.float64).tocsr()
        outer = row_sums(F)[1280:]
        print("| spheres (2 x 1,280) | default | %.1f | %.0f | %d | (closure) | outer rows %.5f .. %.5f (max error %s) | |" % (
            seconds, peak, F.nnz, outer.min(), outer.max(), fmt(abs(outer - 1).max())))
    print()
    for n in notes:
        print("- " + n)


if __name__ == "__main__":
    main()
