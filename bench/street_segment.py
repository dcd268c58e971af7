#!/usr/bin/env python3
"""Cut a segment of street64k for measurements the whole street is too large for (issue 16's mirror
terms by images against rays: the analytic estimator is O(N^2) pairs, hours at 64 k patches).

Usage: street_segment.py STREET64K.obj OUT.obj X0 X1

Keeps the faces whose vertices all lie in X0 <= x <= X1 (buildings, ground, windows) and the whole
sky dome, renumbers the vertices, and points OUT.obj at street64k.mtl (copy it beside OUT.obj).
X0 = -60, X1 = -36 gives 10,039 patches with 108 mirror windows.
"""
import sys


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    source, target, x0, x1 = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    lines = open(source).read().split("\n")
    xs = [float(line.split()[1]) for line in lines if line.startswith("v ")]
    renumbered, body = {}, []
    current_object = current_material = written_object = written_material = None
    for line in lines:
        if line.startswith("o "):
            current_object = line
        elif line.startswith("usemtl"):
            current_material = line
        elif line.startswith("f "):
            corners = [int(token.split("/")[0]) for token in line.split()[1:]]
            if current_object != "o sky" and not all(x0 <= xs[c - 1] <= x1 for c in corners):
                continue
            if current_object != written_object:
                body.append(current_object)
                written_object, written_material = current_object, None
            if current_material != written_material:
                body.append(current_material)
                written_material = current_material
            body.append("f " + " ".join(str(renumbered.setdefault(c, len(renumbered) + 1)) for c in corners))
    vertices = [line for line in lines if line.startswith("v ")]
    with open(target, "w") as out:
        out.write("mtllib street64k.mtl\n")
        for c in sorted(renumbered, key=renumbered.get):
            out.write(vertices[c - 1] + "\n")
        out.write("\n".join(body) + "\n")


if __name__ == "__main__":
    main()
