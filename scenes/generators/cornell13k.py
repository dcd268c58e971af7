#!/usr/bin/env python3
"""Generate cornell13k.obj/.mtl: a closed Cornell-style box (555 mm cube, walls as quad grids),
an emitting UV sphere as the light and five diffuse objects standing on the floor, 12,922 patches
(12,826 quads + 96 triangles, the size of the reference system's Cornell scene).

Usage: cornell13k.py OUTPUT_DIR

Conventions (Hemirad's OBJ loader): one face = one patch; the right-hand-rule normal is the side
a patch emits into and receives from. Walls face into the box, objects face outward. Units mm,
+y up; seen from the camera (inside the box, looking +z) +x points left, so the red wall is x=555.
Deterministic: no randomness.
"""
import math
import os
import sys

NAME = "cornell13k"
SIZE = 555.0

# Resolutions (chosen so that the total is 12,922 patches).
WALL_GRID = 41            # each of the 6 walls: 41 x 41 quads (13.5 mm)
LIGHT_SEGMENTS = 48       # around; the two pole fans give 2 x 48 = 96 triangles
LIGHT_BANDS = 24          # latitude bands (the 2 pole bands are triangle fans)
LIGHT_RADIUS = 60.0

MATERIALS = [
    ("white", (0.73, 0.73, 0.73), (0, 0, 0), 0.0),
    ("red", (0.65, 0.05, 0.05), (0, 0, 0), 0.0),
    ("green", (0.12, 0.45, 0.15), (0, 0, 0), 0.0),
    ("light", (0.78, 0.78, 0.78), (17, 12, 4), 0.0),
]


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from objwriter import ObjWriter, add, cross, dot, mul, newell, sub, write_mtl  # noqa: E402,F401


# ----------------------------------------------------------------------------- geometry builders
def grid(w, origin, u, v, nu, nv, normal):
    """Parallelogram origin + a u + b v (a, b in [0,1]) as nu x nv quads facing `normal`."""
    P = [[add(origin, add(mul(u, i / nu), mul(v, j / nv))) for j in range(nv + 1)] for i in range(nu + 1)]
    for i in range(nu):
        for j in range(nv):
            w.face([P[i][j], P[i + 1][j], P[i + 1][j + 1], P[i][j + 1]], normal)


def outward_from(center):
    return lambda c: sub(c, center)


def prism_sides(w, footprint, height, n_along, n_up, center):
    """Vertical side walls over each edge of a convex footprint [(x, z)...], facing outward."""
    for k, a in enumerate(footprint):
        b = footprint[(k + 1) % len(footprint)]
        p0 = (a[0], 0.0, a[1])
        p1 = (b[0], 0.0, b[1])
        grid(w, p0, sub(p1, p0), (0.0, height, 0.0), n_along, n_up, outward_from(center))


def rotated_square(cx, cz, side, degrees):
    a = math.radians(degrees)
    h = side / 2.0
    ca, sa = math.cos(a), math.sin(a)
    pts = []
    for sx, sz in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        x, z = sx * h, sz * h
        pts.append((cx + ca * x - sa * z, cz + sa * x + ca * z))
    return pts


def block(w, cx, cz, side, height, degrees, n_side, n_up):
    """Box standing on the floor (no bottom): 4 gridded sides and a gridded top."""
    fp = rotated_square(cx, cz, side, degrees)
    center = (cx, height / 2.0, cz)
    prism_sides(w, fp, height, n_side, n_up, center)
    c0 = (fp[0][0], height, fp[0][1])
    u = (fp[1][0] - fp[0][0], 0.0, fp[1][1] - fp[0][1])
    v = (fp[3][0] - fp[0][0], 0.0, fp[3][1] - fp[0][1])
    grid(w, c0, u, v, n_side, n_side, (0.0, 1.0, 0.0))
    return fp


def ring(center, radius, y, segments, phase=0.0):
    return [(center[0] + radius * math.cos(phase + 2 * math.pi * m / segments), y,
             center[2] + radius * math.sin(phase + 2 * math.pi * m / segments)) for m in range(segments)]


def band(w, lower, upper, want):
    n = len(lower)
    for m in range(n):
        w.face([lower[m], lower[(m + 1) % n], upper[(m + 1) % n], upper[m]], want)


def flat_disk_fan_of_quads(w, rim, centre, want):
    """A flat regular polygon (even vertex count) as quads (centre, v2j, v2j+1, v2j+2): each is
    planar (all in the disk plane) and convex (v2j+1 lies outside the chord v2j..v2j+2)."""
    n = len(rim)
    assert n % 2 == 0
    for j in range(n // 2):
        w.face([centre, rim[2 * j], rim[2 * j + 1], rim[(2 * j + 2) % n]], want)


def uv_sphere(w, center, radius, segments, bands, pole_mode):
    """UV sphere, normals outward. Latitude rings at polar angles k pi / bands (k = 1..bands-1).
    pole_mode 'fan': triangle fans to the two poles (2 x segments triangles).
    pole_mode 'flat': the polar caps are flat disks in the first/last ring planes, each split
    into segments/2 planar quads (no triangles)."""
    rings = []
    for k in range(1, bands):
        th = math.pi * k / bands
        rings.append(ring(center, radius * math.sin(th), center[1] + radius * math.cos(th), segments))
    out = outward_from(center)
    for k in range(len(rings) - 1):
        band(w, rings[k + 1], rings[k], out)
    top = rings[0]
    bottom = rings[-1]
    if pole_mode == "fan":
        north = (center[0], center[1] + radius, center[2])
        south = (center[0], center[1] - radius, center[2])
        n = segments
        for m in range(n):
            w.face([north, top[m], top[(m + 1) % n]], out)
            w.face([south, bottom[m], bottom[(m + 1) % n]], out)
    else:
        flat_disk_fan_of_quads(w, top, (center[0], top[0][1], center[2]), (0.0, 1.0, 0.0))
        flat_disk_fan_of_quads(w, bottom, (center[0], bottom[0][1], center[2]), (0.0, -1.0, 0.0))


def cylinder(w, cx, cz, radius, height, segments, n_up, cap_rings):
    """Standing cylinder (no bottom): quad sides and a top of concentric annuli of quads, the
    innermost disk split into segments/2 planar quads around the centre."""
    center = (cx, height / 2.0, cz)
    out = outward_from(center)
    rings = [ring(center, radius, height * j / n_up, segments) for j in range(n_up + 1)]
    for j in range(n_up):
        band(w, rings[j], rings[j + 1], out)
    up = (0.0, 1.0, 0.0)
    caps = [ring(center, radius * (cap_rings - i) / cap_rings, height, segments) for i in range(cap_rings)]
    for i in range(cap_rings - 1):
        band(w, caps[i], caps[i + 1], up)
    flat_disk_fan_of_quads(w, caps[-1], (cx, height, cz), up)


def frustum(w, cx, cz, base, top, height, degrees, n_side, n_up, n_top):
    """Truncated square pyramid (no bottom): each trapezoid side as an n_side x n_up grid of
    planar trapezoids, the top square as n_top x n_top quads."""
    fb = rotated_square(cx, cz, base, degrees)
    ft = rotated_square(cx, cz, top, degrees)
    center = (cx, height / 3.0, cz)
    out = outward_from(center)
    for k in range(4):
        b0 = (fb[k][0], 0.0, fb[k][1])
        b1 = (fb[(k + 1) % 4][0], 0.0, fb[(k + 1) % 4][1])
        t0 = (ft[k][0], height, ft[k][1])
        t1 = (ft[(k + 1) % 4][0], height, ft[(k + 1) % 4][1])

        def P(i, j):
            lo = add(b0, mul(sub(b1, b0), i / n_side))
            hi = add(t0, mul(sub(t1, t0), i / n_side))
            return add(lo, mul(sub(hi, lo), j / n_up))
        for i in range(n_side):
            for j in range(n_up):
                w.face([P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)], out)
    c0 = (ft[0][0], height, ft[0][1])
    u = (ft[1][0] - ft[0][0], 0.0, ft[1][1] - ft[0][1])
    v = (ft[3][0] - ft[0][0], 0.0, ft[3][1] - ft[0][1])
    grid(w, c0, u, v, n_top, n_top, (0.0, 1.0, 0.0))
    return fb


# ----------------------------------------------------------------------------- layout checks
def seg_point_dist(p, a, b):
    ax, az = b[0] - a[0], b[1] - a[1]
    t = ((p[0] - a[0]) * ax + (p[1] - a[1]) * az) / (ax * ax + az * az)
    t = max(0.0, min(1.0, t))
    return math.hypot(p[0] - a[0] - t * ax, p[1] - a[1] - t * az)


def inside_convex(p, poly):
    sign = 0
    for k, a in enumerate(poly):
        b = poly[(k + 1) % len(poly)]
        c = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
        s = 1 if c > 0 else -1
        if sign == 0:
            sign = s
        elif s != sign:
            return False
    return True


def clearance(f1, f2):
    """Minimum distance between two footprints: ('poly', pts) or ('circle', (x, z), r)."""
    if f1[0] == "circle" and f2[0] == "circle":
        return math.hypot(f1[1][0] - f2[1][0], f1[1][1] - f2[1][1]) - f1[2] - f2[2]
    if f1[0] == "circle":
        f1, f2 = f2, f1
    if f2[0] == "circle":
        poly, c, r = f1[1], f2[1], f2[2]
        if inside_convex(c, poly):
            return -1.0
        return min(seg_point_dist(c, a, poly[(k + 1) % len(poly)]) for k, a in enumerate(poly)) - r
    p, q = f1[1], f2[1]
    if any(inside_convex(x, q) for x in p) or any(inside_convex(x, p) for x in q):
        return -1.0
    d = min(seg_point_dist(x, a, q[(k + 1) % len(q)]) for x in p for k, a in enumerate(q))
    return min(d, min(seg_point_dist(x, a, p[(k + 1) % len(p)]) for x in q for k, a in enumerate(p)))


def wall_clearance(f):
    if f[0] == "circle":
        (x, z), r = f[1], f[2]
        return min(x - r, SIZE - x - r, z - r, SIZE - z - r)
    return min(min(x, SIZE - x, z, SIZE - z) for x, z in f[1])


# ----------------------------------------------------------------------------- scene
def build():
    w = ObjWriter()
    S, g = SIZE, WALL_GRID
    walls = [
        # name, material, origin, u, v, inward normal
        ("floor", "white", (0, 0, 0), (S, 0, 0), (0, 0, S), (0, 1, 0)),
        ("ceiling", "white", (0, S, 0), (S, 0, 0), (0, 0, S), (0, -1, 0)),
        ("back_wall", "white", (0, 0, S), (S, 0, 0), (0, S, 0), (0, 0, -1)),
        ("front_wall", "white", (0, 0, 0), (S, 0, 0), (0, S, 0), (0, 0, 1)),
        ("left_wall_red", "red", (S, 0, 0), (0, 0, S), (0, S, 0), (-1, 0, 0)),
        ("right_wall_green", "green", (0, 0, 0), (0, 0, S), (0, S, 0), (1, 0, 0)),
    ]
    for name, mat, o, u, v, n in walls:
        w.object, w.material = name, mat
        grid(w, o, u, v, g, g, n)

    w.object, w.material = "light_sphere", "light"
    uv_sphere(w, (S / 2, S - 100.0, S / 2), LIGHT_RADIUS, LIGHT_SEGMENTS, LIGHT_BANDS, "fan")

    footprints = []
    w.object, w.material = "tall_block", "white"
    footprints.append(("poly", block(w, 368.5, 351.0, 165.0, 330.0, -17.0, 8, 16)))
    w.object = "short_block"
    footprints.append(("poly", block(w, 150.0, 170.0, 165.0, 165.0, 17.0, 8, 8)))
    w.object = "cylinder"
    cylinder(w, 480.0, 150.0, 50.0, 180.0, 24, 9, 3)
    footprints.append(("circle", (480.0, 150.0), 50.0))
    w.object = "sphere"
    radius = 70.0
    bands = 14
    # Rest the flat bottom cap 1 mm above the floor.
    cy = radius * math.cos(math.pi / bands) + 1.0
    uv_sphere(w, (130.0, cy, 430.0), radius, 24, bands, "flat")
    footprints.append(("circle", (130.0, 430.0), radius))
    w.object = "pyramid"
    footprints.append(("poly", frustum(w, 340.0, 110.0, 110.0, 40.0, 140.0, 20.0, 7, 7, 2)))

    for i, f in enumerate(footprints):
        assert wall_clearance(f) >= 10.0, ("object too close to a wall", i, wall_clearance(f))
        for j in range(i):
            assert clearance(f, footprints[j]) >= 10.0, ("objects too close", i, j, clearance(f, footprints[j]))
    return w


def main():
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):  # `--help` is not a folder to write into
        sys.exit("usage: cornell13k.py OUTPUT_DIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    w = build()
    w.write(os.path.join(out, NAME + ".obj"),
            "Closed Cornell-style box (555 mm, gridded walls), emitting UV-sphere light, five objects; 12,922 patches",
            NAME + ".mtl",
            ["# hemirad camera 277.5 277.5 20 277.5 277.5 555 60",
             "# Walls face into the box; light sphere and objects face outward. Units mm, +y up."])
    write_mtl(os.path.join(out, NAME + ".mtl"), "Materials for cornell13k.obj (Kd diffuse, Ke emission)", MATERIALS)
    t, q, o = w.counts
    print("%s: %d patches (%d triangles, %d quads, %d other)" % (NAME, t + q + o, t, q, o))


if __name__ == "__main__":
    main()
