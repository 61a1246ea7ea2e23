#!/usr/bin/env python3
"""Tessellations a CAD exporter writes for round parts, made of long thin triangles.

usage: slivers.py OUT_DIR

Writes, as OBJ files:
- cylinder-N.obj (N = 1024, 2048, 8192): a closed cylinder of radius 1 and height 4 whose caps
  are fans of N slivers from their centres and whose side is N strips of two triangles as long
  as the cylinder;
- fan-2000.obj: an open fan of 2,000 slivers around one corner, 1000 long and 0.02 wide at
  the rim;
- ngon-3000.obj: a disc given as one face of 3,000 corners (readers triangulate it as a fan).

The jet fit samples such discs on their triangles (`curvature/jet_fit/surface.rs`); time them
with `/usr/bin/time crestline extract MESH -o lines.obj -q` (BENCHMARKS.md's table: wall seconds
of the whole run; `--stats` gives the stages, the curvature stage is most of it).
"""
import math
import sys
from pathlib import Path


def write(path, vertices, faces):
    with open(path, "w") as out:
        for v in vertices:
            out.write("v %.12g %.12g %.12g\n" % v)
        for f in faces:
            out.write("f " + " ".join(str(i + 1) for i in f) + "\n")


def cylinder(n, height=4.0):
    ring = [(math.cos(2 * math.pi * j / n), math.sin(2 * math.pi * j / n)) for j in range(n)]
    vertices = [(0.0, 0.0, 0.0), (0.0, 0.0, height)]
    vertices += [(x, y, 0.0) for x, y in ring] + [(x, y, height) for x, y in ring]
    bottom = lambda j: 2 + j % n
    top = lambda j: 2 + n + j % n
    faces = []
    for j in range(n):
        faces.append((0, bottom(j + 1), bottom(j)))
        faces.append((1, top(j), top(j + 1)))
        faces.append((bottom(j), bottom(j + 1), top(j + 1)))
        faces.append((bottom(j), top(j + 1), top(j)))
    return vertices, faces


def fan(n, length=1000.0, width=0.02):
    vertices = [(0.0, 0.0, 0.0)]
    for j in range(n + 1):
        angle = j * width / length
        vertices.append((length * math.cos(angle), length * math.sin(angle), 0.0))
    return vertices, [(0, j + 1, j + 2) for j in range(n)]


def ngon(n):
    vertices = [(math.cos(2 * math.pi * j / n), math.sin(2 * math.pi * j / n), 0.0) for j in range(n)]
    return vertices, [tuple(range(n))]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for n in (1024, 2048, 8192):
        write(out / f"cylinder-{n}.obj", *cylinder(n))
    write(out / "fan-2000.obj", *fan(2000))
    write(out / "ngon-3000.obj", *ngon(3000))


if __name__ == "__main__":
    main()
