#!/usr/bin/env python3
"""Do the lines depend on the resolution? (issue 19, "Resolution")

usage: resolution.py CRESTLINE_BINARY [METHOD ...]      (default methods: hpw ybs)

For each public surface of ../shared/quality, reg20k is refined once by Loop subdivision
(`crestline subdivide`, about 80K faces) and every vertex is put back on the exact surface
(radially for the ellipsoid and the superquadric, to the nearest point for the torus, z = f(x, y)
for the height field), so that the finer mesh samples the same surface. Then both meshes go
through `crestline extract --method METHOD` with default settings and the two line sets are
compared like score.py compares lines with the exact ones: the share of each set's length within
1% of the diagonal of a line of the same kind in the other, and their F1. On the torus (no
crest lines) the detected lengths per diagonal are printed.

The bumpy sphere is left out: its bumps are not given in closed form, and Loop subdivision
without projection is not the same surface to third order (its curvature ripples at the scale of
the coarse edges), which is what crest lines measure.
Needs numpy and scipy.
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

QUALITY = Path(__file__).resolve().parents[2].parent / "shared" / "quality"
sys.path.insert(0, str(QUALITY))
from score import read_polylines  # noqa: E402


def onto_ring(p):
    c = np.array([p[0], p[1], 0.0])
    c /= np.linalg.norm(c)
    return c + (p - c) / np.linalg.norm(p - c) * 0.3


PROJECT = {
    "ovoid": lambda p: p / np.sqrt(p[0] ** 2 + (p[1] / 0.75) ** 2 + (p[2] / 0.5) ** 2),
    "superquadric": lambda p: p / (p[0] ** 4 + p[1] ** 4 + p[2] ** 4) ** 0.25,
    "ring": onto_ring,
    "ridge": lambda p: np.array([p[0], p[1], 0.3 * np.exp(-((p[0] - 0.3 * np.sin(2 * p[1])) ** 2) / 0.15)]),
}


def project_obj(path, project):
    out = []
    for line in Path(path).read_text().splitlines():
        if line.startswith("v "):
            p = project(np.array([float(x) for x in line.split()[1:4]]))
            line = "v %.15g %.15g %.15g" % tuple(p)
        out.append(line)
    Path(path).write_text("\n".join(out) + "\n")


def samples(polys, kind, step):
    pts, weights = [], []
    for label, p in polys:
        if kind not in label:
            continue
        for a, b in zip(p[:-1], p[1:]):
            length = np.linalg.norm(b - a)
            n = max(1, int(np.ceil(length / step)))
            t = (np.arange(n) + 0.5) / n
            pts.append(a + np.outer(t, b - a))
            weights.append(np.full(n, length / n))
    if not pts:
        return np.zeros((0, 3)), np.zeros(0)
    return np.concatenate(pts), np.concatenate(weights)


def covered(a, b, tau):
    if len(a[0]) == 0:
        return 0.0, 0.0
    if len(b[0]) == 0:
        return 0.0, a[1].sum()
    d, _ = cKDTree(b[0]).query(a[0])
    return a[1][d <= tau].sum(), a[1].sum()


def main():
    binary = sys.argv[1]
    methods = sys.argv[2:] or ["hpw", "ybs"]
    index = json.loads((QUALITY / "cases" / "index.json").read_text())
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        print("| surface | method | reg20k lines near 80K lines | 80K lines near reg20k lines | F1 |")
        print("| --- | --- | ---: | ---: | ---: |")
        for surface, project in PROJECT.items():
            coarse = QUALITY / "cases" / surface / "reg20k.obj"
            fine = tmp / f"{surface}-80k.obj"
            subprocess.run([binary, "subdivide", str(coarse), "-o", str(fine)], check=True, capture_output=True)
            project_obj(fine, project)
            diag = index[surface]["diag"]
            tau = 0.01 * diag
            for method in methods:
                lines = []
                for mesh in (coarse, fine):
                    out = tmp / f"{surface}-{method}-{mesh.stem}-lines.obj"
                    subprocess.run(
                        [binary, "extract", str(mesh), "-o", str(out), "--method", method, "-q"], check=True
                    )
                    lines.append(read_polylines(out))
                if surface == "ring":
                    lengths = [sum(np.linalg.norm(np.diff(p, axis=0), axis=1).sum() for _, p in ls) / diag for ls in lines]
                    print(f"| ring | {method} | spurious {lengths[0]:.3f} diagonals | spurious {lengths[1]:.3f} diagonals | |")
                    continue
                near = [0.0, 0.0]
                total = [0.0, 0.0]
                for kind in ("ridge", "valley"):
                    a = samples(lines[0], kind, tau / 4)
                    b = samples(lines[1], kind, tau / 4)
                    for i, (x, y) in enumerate((covered(a, b, tau), covered(b, a, tau))):
                        near[i] += x
                        total[i] += y
                p, r = (near[i] / total[i] if total[i] > 0 else 0.0 for i in range(2))
                f1 = 2 * p * r / (p + r) if p + r > 0 else 0.0
                print(f"| {surface} | {method} | {p:.3f} | {r:.3f} | **{f1:.3f}** |", flush=True)


if __name__ == "__main__":
    main()
