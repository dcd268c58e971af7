#!/usr/bin/env python3
"""Writes the STL files of the malformed corpus (tests/data/malformed/*.stl); run from the repository root.

The binary ones cannot be written by hand; this script is how they were made. Each file's expected
message is in tests/engine/test_malformed_corpus.cpp.
"""
import math
import struct

OUT = "tests/data/malformed/"

# Two triangles of the unit square in z = 0, facing +z.
SQUARE = [((0, 0, 1), (0, 0, 0), (1, 0, 0), (1, 1, 0)),
          ((0, 0, 1), (0, 0, 0), (1, 1, 0), (0, 1, 0))]


def binary(triangles, count=None, header=b"hemirad malformed corpus"):
    out = header.ljust(80, b" ") + struct.pack("<I", len(triangles) if count is None else count)
    for normal, *vertices in triangles:
        out += struct.pack("<3f", *normal)
        for v in vertices:
            out += struct.pack("<3f", *v)
        out += struct.pack("<H", 0)
    return out


def write(name, data):
    with open(OUT + name, "wb") as f:
        f.write(data)


whole = binary(SQUARE)
write("stl_truncated.stl", whole[:84 + 50 + 30])                    # cut inside triangle 1
write("stl_wrong_count.stl", binary(SQUARE + [SQUARE[0]], count=2))  # 3 triangles, header says 2
nan = [SQUARE[0], (SQUARE[1][0], SQUARE[1][1], SQUARE[1][2], (math.nan, 1, 0))]
write("stl_nan_vertex.stl", binary(nan))                             # triangle 1, third vertex x
# A binary file whose header starts with "solid", as many exporters write it, cut short: the size
# test fails, and the NUL bytes keep it from being read as ASCII.
write("stl_solid_header_truncated.stl", binary(SQUARE, header=b"solid square")[:150])
write("stl_empty.stl", b"")
write("stl_zero_area.stl", b"""solid square
  facet normal 0 0 1
    outer loop
      vertex 0 0 0
      vertex 1 0 0
      vertex 1 1 0
    endloop
  endfacet
  facet normal 0 0 1
    outer loop
      vertex 0 0 0
      vertex 1 1 0
      vertex 2 2 0
    endloop
  endfacet
endsolid square
""")
write("stl_facet_not_closed.stl", b"""solid square
  facet normal 0 0 1
    outer loop
      vertex 0 0 0
      vertex 1 0 0
      vertex 1 1 0
    endloop
endsolid square
""")
write("stl_four_vertices.stl", b"""solid square
  facet normal 0 0 1
    outer loop
      vertex 0 0 0
      vertex 1 0 0
      vertex 1 1 0
      vertex 0 1 0
    endloop
  endfacet
endsolid square
""")
