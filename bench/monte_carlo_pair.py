#!/usr/bin/env python3
"""A Monte Carlo estimate of one form factor F_ij of a triangulated OBJ scene, independent of
Hemirad's code: pairs of uniform points on triangles i and j, Lambert's kernel
cos_i cos_j / (pi r^2) A_j, each segment tested against every other triangle (Moller-Trumbore).
Prints the unoccluded and the visible estimate, each with one standard error. Faces are 0-based
(as Hemirad's patch ids for a scene of triangles) and must be triangles.

    python3 bench/monte_carlo_pair.py district1k.obj 157 832 [SAMPLES] [--who]

--who lists the triangles that hide part of the pair and how much of F each hides. Used to check
the reference `--pairs whole --pair-digits 4` on district1k (bench/BENCHMARKS.md); 200,000 samples
take about 20 s on two cores of this VM for a scene of 1,000 triangles.
"""
import sys

import numpy as np


def load(path):
    vertices, triangles = [], []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                vertices.append([float(x) for x in t[1:4]])
            elif t[0] == "f":
                if len(t) != 4:
                    sys.exit(f"{path}:{number}: face with {len(t) - 1} corners; only triangles are taken")
                triangles.append(np.array([vertices[int(x.split("/")[0]) - 1] for x in t[1:]]))
    return triangles


def sample(triangle, n, rng):
    a, b, c = triangle
    u, v = rng.random(n), rng.random(n)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    return a + u[:, None] * (b - a) + v[:, None] * (c - a)


def normal(triangle):
    n = np.cross(triangle[1] - triangle[0], triangle[2] - triangle[0])
    return n / np.linalg.norm(n)


def blocked(p, q, triangle):
    """Whether segments p -> q cross the triangle strictly between their ends."""
    d = q - p
    e1, e2 = triangle[1] - triangle[0], triangle[2] - triangle[0]
    h = np.cross(d, e2)
    a = h @ e1
    ok = np.abs(a) > 1e-14
    f = np.where(ok, 1 / np.where(ok, a, 1), 0)
    s = p - triangle[0]
    u = f * np.einsum("ij,ij->i", s, h)
    qv = np.cross(s, e1)
    v = f * np.einsum("ij,ij->i", d, qv)
    w = f * (qv @ e2)
    return ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (w > 1e-9) & (w < 1 - 1e-9)


def main():
    args = [a for a in sys.argv[1:] if a != "--who"]
    if len(args) < 3:
        sys.exit(__doc__)
    triangles = load(args[0])
    i, j = int(args[1]), int(args[2])
    samples = int(args[3]) if len(args) > 3 else 200000
    rng = np.random.default_rng(1)
    ni, nj = normal(triangles[i]), normal(triangles[j])
    aj = 0.5 * np.linalg.norm(np.cross(triangles[j][1] - triangles[j][0], triangles[j][2] - triangles[j][0]))
    whole, seen, hiders = [], [], {}
    chunk = 20000
    for _ in range(max(1, samples // chunk)):
        p, q = sample(triangles[i], chunk, rng), sample(triangles[j], chunk, rng)
        d = q - p
        r2 = np.einsum("ij,ij->i", d, d)
        r = np.sqrt(r2)
        kernel = np.maximum(d @ ni / r, 0) * np.maximum(-(d @ nj) / r, 0) / (np.pi * r2) * aj
        hit = np.zeros(chunk, bool)
        for k, t in enumerate(triangles):
            if k in (i, j):
                continue
            b = blocked(p, q, t)
            if b.any():
                hiders[k] = hiders.get(k, 0.0) + (kernel * b).sum()
            hit |= b
        whole.append(kernel)
        seen.append(kernel * ~hit)
    whole, seen = np.concatenate(whole), np.concatenate(seen)
    n = len(whole)
    print(f"F_{i},{j} unoccluded {whole.mean():.6g} +- {whole.std() / np.sqrt(n):.2g}, "
          f"visible {seen.mean():.6g} +- {seen.std() / np.sqrt(n):.2g} ({n} samples)")
    if "--who" in sys.argv:
        for k, h in sorted(hiders.items(), key=lambda t: -t[1]):
            print(f"  triangle {k} hides {h / n:.4g} of F")


if __name__ == "__main__":
    main()
