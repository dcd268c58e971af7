#!/usr/bin/env python3
"""View factors and radiosity of a room with a table in it, with Hemirad's Python module.

A 4 m x 3 m room, 2.5 m high, lit by its ceiling (100 W/m^2), subdivided into patches. The script
1. computes F of the empty room and compares its wall-to-wall factors with the closed forms
   (Howell C-11 for parallel, C-14 for perpendicular rectangles);
2. puts a table (a 1.2 m x 0.8 m top at 0.75 m) into the room: it shades the floor;
3. solves the radiosity and plots the floor's irradiance-driven radiosity per patch (PNG).

    PYTHONPATH=build/python python3 examples/room_view_factors.py --out out
"""

import argparse
import math
import os
import tempfile

import numpy as np

import hemirad

W, D, H = 4.0, 3.0, 2.5  # room: x in [0, W], y in [0, D], z in [0, H]


def c11(a, b, c):
    """Howell C-11: parallel, directly opposed rectangles a x b at distance c."""
    x, y = a / c, b / c
    return 2 / (math.pi * x * y) * (
        math.log(math.sqrt((1 + x * x) * (1 + y * y) / (1 + x * x + y * y)))
        + x * math.sqrt(1 + y * y) * math.atan(x / math.sqrt(1 + y * y))
        + y * math.sqrt(1 + x * x) * math.atan(y / math.sqrt(1 + x * x))
        - x * math.atan(x) - y * math.atan(y))


def c14(w, h, l):
    """Howell C-14: perpendicular rectangles with a common edge l; from w x l to h x l."""
    W_, H_ = w / l, h / l
    s = W_ * W_ + H_ * H_
    a = (1 + W_ * W_) * (1 + H_ * H_) / (1 + s)
    b = (W_ * W_ * (1 + s) / ((1 + W_ * W_) * s)) ** (W_ * W_)
    c = (H_ * H_ * (1 + s) / ((1 + H_ * H_) * s)) ** (H_ * H_)
    return (W_ * math.atan(1 / W_) + H_ * math.atan(1 / H_) - math.sqrt(s) * math.atan(1 / math.sqrt(s))
            + 0.25 * math.log(a * b * c)) / (math.pi * W_)


def write_room(folder, table):
    """The room as OBJ + MTL, faces facing inwards (counter-clockwise seen from inside)."""
    quads = {
        "floor": [(0, 0, 0), (W, 0, 0), (W, D, 0), (0, D, 0)],
        "ceiling": [(0, 0, H), (0, D, H), (W, D, H), (W, 0, H)],
        "wall_south": [(0, 0, 0), (0, 0, H), (W, 0, H), (W, 0, 0)],  # y = 0
        "wall_north": [(0, D, 0), (W, D, 0), (W, D, H), (0, D, H)],  # y = D
        "wall_west": [(0, 0, 0), (0, D, 0), (0, D, H), (0, 0, H)],   # x = 0
        "wall_east": [(W, 0, 0), (W, 0, H), (W, D, H), (W, D, 0)],   # x = W
    }
    if table:  # a top seen from above and from below
        x0, x1, y0, y1, z = 1.4, 2.6, 1.1, 1.9, 0.75
        quads["table_top"] = [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]
        quads["table_underside"] = [(x0, y0, z), (x0, y1, z), (x1, y1, z), (x1, y0, z)]
    materials = {"floor": "floor", "ceiling": "light", "table_top": "wood", "table_underside": "wood"}
    path = os.path.join(folder, "room_table.obj" if table else "room.obj")
    with open(path, "w") as obj:
        obj.write("mtllib room.mtl\n")
        for k, (name, corners) in enumerate(quads.items()):
            for v in corners:
                obj.write("v %g %g %g\n" % v)
            obj.write(f"o {name}\nusemtl {materials.get(name, 'wall')}\n")
            obj.write("f %d %d %d %d\n" % tuple(4 * k + i + 1 for i in range(4)))
    with open(os.path.join(folder, "room.mtl"), "w") as mtl:
        mtl.write("newmtl wall\nKd 0.5 0.5 0.5\nnewmtl floor\nKd 0.3 0.3 0.3\n"
                  "newmtl wood\nKd 0.4 0.3 0.2\nnewmtl light\nKd 0.8 0.8 0.8\nKe 100 100 100\n")
    return path


def surface_factor(scene, F, source, target):
    """F from surface `source` to `target` (object names): the area-weighted mean over its patches."""
    names = np.asarray(scene.object_names)[scene.object]
    i, j = names == source, names == target
    area = scene.area
    return float((area[i] @ F[i][:, j].sum(axis=1)) / area[i].sum())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="out", help="folder for the plot (default out)")
    parser.add_argument("--divisions", type=int, default=8, help="patches per metre along an edge (default 8)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    edge = 1.0 / args.divisions

    with tempfile.TemporaryDirectory() as folder:
        empty = hemirad.load(write_room(folder, table=False), subdivide=edge)
        F, report = hemirad.form_factors(empty, all_rows=True)
        print(f"empty room: {len(empty)} patches, F in {report['seconds']['compute']:.2f} s, "
              f"{F.nnz} nonzeros, row sums {report['row_sum_min']:.6f} .. {report['row_sum_max']:.6f}")
        print(f"{'factor':24} {'Hemirad':>10} {'closed form':>12} {'difference':>11}")
        for source, target, exact in [
            ("floor", "ceiling", c11(W, D, H)),
            ("floor", "wall_south", c14(D, H, W)),
            ("floor", "wall_west", c14(W, H, D)),
            ("wall_west", "wall_east", c11(D, H, W)),
        ]:
            value = surface_factor(empty, F, source, target)
            print(f"{source + ' -> ' + target:24} {value:10.6f} {exact:12.6f} {value - exact:11.2e}")

        room = hemirad.load(write_room(folder, table=True), subdivide=edge)
        F, report = hemirad.form_factors(room)
        print(f"with the table: {len(room)} patches; floor -> ceiling {surface_factor(room, F, 'floor', 'ceiling'):.6f}")
        B, _ = hemirad.solve(room, F)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    names = np.asarray(room.object_names)[room.object]
    floor = np.flatnonzero(names == "floor")
    polygons = [room.polygon(i)[:, :2] for i in floor]
    figure, axes = plt.subplots(figsize=(7, 5))
    patches = PolyCollection(polygons, array=B[floor, 0], cmap="inferno", edgecolors="none")
    axes.add_collection(patches)
    axes.set_xlim(0, W)
    axes.set_ylim(0, D)
    axes.set_aspect("equal")
    axes.set_title("Floor radiosity under a table, lit by the ceiling")
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    figure.colorbar(patches, label="B (W/m$^2$)")
    output = os.path.join(args.out, "room_radiosity.png")
    figure.savefig(output, dpi=100)
    print(f"floor B {B[floor, 0].min():.2f} .. {B[floor, 0].max():.2f} W/m^2; plot: {output}")


if __name__ == "__main__":
    main()
