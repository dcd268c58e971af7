"""Shared helpers of the scene generators: small vector maths and an OBJ/MTL writer that writes each
distinct vertex once and orients faces toward a wanted side."""

# ----------------------------------------------------------------------------- small vector helpers
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def newell(pts):
    n = [0.0, 0.0, 0.0]
    for k, a in enumerate(pts):
        b = pts[(k + 1) % len(pts)]
        n[0] += (a[1] - b[1]) * (a[2] + b[2])
        n[1] += (a[2] - b[2]) * (a[0] + b[0])
        n[2] += (a[0] - b[0]) * (a[1] + b[1])
    return tuple(n)


# ----------------------------------------------------------------------------- OBJ writer
class ObjWriter:
    """Collects faces; writes each distinct vertex (by its formatted text) once."""

    FMT = "%.4f"

    def __init__(self):
        self.vertex_text = []
        self.vertex_index = {}
        self.records = []          # (object, material, [indices])
        self.object = "default"
        self.material = None
        self.counts = [0, 0, 0]    # triangles, quads, other
        self.shift_x = 0.0         # added to every vertex's x (tiled copies of a layout)

    def number(self, c):
        text = self.FMT % c
        return "0.0000" if text == "-0.0000" else text

    def vertex(self, p):
        p = (p[0] + self.shift_x, p[1], p[2])
        key = " ".join(self.number(c) for c in p)
        idx = self.vertex_index.get(key)
        if idx is None:
            self.vertex_text.append(key)
            idx = len(self.vertex_text)
            self.vertex_index[key] = idx
        return idx

    def face(self, pts, want=None, material=None):
        """Add a polygon. If `want` is given, the polygon is reversed when its right-hand-rule
        normal points away from `want` (a direction, or a callable centroid -> direction)."""
        if want is not None:
            c = (0.0, 0.0, 0.0)
            for p in pts:
                c = add(c, p)
            c = mul(c, 1.0 / len(pts))
            w = want(c) if callable(want) else want
            if dot(newell(pts), w) < 0.0:
                pts = list(reversed(pts))
        idx = [self.vertex(p) for p in pts]
        assert len(set(idx)) == len(idx), "face with repeated vertex"
        self.records.append((self.object, material or self.material, idx))
        n = len(idx)
        self.counts[0 if n == 3 else 1 if n == 4 else 2] += 1

    def write(self, obj_path, header, mtl_name, extra_header=()):
        with open(obj_path, "w") as f:
            f.write("# " + header + "\n")
            f.write("mtllib %s\n" % mtl_name)
            for line in extra_header:
                f.write(line + "\n")
            for v in self.vertex_text:
                f.write("v " + v + "\n")
            obj = mat = None
            for o, m, idx in self.records:
                if o != obj:
                    f.write("o %s\n" % o)
                    obj = o
                    mat = None
                if m != mat:
                    f.write("usemtl %s\n" % m)
                    mat = m
                f.write("f " + " ".join(str(i) for i in idx) + "\n")


def write_mtl(path, header, materials):
    with open(path, "w") as f:
        f.write("# " + header + "\n")
        for name, kd, ke, s in materials:
            assert max(kd) + s <= 1.0
            f.write("\nnewmtl %s\n" % name)
            f.write("Kd %.6g %.6g %.6g\n" % kd)
            f.write("Ks %.6g %.6g %.6g\n" % (s, s, s))
            f.write("Ke %.6g %.6g %.6g\n" % ke)
            f.write("illum %d\n" % (3 if s > 0 else 1))
