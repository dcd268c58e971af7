#!/usr/bin/env python3
"""Generate street64k.obj/.mtl: an urban street canyon (two rows of buildings with window panes,
some of them mirrors, street and sidewalk ground) under a sky dome of equal-solid-angle cells from
the Beckers & Beckers (2012) hemisphere partition, ten of which form an emitting sun.

Usage: street64k.py OUTPUT_DIR [--tiles N]

--tiles N repeats the street (buildings and ground) N times along x, an alley apart, centred on the
origin, under one sky dome: street64k_xN.obj (N = 4: 249,807 patches, the scale-out benchmark).

Conventions (Hemirad's OBJ loader): one face = one patch; the right-hand-rule normal is the side
a patch emits into and receives from. Buildings face outward, the ground faces up, the sky dome
faces inward (toward the street). Units metres, +y up, the street runs along x.
Deterministic: no randomness.
"""
import math
import os
import sys

NAME = "street64k"

# ----------------------------------------------------------------------------- layout (metres)
STREET_X0, STREET_X1 = -100.0, 100.0
ROAD_HALF = 6.0          # asphalt for |z| <= 6
FACADE_Z = 9.0           # sidewalks 6 <= |z| <= 9, facades at |z| = 9
GROUND_CELL = 1.0        # street, sidewalk and alley ground quads
COARSE_CELL = 1.0        # roofs, side and back walls
ALLEY = 2.0              # gap between neighbouring buildings

# Facade grid: each bay (width ~BAY) x floor (FLOOR high) is a 4 x 7 grid of cells; the window
# (1.2 x 1.5 m) replaces the 2 x 3 middle cells, the other 22 cells are wall.
BAY = 2.4
WINDOW_W, WINDOW_H = 1.2, 1.5
FLOOR = 3.5
SILL = 1.0               # window from 1.0 to 2.5 m above the floor level
PARAPET = 1.0            # wall band above the top floor (2 rows of 0.5 m)

SKY_RADIUS = 500.0
SKY_CELLS = 2407
SUN_ELEVATION, SUN_AZIMUTH = 45.0, 30.0   # degrees; azimuth from +x toward +z
SUN_CELLS = 10

# Buildings per side, west to east: (width, floors, depth, window mode, wall material).
# Window modes: 'mirror' every pane a mirror, 'alternate' checkerboard of mirror and diffuse
# panes, 'diffuse' glass-less diffuse panes. Widths sum to 184 m (+ 8 alleys of 2 m = 200 m).
NORTH = [  # z > 0, facades face -z
    (18.0, 6, 14.0, "diffuse", "concrete"),
    (22.0, 9, 18.0, "mirror", "concrete"),
    (19.2, 4, 12.0, "diffuse", "brick"),
    (24.0, 11, 20.0, "alternate", "sandstone"),
    (16.8, 6, 15.0, "diffuse", "concrete"),
    (21.6, 5, 13.0, "diffuse", "brick"),
    (20.4, 10, 19.0, "mirror", "sandstone"),
    (19.2, 7, 16.0, "alternate", "concrete"),
    (22.8, 6, 17.0, "diffuse", "brick"),
]
SOUTH = [  # z < 0, facades face +z
    (21.0, 8, 16.0, "alternate", "brick"),
    (17.4, 5, 12.0, "diffuse", "sandstone"),
    (23.4, 11, 20.0, "mirror", "concrete"),
    (19.8, 6, 14.0, "diffuse", "brick"),
    (20.2, 8, 18.0, "diffuse", "sandstone"),
    (18.6, 4, 13.0, "alternate", "concrete"),
    (22.6, 7, 17.0, "diffuse", "brick"),
    (16.4, 9, 15.0, "mirror", "sandstone"),
    (24.6, 6, 19.0, "diffuse", "concrete"),
]

# name, Kd, Ke, mirror reflectance s (0 = diffuse)
MATERIALS = [
    ("asphalt", (0.1, 0.1, 0.1), (0, 0, 0), 0.0),
    ("sidewalk", (0.3, 0.3, 0.3), (0, 0, 0), 0.0),
    ("concrete", (0.5, 0.5, 0.5), (0, 0, 0), 0.0),
    ("brick", (0.45, 0.25, 0.2), (0, 0, 0), 0.0),
    ("sandstone", (0.6, 0.55, 0.45), (0, 0, 0), 0.0),
    ("roof", (0.3, 0.3, 0.3), (0, 0, 0), 0.0),
    ("window", (0.2, 0.25, 0.3), (0, 0, 0), 0.0),
    ("mirror", (0.05, 0.05, 0.05), (0, 0, 0), 0.8),
    ("sky", (0, 0, 0), (0.5, 0.6, 0.8), 0.0),
    ("sun", (0, 0, 0), (50, 48, 45), 0.0),
]


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from objwriter import ObjWriter, add, dot, mul, newell, sub, write_mtl  # noqa: E402,F401


# ----------------------------------------------------------------------------- builders
def divisions(length, cell):
    return max(1, int(round(length / cell)))


def axis_rect(w, fixed_axis, fixed, a0, a1, b0, b1, na, nb, normal, material=None):
    """Axis-aligned rectangle in the plane coord[fixed_axis] = fixed; the other two axes (in
    x, y, z order) span [a0, a1] x [b0, b1] as na x nb quads facing `normal`."""
    free = [k for k in range(3) if k != fixed_axis]

    def P(u, v):
        p = [0.0, 0.0, 0.0]
        p[fixed_axis] = fixed
        p[free[0]] = u
        p[free[1]] = v
        return tuple(p)
    us = [a0 + (a1 - a0) * i / na for i in range(na + 1)]
    vs = [b0 + (b1 - b0) * j / nb for j in range(nb + 1)]
    for i in range(na):
        for j in range(nb):
            w.face([P(us[i], vs[j]), P(us[i + 1], vs[j]), P(us[i + 1], vs[j + 1]), P(us[i], vs[j + 1])],
                   normal, material)


def facade(w, x0, x1, z, height, floors, outward_z, mode, wall):
    """Street facade in the plane z = const: a grid of cells, window cells as single panes.
    Column breakpoints per bay: margin, 0.6, 0.6, margin; rows per floor: 0.5 m each with the
    window spanning rows 2..4 (1.0..2.5 m); a parapet of 2 rows above the top floor."""
    nb = divisions(x1 - x0, BAY)
    bay = (x1 - x0) / nb
    margin = (bay - WINDOW_W) / 2.0
    xs = []
    for b in range(nb):
        bx = x0 + b * bay
        xs += [bx, bx + margin, bx + margin + WINDOW_W / 2, bx + margin + WINDOW_W]
    xs.append(x1)
    rows_per_floor = int(round(FLOOR / 0.5))
    ys = [f * FLOOR + r * 0.5 for f in range(floors) for r in range(rows_per_floor)]
    top = floors * FLOOR
    n_par = divisions(height - top, 0.5)
    ys += [top + (height - top) * r / n_par for r in range(n_par + 1)]
    win_row0 = int(round(SILL / 0.5))           # first window row within a floor
    win_rows = int(round(WINDOW_H / 0.5))       # 3 rows
    normal = (0.0, 0.0, outward_z)

    def P(x, y):
        return (x, y, z)
    for i in range(len(xs) - 1):
        for j in range(len(ys) - 1):
            b, ci = divmod(i, 4)
            f, rj = divmod(j, rows_per_floor)
            in_window = (f < floors and ci in (1, 2) and win_row0 <= rj < win_row0 + win_rows)
            if not in_window:
                w.face([P(xs[i], ys[j]), P(xs[i + 1], ys[j]), P(xs[i + 1], ys[j + 1]), P(xs[i], ys[j + 1])],
                       normal, wall)
            elif ci == 1 and rj == win_row0:
                # The window pane: one quad over the 2 x 3 cells.
                xa, xb = xs[i], xs[i + 2]
                ya, yb = ys[j], ys[j + win_rows]
                if mode == "mirror" or (mode == "alternate" and (b + f) % 2 == 0):
                    mat = "mirror"
                else:
                    mat = "window"
                w.face([P(xa, ya), P(xb, ya), P(xb, yb), P(xa, yb)], normal, mat)
    return nb * floors


def building(w, name, x0, x1, depth, floors, side, mode, wall):
    """side = +1: north row (z from 9 to 9+depth, facade faces -z); -1: south row."""
    height = floors * FLOOR + PARAPET
    zf = side * FACADE_Z
    zb = side * (FACADE_Z + depth)
    za, zc = min(zf, zb), max(zf, zb)
    w.object = name
    w.material = wall
    windows = facade(w, x0, x1, zf, height, floors, -side, mode, wall)
    nx = divisions(x1 - x0, COARSE_CELL)
    ny = divisions(height, COARSE_CELL)
    nz = divisions(depth, COARSE_CELL)
    axis_rect(w, 2, zb, x0, x1, 0.0, height, nx, ny, (0.0, 0.0, side))          # back wall
    axis_rect(w, 0, x0, 0.0, height, za, zc, ny, nz, (-1.0, 0.0, 0.0))         # west side
    axis_rect(w, 0, x1, 0.0, height, za, zc, ny, nz, (1.0, 0.0, 0.0))          # east side
    axis_rect(w, 1, height, x0, x1, za, zc, nx, nz, (0.0, 1.0, 0.0), "roof")   # roof
    return windows


def beckers_hemisphere(n):
    """Beckers & Beckers (2012) equal-solid-angle partition of the hemisphere into n cells:
    returns cumulative counts S (S[0] = 1 cap cell, S[-1] = n); ring j has S[j] - S[j-1] cells
    between cos(theta) = 1 - S[j-1]/n and 1 - S[j]/n."""
    w = math.sqrt(2.0 * math.pi / n)
    t = math.pi / 2.0
    k = [n]
    while True:
        t1 = t - w
        k1 = int(math.floor(k[-1] * (math.sin(t1 / 2.0) / math.sin(t / 2.0)) ** 2 + 0.5)) if t1 > 0 else 0
        if k1 < 7:
            k.append(1)
            break
        t = 2.0 * math.asin(math.sin(t / 2.0) * math.sqrt(k1 / k[-1]))
        k.append(k1)
    return list(reversed(k))


def sky_dome(w):
    """Sky dome cells (normals toward the centre); the SUN_CELLS cells whose centre directions are
    closest to the sun direction get the 'sun' material. Returns the number of cells."""
    assert beckers_hemisphere(96) == [1, 14, 29, 49, 72, 96]   # test fixture (physics notes)
    S = beckers_hemisphere(SKY_CELLS)
    R = SKY_RADIUS
    el, az = math.radians(SUN_ELEVATION), math.radians(SUN_AZIMUTH)
    sun = (math.cos(el) * math.cos(az), math.sin(el), math.cos(el) * math.sin(az))

    def point(cos_t, phi):
        sin_t = math.sqrt(max(0.0, 1.0 - cos_t * cos_t))
        return (R * sin_t * math.cos(phi), R * cos_t, R * sin_t * math.sin(phi))

    def direction(cos_t, phi):
        p = point(cos_t, phi)
        return (p[0] / R, p[1] / R, p[2] / R)

    inward = lambda c: mul(c, -1.0)
    cells = []   # (polygon, centre direction)
    # Cap: the first ring's inner circle, with the first ring's azimuth divisions as vertices.
    n1 = S[1] - S[0]
    c0 = 1.0 - S[0] / SKY_CELLS
    cells.append(([point(c0, 2 * math.pi * m / n1) for m in range(n1)], (0.0, 1.0, 0.0)))
    for j in range(1, len(S)):
        nj = S[j] - S[j - 1]
        ca = 1.0 - S[j - 1] / SKY_CELLS
        cb = 1.0 - S[j] / SKY_CELLS
        cm = 0.5 * (ca + cb)   # solid-angle median of the ring
        for m in range(nj):
            p0, p1 = 2 * math.pi * m / nj, 2 * math.pi * (m + 1) / nj
            poly = [point(ca, p0), point(ca, p1), point(cb, p1), point(cb, p0)]
            cells.append((poly, direction(cm, 0.5 * (p0 + p1))))
    assert len(cells) == SKY_CELLS
    order = sorted(range(len(cells)), key=lambda i: -dot(cells[i][1], sun))
    sun_cells = set(order[:SUN_CELLS])
    w.object = "sky"
    for i, (poly, _) in enumerate(cells):
        w.face(poly, inward, "sun" if i in sun_cells else "sky")
    return len(cells), S


def street_bands():
    return [(-FACADE_Z, -ROAD_HALF, "sidewalk"), (-ROAD_HALF, ROAD_HALF, "asphalt"), (ROAD_HALF, FACADE_Z, "sidewalk")]


def ground(w, rows, prefix=""):
    w.object = prefix + "ground"
    nx = divisions(STREET_X1 - STREET_X0, GROUND_CELL)
    up = (0.0, 1.0, 0.0)
    for z0, z1, mat in street_bands():
        axis_rect(w, 1, 0.0, STREET_X0, STREET_X1, z0, z1, nx, divisions(z1 - z0, GROUND_CELL), up, mat)
    # Alleys between neighbouring buildings, back to the deeper neighbour's back wall.
    for side, spans in rows:
        for (xa, xb, da), (xc, xd, dc) in zip(spans, spans[1:]):
            depth = max(da, dc)
            z0, z1 = sorted((side * FACADE_Z, side * (FACADE_Z + depth)))
            axis_rect(w, 1, 0.0, xb, xc, z0, z1, divisions(xc - xb, GROUND_CELL), divisions(depth, GROUND_CELL),
                      up, "sidewalk")


def build(tiles=1):
    w = ObjWriter()
    windows = 0
    # Tiles an alley apart (touching end walls would face each other at distance 0).
    pitch = STREET_X1 - STREET_X0 + ALLEY
    for tile in range(tiles):
        w.shift_x = (tile - (tiles - 1) / 2.0) * pitch
        windows += build_street(w, "" if tiles == 1 else "tile%d_" % (tile + 1))
        if tile + 1 < tiles:  # the street across the alley to the next tile
            up = (0.0, 1.0, 0.0)
            for z0, z1, mat in street_bands():
                axis_rect(w, 1, 0.0, STREET_X1, STREET_X1 + ALLEY, z0, z1, divisions(ALLEY, GROUND_CELL),
                          divisions(z1 - z0, GROUND_CELL), up, mat)
    w.shift_x = 0.0
    sky, S = sky_dome(w)
    return w, windows, sky, S


def build_street(w, prefix):
    """The buildings and ground of one street (objects named with `prefix`); returns the window count."""
    rows = []
    windows = 0
    for side, table, label in ((1, NORTH, "north"), (-1, SOUTH, "south")):
        total = sum(b[0] for b in table) + ALLEY * (len(table) - 1)
        assert abs(total - (STREET_X1 - STREET_X0)) < 1e-9, (label, total)
        x = STREET_X0
        spans = []
        for k, (width, floors, depth, mode, wall) in enumerate(table):
            height = floors * FLOOR + PARAPET
            assert 12.0 <= height <= 40.0 and 12.0 <= depth <= 20.0
            windows += building(w, "%sbuilding_%s_%d" % (prefix, label, k + 1), x, x + width, depth, floors, side, mode,
                                wall)
            spans.append((x, x + width, depth))
            x += width + ALLEY
        rows.append((side, spans))
    ground(w, rows, prefix)
    return windows


def main():
    args = sys.argv[1:]
    tiles = 1
    if len(args) == 3 and args[1] == "--tiles" and args[2].isdigit() and int(args[2]) >= 1:
        tiles = int(args[2])
        args = args[:1]
    if len(args) != 1 or args[0].startswith("-"):  # `--help` is not a folder to write into
        sys.exit("usage: street64k.py OUTPUT_DIR [--tiles N]")
    out = args[0]
    os.makedirs(out, exist_ok=True)
    w, windows, sky, S = build(tiles)
    name = NAME if tiles == 1 else "%s_x%d" % (NAME, tiles)
    t, q, o = w.counts
    w.write(os.path.join(out, name + ".obj"),
            "Urban street canyon%s: %d buildings with window panes (some mirrors), ground, Beckers sky dome "
            "of %d cells with %d sun cells; %d patches"
            % ("" if tiles == 1 else " repeated %d times along x" % tiles, 18 * tiles, sky, SUN_CELLS, t + q + o),
            NAME + ".mtl",
            ["# hemirad camera -95 1.7 0 100 12 0 70",
             "# Buildings face outward, ground up, sky dome inward. Units m, +y up, street along x.",
             "# Sky: Beckers & Beckers equal-solid-angle hemisphere partition, N = %d, %d rings, radius %g m."
             % (SKY_CELLS, len(S) - 1, SKY_RADIUS)])
    write_mtl(os.path.join(out, NAME + ".mtl"),
              "Materials for street64k.obj (Kd diffuse, Ke emission, illum 3 + Ks s = mirror)", MATERIALS)
    print("%s: %d patches (%d triangles, %d quads, %d other); %d windows, %d sky cells"
          % (name, t + q + o, t, q, o, windows, sky))


if __name__ == "__main__":
    main()
