#!/usr/bin/env python3
"""Generate a non-conforming urban district (district1k/district25k .obj/.mtl): box buildings on a
square ground, everything triangles, with the T-junctions of real urban-climate and CAD exports.

Usage: district.py OUT_DIR [--preset 1k|25k] [--buildings N] [--seed S] [--ground-cell G]
                   [--wall-split K] [--name NAME] [--closed]

What makes it non-conforming (the contacts where exact form factors of touching patches go wrong):
- The ground is cut into G x G cells that ignore the footprints; each cell's part outside the
  footprints is split into rectangles along the footprint edges and every rectangle triangulated
  (ear clipping, no Steiner points). The ground is conforming within itself, but along a footprint
  its edges stop at cell lines and at other footprints' edge lines, while the wall above has one
  bottom edge per strip: ground vertices lie inside wall edges and wall corners inside ground edges.
  Footprint corners near a cell line give thin ground strips, so slivers.
- Walls: each exposed wall rectangle is K vertical strips of 2 triangles (random diagonals).
  Buildings that touch share part of a wall: only the exposed parts are emitted (no back-to-back
  faces inside a block); the higher building's wall above the lower one's roof starts at that roof,
  so roof edges, wall pieces and the neighbour's walls meet non-conformingly at the junction.
- Roofs: 2 triangles; some touching neighbours have the same height (flush, coplanar roofs).

Conventions (Hemirad's OBJ loader): one face = one patch; the right-hand-rule normal is the side a
patch emits into. Ground and roofs face up (+z), walls outward from their building, the enclosure
of --closed inward. Units m, z up. Every vertex lies on a 1/8 m lattice, exact in the OBJ text, so
the T-junction count below is exact (integer arithmetic). Objects: `ground`, `building_NN`, and
`enclosure` with --closed. Nothing emits except the enclosure's ceiling (--closed).
Deterministic for a given seed (random.Random(seed)).

Printed: triangles, buildings, T-junctions (vertices lying strictly inside another triangle's edge),
slivers (longest edge^2 / (2 area) > 20), edges (distinct vertex pairs of triangle edges).
"""
import argparse
import math
import os
import random
import sys
from bisect import bisect_left, bisect_right
from collections import Counter, defaultdict

Q = 8                     # lattice ticks per metre: every coordinate is an integer number of ticks
HALF = Q // 2             # footprints and heights on a half-metre grid
MARGIN = 8 * Q            # clear ground between the buildings and the edge of the square
SITE = 1000.0             # ground area per building (m^2): the square's side follows from N
SLIVER = 20.0             # aspect longest^2 / (2 area) above which a triangle is a sliver

PRESETS = {  # buildings, ground cell (m), wall strips
    "1k": dict(buildings=28, cell=20.0, split=2),
    "25k": dict(buildings=380, cell=8.0, split=3),
}

# name, Kd, Ke, mirror reflectance s (0 = diffuse)
MATERIALS = [
    ("ground", (0.2, 0.2, 0.2), (0, 0, 0), 0.0),
    ("wall", (0.4, 0.4, 0.4), (0, 0, 0), 0.0),
    ("roof", (0.3, 0.3, 0.3), (0, 0, 0), 0.0),
]
ENCLOSURE_MATERIALS = [
    ("enclosure", (0.5, 0.5, 0.5), (0, 0, 0), 0.0),
    ("enclosure_sky", (0.5, 0.5, 0.5), (1, 1, 1), 0.0),
]

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from objwriter import ObjWriter, write_mtl  # noqa: E402


# ----------------------------------------------------------------------------- integer geometry
def isub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def icross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def idot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def tri_normal(t):
    """Twice the area vector of triangle t (right-hand rule), in ticks^2."""
    return icross(isub(t[1], t[0]), isub(t[2], t[0]))


def oriented(t, want):
    """Triangle t with its vertices ordered so that its normal points along `want`."""
    n = tri_normal(t)
    assert n != (0, 0, 0), "degenerate triangle %r" % (t,)
    return t if idot(n, want) > 0 else (t[0], t[2], t[1])


def cross2(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


# ----------------------------------------------------------------------------- buildings
class Building:
    def __init__(self, x0, y0, x1, y1, h):
        self.x0, self.y0, self.x1, self.y1, self.h = x0, y0, x1, y1, h

    def area(self):
        return (self.x1 - self.x0) * (self.y1 - self.y0)


def overlap(a0, a1, b0, b1):
    return min(a1, b1) - max(a0, b0)


def interiors_meet(a, b):
    return overlap(a.x0, a.x1, b.x0, b.x1) > 0 and overlap(a.y0, a.y1, b.y0, b.y1) > 0


def shared_wall(a, b):
    """Length (ticks) of the wall segment footprints a and b share (0 when they do not touch along a side)."""
    if a.x1 == b.x0 or b.x1 == a.x0:
        return max(0, overlap(a.y0, a.y1, b.y0, b.y1))
    if a.y1 == b.y0 or b.y1 == a.y0:
        return max(0, overlap(a.x0, a.x1, b.x0, b.x1))
    return 0


def place_buildings(rng, n, side):
    """n footprints with disjoint interiors inside the square [0, side]^2 less MARGIN; about 60 % are
    attached to an earlier one (touching along part of a side), a third of those at its height."""
    def half_metres(lo, hi):
        return rng.randint(lo * 2, hi * 2) * HALF
    blds = []
    attempts = 0
    while len(blds) < n:
        attempts += 1
        if attempts > 5000 * n:
            sys.exit("district.py: could not place %d buildings on a %g m square" % (n, side / Q))
        w, d, h = half_metres(8, 28), half_metres(8, 24), half_metres(6, 30)
        if blds and rng.random() < 0.6:
            a = rng.choice(blds)
            s = rng.randrange(4)
            least = 3 * Q   # the shared segment is at least 3 m
            if s < 2:       # beside a's south or north side, overlapping it in x
                x0 = rng.randint((a.x0 - w + least) // HALF, (a.x1 - least) // HALF) * HALF
                y0 = a.y0 - d if s == 0 else a.y1
            else:           # beside a's west or east side, overlapping it in y
                y0 = rng.randint((a.y0 - d + least) // HALF, (a.y1 - least) // HALF) * HALF
                x0 = a.x0 - w if s == 2 else a.x1
            if rng.random() < 0.35:
                h = a.h
        else:
            x0 = rng.randint(MARGIN // HALF, (side - MARGIN - w) // HALF) * HALF
            y0 = rng.randint(MARGIN // HALF, (side - MARGIN - d) // HALF) * HALF
        b = Building(x0, y0, x0 + w, y0 + d, h)
        if b.x0 < MARGIN or b.y0 < MARGIN or b.x1 > side - MARGIN or b.y1 > side - MARGIN:
            continue
        if any(interiors_meet(b, c) for c in blds):
            continue
        blds.append(b)
    return blds


def building_triangles(rng, b, blds, split):
    """Wall and roof triangles of building b: (triangle, material). Each side is split where touching
    footprints cover it; a covered part is exposed above the neighbour's roof only."""
    tris = []
    cx2, cy2 = b.x0 + b.x1, b.y0 + b.y1
    # side: (fixed axis, fixed value, s range, outward normal, neighbours' touching coordinate test)
    sides = [
        (1, b.y0, b.x0, b.x1, (0, -1, 0), lambda c: c.y1 == b.y0, lambda c: (c.x0, c.x1)),
        (0, b.x1, b.y0, b.y1, (1, 0, 0), lambda c: c.x0 == b.x1, lambda c: (c.y0, c.y1)),
        (1, b.y1, b.x0, b.x1, (0, 1, 0), lambda c: c.y0 == b.y1, lambda c: (c.x0, c.x1)),
        (0, b.x0, b.y0, b.y1, (-1, 0, 0), lambda c: c.x1 == b.x0, lambda c: (c.y0, c.y1)),
    ]
    for axis, fixed, s0, s1, normal, touches, span in sides:
        covers = []   # (a, b, neighbour height)
        for c in blds:
            if c is b or not touches(c):
                continue
            a0, a1 = span(c)
            lo, hi = max(s0, a0), min(s1, a1)
            if hi > lo:
                covers.append((lo, hi, c.h))
        breaks = sorted({s0, s1} | {p for lo, hi, _ in covers for p in (lo, hi)})
        pieces = []   # (sa, sb, zlo) merged
        for sa, sb in zip(breaks, breaks[1:]):
            zlo = 0
            for lo, hi, hc in covers:
                if lo <= sa and sb <= hi:
                    zlo = hc
            if pieces and pieces[-1][1] == sa and pieces[-1][2] == zlo:
                pieces[-1] = (pieces[-1][0], sb, zlo)
            else:
                pieces.append((sa, sb, zlo))

        def P(s, z):
            return (fixed, s, z) if axis == 0 else (s, fixed, z)
        for sa, sb, zlo in pieces:
            if zlo >= b.h:
                continue
            k = min(split, max(1, (sb - sa) // Q))   # strips at least 1 m wide
            cuts = [sa + (2 * (sb - sa) * i + k) // (2 * k) for i in range(k + 1)]
            for u, v in zip(cuts, cuts[1:]):
                quad = [P(u, zlo), P(v, zlo), P(v, b.h), P(u, b.h)]
                if rng.random() < 0.5:
                    pair = [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
                else:
                    pair = [(quad[0], quad[1], quad[3]), (quad[1], quad[2], quad[3])]
                for t in pair:
                    tris.append((oriented(t, normal), "wall"))
    r = [(b.x0, b.y0, b.h), (b.x1, b.y0, b.h), (b.x1, b.y1, b.h), (b.x0, b.y1, b.h)]
    pair = [(r[0], r[1], r[2]), (r[0], r[2], r[3])] if rng.random() < 0.5 else [(r[0], r[1], r[3]), (r[1], r[2], r[3])]
    for t in pair:
        tris.append((oriented(t, (0, 0, 1)), "roof"))
    assert all(idot(tri_normal(t), (cx2 - 2 * t[0][0], cy2 - 2 * t[0][1], 0)) < 0
               for t, m in tris if m == "wall"), "wall facing into its building"
    return tris


# ----------------------------------------------------------------------------- ground
def cell_lines(side, cell):
    lines = list(range(0, side, cell))
    return lines + [side]


def ground_rectangles(blds, side, cell):
    """The square less the footprints as axis-aligned rectangles (xa, ya, xb, yb): per G x G cell,
    bands between the footprint edges crossing it, free x-intervals in each band, bands with equal
    intervals merged."""
    lines = cell_lines(side, cell)
    # Footprints by cell (a footprint may span several cells).
    by_cell = defaultdict(list)
    for b in blds:
        for i in range(bisect_right(lines, b.x0) - 1, bisect_left(lines, b.x1)):
            for j in range(bisect_right(lines, b.y0) - 1, bisect_left(lines, b.y1)):
                by_cell[(i, j)].append(b)
    rects = []
    for i in range(len(lines) - 1):
        X0, X1 = lines[i], lines[i + 1]
        for j in range(len(lines) - 1):
            Y0, Y1 = lines[j], lines[j + 1]
            inside = [(max(X0, b.x0), max(Y0, b.y0), min(X1, b.x1), min(Y1, b.y1)) for b in by_cell.get((i, j), ())]
            inside = [f for f in inside if f[2] > f[0] and f[3] > f[1]]
            ys = sorted({Y0, Y1} | {y for f in inside for y in (f[1], f[3])})
            open_rects = {}   # (xa, xb) -> ya of a rectangle still growing upward
            for ya, yb in zip(ys, ys[1:]):
                blocked = sorted((f[0], f[2]) for f in inside if f[1] <= ya and yb <= f[3])
                free, x = [], X0
                for a, c in blocked:
                    if a > x:
                        free.append((x, a))
                    x = max(x, c)
                if x < X1:
                    free.append((x, X1))
                grown = {}
                for iv in free:
                    grown[iv] = open_rects.pop(iv, ya)
                for (xa, xb), y0 in open_rects.items():
                    rects.append((xa, y0, xb, ya))
                open_rects = grown
            for (xa, xb), y0 in open_rects.items():
                rects.append((xa, y0, xb, Y1))
    return rects


def triangulate_convex(poly):
    """Triangles of a convex polygon (CCW, 2D) that may have collinear vertices, without Steiner
    points and without degenerate triangles: clip the ear with the largest smallest angle among the
    strictly convex vertices whose removal leaves a polygon of positive area."""
    poly = list(poly)
    tris = []

    def area2(p):
        return sum(p[k][0] * p[(k + 1) % len(p)][1] - p[(k + 1) % len(p)][0] * p[k][1] for k in range(len(p)))

    def min_angle(a, b, c):
        la = math.dist(b, c)
        lb = math.dist(a, c)
        lc = math.dist(a, b)
        cosines = [(lb * lb + lc * lc - la * la) / (2 * lb * lc), (la * la + lc * lc - lb * lb) / (2 * la * lc),
                   (la * la + lb * lb - lc * lc) / (2 * la * lb)]
        return min(math.acos(max(-1.0, min(1.0, x))) for x in cosines)

    while len(poly) > 3:
        best = None
        n = len(poly)
        for k in range(n):
            u, v, w = poly[k - 1], poly[k], poly[(k + 1) % n]
            if cross2(u, v, w) <= 0:
                continue
            rest = poly[:k] + poly[k + 1:]
            if area2(rest) <= 0:
                continue
            q = min_angle(u, v, w)
            if best is None or q > best[0]:
                best = (q, k)
        assert best is not None, "no ear in %r" % (poly,)
        k = best[1]
        tris.append((poly[k - 1], poly[k], poly[(k + 1) % n]))
        del poly[k]
    assert cross2(*poly) > 0
    tris.append(tuple(poly))
    return tris


def ground_triangles(blds, side, cell):
    """Ground triangles (z = 0, facing up), conforming among themselves: each rectangle is
    triangulated with every rectangle corner that lies on its boundary."""
    rects = ground_rectangles(blds, side, cell)
    by_x, by_y = defaultdict(set), defaultdict(set)
    for xa, ya, xb, yb in rects:
        for x, y in ((xa, ya), (xb, ya), (xb, yb), (xa, yb)):
            by_x[x].add(y)
            by_y[y].add(x)
    by_x = {k: sorted(v) for k, v in by_x.items()}
    by_y = {k: sorted(v) for k, v in by_y.items()}

    def between(lst, a, b):
        return lst[bisect_right(lst, a):bisect_left(lst, b)]
    tris = []
    for xa, ya, xb, yb in rects:
        poly = [(xa, ya)] + [(x, ya) for x in between(by_y[ya], xa, xb)]
        poly += [(xb, ya)] + [(xb, y) for y in between(by_x[xb], ya, yb)]
        poly += [(xb, yb)] + [(x, yb) for x in reversed(between(by_y[yb], xa, xb))]
        poly += [(xa, yb)] + [(xa, y) for y in reversed(between(by_x[xa], ya, yb))]
        for t in triangulate_convex(poly):
            tris.append(tuple((p[0], p[1], 0) for p in t))
    return tris, len(rects)


# ----------------------------------------------------------------------------- mesh statistics
def mesh_stats(faces):
    """faces: [(triangle, kind)]. Returns edges, T-junction vertices (a vertex strictly inside an
    edge of another triangle, exact on the lattice), their kinds, slivers."""
    index = {}
    tri_ids = []
    for t, _ in faces:
        tri_ids.append(tuple(index.setdefault(p, len(index)) for p in t))
    verts = [None] * len(index)
    for p, k in index.items():
        verts[k] = p
    vkinds = defaultdict(set)
    edges = {}
    for (t, kind), ids in zip(faces, tri_ids):
        for k in range(3):
            vkinds[ids[k]].add(kind)
            a, b = ids[k], ids[(k + 1) % 3]
            edges.setdefault((min(a, b), max(a, b)), set()).add(kind)
    # Axis-aligned lines: coordinate along the axis, sorted, per (other two coordinates).
    lines = [defaultdict(list) for _ in range(3)]
    for k, p in enumerate(verts):
        for ax in range(3):
            lines[ax][tuple(p[m] for m in range(3) if m != ax)].append((p[ax], k))
    for ax in range(3):
        for key in lines[ax]:
            lines[ax][key].sort()
    inside = defaultdict(set)   # vertex -> kinds of the edges it lies inside
    for (a, b), ekinds in edges.items():
        pa, pb = verts[a], verts[b]
        d = isub(pb, pa)
        moving = [ax for ax in range(3) if d[ax] != 0]
        if len(moving) == 1:
            ax = moving[0]
            lst = lines[ax][tuple(pa[m] for m in range(3) if m != ax)]
            lo, hi = sorted((pa[ax], pb[ax]))
            i = bisect_right(lst, (lo, len(verts)))
            while i < len(lst) and lst[i][0] < hi:
                inside[lst[i][1]] |= ekinds
                i += 1
        else:   # the lattice points strictly inside the segment
            g = math.gcd(math.gcd(abs(d[0]), abs(d[1])), abs(d[2]))
            step = (d[0] // g, d[1] // g, d[2] // g)
            for s in range(1, g):
                k = index.get((pa[0] + s * step[0], pa[1] + s * step[1], pa[2] + s * step[2]))
                if k is not None:
                    inside[k] |= ekinds
    kinds = Counter(k for ek in inside.values() for k in ek)   # T-junctions by the kind of edge they lie inside
    slivers = 0
    for t, _ in faces:
        n = tri_normal(t)
        area2 = math.sqrt(idot(n, n))
        longest = max(idot(isub(t[k], t[k - 1]), isub(t[k], t[k - 1])) for k in range(3))
        if longest / area2 > SLIVER:
            slivers += 1
    return dict(vertices=len(verts), edges=len(edges), tjunctions=len(inside), tkinds=kinds, slivers=slivers)


# ----------------------------------------------------------------------------- scene
def build(n, seed, cell_m, split, closed):
    rng = random.Random(seed)
    cell = int(round(cell_m * Q))
    assert cell >= Q and abs(cell - cell_m * Q) < 1e-9, "--ground-cell must be >= 1 m, a multiple of 1/8 m"
    side = max(60, int(math.ceil(math.sqrt(n * SITE) / 10.0)) * 10) * Q
    blds = place_buildings(rng, n, side)
    faces = []     # (triangle, kind); kind is the material
    objects = []   # (object name, [(triangle, material)])
    gtris, nrects = ground_triangles(blds, side, cell)
    objects.append(("ground", [(t, "ground") for t in gtris]))
    width = max(2, len(str(n)))
    for k, b in enumerate(blds):
        objects.append(("building_%0*d" % (width, k + 1), building_triangles(rng, b, blds, split)))
    top = 0
    if closed:
        top = (max(b.h for b in blds) // Q + 20) * Q
        c = [(0, 0), (side, 0), (side, side), (0, side)]
        enc = []
        for k in range(4):
            (xa, ya), (xb, yb) = c[k], c[(k + 1) % 4]
            quad = [(xa, ya, 0), (xb, yb, 0), (xb, yb, top), (xa, ya, top)]
            inward = (side - xa - xb, side - ya - yb, 0)
            for t in [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]:
                enc.append((oriented(t, inward), "enclosure"))
        cz = [(x, y, top) for x, y in c]
        for t in [(cz[0], cz[1], cz[2]), (cz[0], cz[2], cz[3])]:
            enc.append((oriented(t, (0, 0, -1)), "enclosure_sky"))
        objects.append(("enclosure", enc))
    for _, tris in objects:
        faces.extend(tris)

    # Checks: valid triangles, orientations, the ground covers the square less the footprints.
    for t, m in faces:
        nrm = tri_normal(t)
        assert nrm != (0, 0, 0)
        if m in ("ground", "roof"):
            assert nrm[0] == 0 and nrm[1] == 0 and nrm[2] > 0, (m, t)
        elif m == "wall":
            assert nrm[2] == 0, t
    for a in range(len(blds)):
        for b in range(a + 1, len(blds)):
            assert not interiors_meet(blds[a], blds[b])
    ground2 = sum(tri_normal(t)[2] for t in gtris)           # twice the area, ticks^2
    expected2 = 2 * (side * side - sum(b.area() for b in blds))
    assert ground2 == expected2, (ground2, expected2)
    assert abs(ground2 - expected2) <= 1e-9 * expected2
    pairs = [(a, b) for i, a in enumerate(blds) for b in blds[i + 1:] if shared_wall(a, b) > 0]
    info = dict(side=side, cell=cell, buildings=len(blds), rects=nrects, top=top,
                shared=len(pairs), flush=sum(1 for a, b in pairs if a.h == b.h),
                footprint=sum(b.area() for b in blds))
    return objects, faces, info


def main():
    ap = argparse.ArgumentParser(description="Non-conforming urban district (triangles, z up, metres).")
    ap.add_argument("out_dir")
    ap.add_argument("--preset", choices=sorted(PRESETS), default="1k",
                    help="1k: 28 buildings, 20 m cells, 2 wall strips (default); "
                         "25k: 380 buildings, 8 m cells, 3 strips")
    ap.add_argument("--buildings", type=int, help="number of buildings N")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--ground-cell", type=float, help="ground cell G (m, multiple of 1/8)")
    ap.add_argument("--wall-split", type=int, help="vertical strips K per wall (2 triangles each)")
    ap.add_argument("--name", help="output name (default district<preset>, _closed with --closed)")
    ap.add_argument("--closed", action="store_true",
                    help="add an enclosing box (walls and emitting ceiling facing inward): a closed enclosure")
    args = ap.parse_args()
    p = PRESETS[args.preset]
    n = args.buildings if args.buildings is not None else p["buildings"]
    cell = args.ground_cell if args.ground_cell is not None else p["cell"]
    split = args.wall_split if args.wall_split is not None else p["split"]
    if n < 1 or split < 1:
        ap.error("--buildings and --wall-split must be >= 1")
    if not (cell >= 1.0 and cell * Q == int(cell * Q)):
        ap.error("--ground-cell must be >= 1 m and a multiple of 1/8 m")
    name = args.name or "district%s%s" % (args.preset, "_closed" if args.closed else "")

    objects, faces, info = build(n, args.seed, cell, split, args.closed)
    stats = mesh_stats(faces)

    w = ObjWriter()
    for obj, tris in objects:
        w.object = obj
        for t, m in tris:
            w.face([(p[0] / Q, p[1] / Q, p[2] / Q) for p in t], None, m)
    os.makedirs(args.out_dir, exist_ok=True)
    L = info["side"] / Q
    counts = Counter(m for _, m in faces)
    desc = ("Non-conforming urban district: %d box buildings on a %g m square ground (%g m cells), walls in %d "
            "strip(s) of 2 triangles%s; seed %d; %d triangles, %d T-junctions"
            % (info["buildings"], L, info["cell"] / Q, split, ", closed by an enclosing box" if args.closed else "",
               args.seed, len(faces), stats["tjunctions"]))
    if args.closed:   # inside the enclosure, under its ceiling, looking north over the district
        eye, target = (0.5 * L, 2.0, info["top"] / Q - 10.0), (0.5 * L, 0.55 * L, 0.0)
    else:             # an aerial view from the south
        eye, target = (0.5 * L, -0.45 * L, 0.75 * L), (0.5 * L, 0.45 * L, 0.0)
    camera = "# hemirad camera %g %g %g %g %g %g %g" % (eye + target + (75 if args.closed else 50,))
    w.write(os.path.join(args.out_dir, name + ".obj"), desc, name + ".mtl",
            ["# hemirad unit m",
             "# hemirad up z",
             camera,
             "# Ground and roofs face up (+z), walls outward, enclosure inward. Units m, z up.",
             "# Objects: ground, building_NN%s. Generated by scenes/generators/district.py." %
             (", enclosure" if args.closed else "")])
    write_mtl(os.path.join(args.out_dir, name + ".mtl"), "Materials for %s.obj (Kd diffuse, Ke emission)" % name,
              MATERIALS + (ENCLOSURE_MATERIALS if args.closed else []))
    by_kind = sorted(stats["tkinds"].items(), key=lambda kv: (-kv[1], kv[0]))
    kinds = ", ".join("%d in %s edges" % (c, k) for k, c in by_kind)
    if stats["slivers"] == 0:
        print("district.py: warning: no slivers (thin ground strips need footprint edges near cell lines)",
              file=sys.stderr)
    print("%s: %d triangles (ground %d, walls %d, roofs %d%s); %d buildings (%d touching pairs, %d flush roofs); "
          "%d T-junctions (%s); %d slivers; %d edges, %d vertices"
          % (name, len(faces), counts["ground"], counts["wall"], counts["roof"],
             ", enclosure %d" % (counts["enclosure"] + counts["enclosure_sky"]) if args.closed else "",
             info["buildings"], info["shared"], info["flush"], stats["tjunctions"], kinds, stats["slivers"],
             stats["edges"], stats["vertices"]))


if __name__ == "__main__":
    main()
