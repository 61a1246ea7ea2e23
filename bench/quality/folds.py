#!/usr/bin/env python3
"""Do the corrected lines fold back? (lines/debias.rs, step 4)

usage: folds.py CRESTLINE_BINARY MESH [MESH ...]

Each mesh goes through `crestline extract` with default settings and again with --no-debias;
the two line sets have the same lines, point for point, before and after the correction. A
segment of a corrected line that points against the same segment of the traced line (their dot
product not positive) is a fold: the correction turned the line back on itself. Prints, per
mesh, the folded segments, the lines they are in and the segments compared.
"""
import subprocess
import sys
import tempfile
from pathlib import Path


def read_lines(path):
    """Polylines of a crestline OBJ line file: vertices, then `l` elements."""
    vertices, lines = [], []
    for row in Path(path).read_text().splitlines():
        parts = row.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append(tuple(float(x) for x in parts[1:4]))
        elif parts[0] == "l":
            lines.append([vertices[int(i) - 1] for i in parts[1:]])
    return lines


def folds(corrected, traced):
    folded = lines = total = 0
    for a, b in zip(corrected, traced):
        if len(a) != len(b):
            continue
        here = 0
        for k in range(len(a) - 1):
            da = [a[k + 1][i] - a[k][i] for i in range(3)]
            db = [b[k + 1][i] - b[k][i] for i in range(3)]
            here += sum(x * y for x, y in zip(da, db)) <= 0.0
        total += len(a) - 1
        folded += here
        lines += here > 0
    return folded, lines, total


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    binary = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        for mesh in sys.argv[2:]:
            outs = []
            for extra in ([], ["--no-debias"]):
                out = Path(tmp) / f"lines{len(outs)}.obj"
                subprocess.run([binary, "extract", mesh, "-o", str(out), "-q", *extra], check=True)
                outs.append(read_lines(out))
            folded, lines, total = folds(*outs)
            print(f"{Path(mesh).name}: {folded} folded segments in {lines} lines, of {total}")


if __name__ == "__main__":
    main()
