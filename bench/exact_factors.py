#!/usr/bin/env python3
"""Exact form factors against closed forms (issue 16): time, error and peak memory on one thread.

Cases, each a whole `hemirad formfactors ... --threads 1` process (wall time, its own peak RSS by
GNU time, F's size in memory):
- the closed unit cube, n x n patches per face (n = 8, 16, 32): the worst opposite and adjacent
  wall-to-wall factors against their closed forms (Howell C-11 and C-14);
- two parallel unit plates at distance 1 with a 0.5 x 0.5 blocker half-way (n x n patches per plate,
  n/2 x n/2 on the blocker, one-sided, facing the emitter): the plate-to-plate factors both ways
  against superposition (from each emitter point, B-3 of the receiver minus B-3 of the blocker's
  shadow on it, integrated by composite Gauss-Legendre to ~1e-13);
- the Cornell box subdivided at 60 mm: the mean per-row sum |F_ij - F_ref,ij| against a reference
  run (--pair-digits 5 --origins 64).
Each case runs the default settings and the accuracy setting (--pair-digits 4). View3D's figures
are issue 16's (NIST View3D built with -O3, one thread, binary output, on this VM class).

Usage: bench/exact_factors.py BUILD_DIR [CASES...]   (cases: cube8 cube16 cube32 plates4 plates16
plates32 cornell60; default all). Prints Markdown (make bench writes it to results/exact_factors.md).
"""

import math
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

from formfactor_process import timed

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CUBE_OPPOSITE = 0.19982489569838746  # C-11(1, 1, 1)
CUBE_ADJACENT = 0.20004377607540316  # C-14(1, 1, 1)
SETTINGS = [("default", []), ("--pair-digits 4", ["--pair-digits", "4"])]
# Issue 16's View3D figures: (seconds, opposite error, adjacent error), default and eps = 1e-5.
VIEW3D = {8: ((0.04, 1.3e-5, 3.2e-6), (0.05, 4.1e-7, 1.1e-7)),
          16: ((0.34, 7.2e-6, 1.8e-6), (0.34, 2.0e-7, 5.3e-8)),
          32: ((6.9, 4.0e-6, 9.9e-7), (6.3, 3.0e-8, 7.7e-9))}


def read_f(path):
    return hemirad.read_form_factors(path).astype(np.float64)


def polygons(obj):
    """The faces of an OBJ as arrays of corner positions."""
    vertices, faces = [], []
    for line in open(obj):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append([float(v) for v in parts[1:4]])
        elif parts[0] == "f":
            faces.append([int(p.split("/")[0]) - 1 for p in parts[1:]])
    vertices = np.array(vertices)
    return [vertices[f] for f in faces]


def cube_errors(faces, F):
    """Worst |opposite - C-11| and |adjacent - C-14| over the cube's wall pairs (faces: polygons())."""
    wall = []
    for p in faces:
        c = p.mean(axis=0)
        axis = int(np.argmax(np.ptp(p, axis=0) < 1e-12))
        wall.append(2 * axis + int(c[axis] > 0.5))
    wall = np.array(wall)
    worst = [0.0, 0.0]
    for a in range(6):
        rows = F[wall == a]
        count = rows.shape[0]
        for b in range(6):
            if a == b:
                continue
            value = rows[:, np.flatnonzero(wall == b)].sum() / count
            opposite = a // 2 == b // 2
            error = abs(value - (CUBE_OPPOSITE if opposite else CUBE_ADJACENT))
            worst[0 if opposite else 1] = max(worst[0 if opposite else 1], error)
    return worst


def write_cube(folder, n):
    path = os.path.join(folder, "cube%d.obj" % n)
    subprocess.run([HEMIRAD, "subdivide", os.path.join(ROOT, "scenes/unit_cube.obj"), "-o", path, "--max-edge",
                    repr(1.0 / n), "--quiet"], check=True)
    return path


def write_plates(folder, n):
    """Emitter z = 0 facing +z, receiver z = 1 facing -z, both [-0.5, 0.5]^2 in n x n quads; the
    blocker z = 0.5, [-0.25, 0.25]^2 in n/2 x n/2 quads facing -z."""
    path = os.path.join(folder, "plates%d.obj" % n)
    lines = ["mtllib plates%d.mtl" % n]
    count = 0

    def grid(name, z, half, k, up):
        nonlocal count
        lines.append("o " + name)
        lines.append("usemtl grey")
        for a in range(k):
            for b in range(k):
                x0, x1 = -half + 2 * half * a / k, -half + 2 * half * (a + 1) / k
                y0, y1 = -half + 2 * half * b / k, -half + 2 * half * (b + 1) / k
                corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
                if not up:
                    corners.reverse()
                for x, y in corners:
                    lines.append("v %.17g %.17g %.17g" % (x, y, z))
                lines.append("f %d %d %d %d" % (count + 1, count + 2, count + 3, count + 4))
                count += 4

    grid("emitter", 0.0, 0.5, n, True)
    grid("receiver", 1.0, 0.5, n, False)
    grid("blocker", 0.5, 0.25, max(1, n // 2), False)
    open(path, "w").write("\n".join(lines) + "\n")
    open(path[:-4] + ".mtl", "w").write("newmtl grey\nKd 0.5 0.5 0.5\nKs 0 0 0\nillum 1\n")
    return path


def point_rectangle(x0, x1, y0, y1, c):
    """Howell B-3 by corners: the factor from a point to the parallel rectangle [x0, x1] x [y0, y1]
    (relative to the point) at distance c (vectorised over the point)."""
    def corner(a, b):
        sa, sb = np.sign(a), np.sign(b)
        a, b = np.abs(a), np.abs(b)
        ra, rb = np.sqrt(a * a + c * c), np.sqrt(b * b + c * c)
        return sa * sb * (a / ra * np.arctan(b / ra) + b / rb * np.arctan(a / rb)) / (2 * math.pi)
    return corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0)


def plates_reference():
    """F(emitter -> receiver) past the blocker: the blocker's shadow from emitter point p is
    [-0.5 - p, 0.5 - p] per axis, which leaves the receiver only where p = 0, so each quadrant of
    the emitter is smooth: composite Gauss-Legendre, 40 x 40 points on each of 4 x 4 cells per quadrant."""
    nodes, weights = np.polynomial.legendre.leggauss(40)
    cells = 4
    total = 0.0
    for qx in (-1, 1):
        for qy in (-1, 1):
            for cx in range(cells):
                for cy in range(cells):
                    ax = qx * 0.5 * (cx + 0.5 * (nodes + 1)) / cells
                    ay = qy * 0.5 * (cy + 0.5 * (nodes + 1)) / cells
                    px, py = np.meshgrid(ax, ay, indexing="ij")
                    w = np.outer(weights, weights) * (0.25 / cells / cells) / 4
                    free = point_rectangle(-0.5 - px, 0.5 - px, -0.5 - py, 0.5 - py, 1.0)
                    sx0, sx1 = np.maximum(-0.5, -0.5 - px), np.minimum(0.5, 0.5 - px)
                    sy0, sy1 = np.maximum(-0.5, -0.5 - py), np.minimum(0.5, 0.5 - py)
                    hidden = point_rectangle(sx0 - px, sx1 - px, sy0 - py, sy1 - py, 1.0)
                    total += float(np.sum(w * (free - hidden)))
    return total


def plates_errors(n, F, reference):
    e, r = np.arange(n * n), np.arange(n * n, 2 * n * n)
    forward = F[e][:, r].sum() / (n * n)
    backward = F[r][:, e].sum() / (n * n)
    return abs(forward - reference), abs(backward - reference)


def fmt(x):
    return "%.1e" % x if x >= 5e-10 else "< 5e-10"


def main():
    global HEMIRAD, hemirad
    build = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build")
    HEMIRAD = os.path.join(build, "hemirad")
    sys.path.insert(0, os.path.join(build, "python"))
    import hemirad
    cases = sys.argv[2:] or ["cube8", "cube16", "cube32", "plates4", "plates16", "plates32", "cornell60"]
    folder = tempfile.TemporaryDirectory()  # F files of up to 250 MB: removed at exit
    work = folder.name
    reference_plates = plates_reference()
    f_path = os.path.join(work, "F.hff")
    print("# Exact form factors against closed forms (issue 16)\n")
    print("`hemirad formfactors SCENE -o F.hff --threads 1` per row, a whole process each (load, F, write):")
    print("wall seconds, its own peak RSS (GNU time) and F's size in memory (8 bytes per nonzero and per row); %d cores, %s." %
          (os.cpu_count(), time.strftime("%Y-%m-%d", time.gmtime())))
    print("Errors: cube, worst opposite / adjacent wall-to-wall factor against C-11 / C-14; plates, the")
    print("plate-to-plate factor both ways against superposition (%.10f); Cornell, mean per-row" % reference_plates)
    print("sum |F - F_ref| against --pair-digits 5 --origins 64. View3D: issue 16's figures.\n")
    print("| case | patches | setting | seconds | errors | peak MiB | F MiB | peak / F | View3D default | View3D eps=1e-5 |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for case in cases:
        kind, n = re.match(r"([a-z]+)(\d+)", case).groups()
        n = int(n)
        if kind == "cube":
            scene = write_cube(work, n)
        elif kind == "plates":
            scene = write_plates(work, n)
        else:
            scene = os.path.join(work, "cornell%d.obj" % n)
            subprocess.run([HEMIRAD, "subdivide", os.path.join(ROOT, "scenes/cornell_box.obj"), "-o", scene,
                            "--max-edge", str(n), "--quiet"], check=True)
            timed(HEMIRAD, scene, f_path, ["--pair-digits", "5", "--origins", "64"], os.cpu_count())
            F_ref = read_f(f_path)
        faces = polygons(scene)
        for label, extra in SETTINGS:
            seconds, peak, _ = timed(HEMIRAD, scene, f_path, extra)
            F = read_f(f_path)
            f_mib = (F.nnz * 12 + (F.shape[0] + 1) * 8) / 2**20  # double values, 32-bit columns, row offsets
            if kind == "cube":
                errors = "%s / %s" % tuple(fmt(e) for e in cube_errors(faces, F))
            elif kind == "plates":
                errors = "%s / %s" % tuple(fmt(e) for e in plates_errors(n, F, reference_plates))
            else:
                errors = fmt(float(np.abs(F - F_ref).sum(axis=1).mean()))
            view3d = ["", ""]
            if kind == "cube" and n in VIEW3D:
                view3d = ["%.2f s, %.1e / %.1e" % v for v in VIEW3D[n]]
            print("| %s | %d | %s | %.2f | %s | %.0f | %.2f | %.1f | %s | %s |" %
                  (case, len(faces), label, seconds, errors, peak, f_mib, peak / f_mib, view3d[0], view3d[1]))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
