#!/usr/bin/env python3
"""Exact-answer cases meshed as marching cubes leaves them: vertices not projected.

usage: mc_raw.py OUTDIR [--cases ../shared/quality/cases] [--cells 30] [--only NAME ...]

The public `mc` meshes are marching cubes of the implicit surface with every vertex projected
onto it. Marching cubes as users run it (scikit-image, VTK, Open3D, CGAL) puts each vertex where
the linear interpolation of the function along a grid edge crosses zero, off the surface by up
to about h^2 f'' / (8 f') for grid spacing h: terraces where the surface crosses the grid's
planes. This writes, for the public surfaces given by an implicit function here (ovoid,
superquadric, ring), OUTDIR/NAME/mcraw.obj: scikit-image's marching cubes on a grid of CELLS
cells per unit length, the vertices as it returns them; beside links to the surface's
truth_lines.npz and .obj, listed in OUTDIR/index.json, so that the public scorer runs on them:

    python3 bench/quality/mc_raw.py /tmp/mcraw --cells 30
    python3 ../shared/quality/score.py 'target/release/crestline extract {in} -o {out} -q' \\
        --cases /tmp/mcraw

Needs numpy and scikit-image.
"""
import argparse
import json
from pathlib import Path

import numpy as np
from skimage.measure import marching_cubes

from noisy_cases import open_case_set, write_case

# The public surfaces as implicit functions (negative inside) and the half-width of a box
# around them.
SURFACES = {
    "ovoid": (lambda x, y, z: x * x + (y / 0.75) ** 2 + (z / 0.5) ** 2 - 1, 1.1),
    "superquadric": (lambda x, y, z: x**4 + y**4 + z**4 - 1, 1.1),
    "ring": (lambda x, y, z: (np.sqrt(x * x + y * y) - 1) ** 2 + z * z - 0.09, 1.4),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("--cases", default=str(Path(__file__).resolve().parents[3] / "shared/quality/cases"))
    ap.add_argument("--cells", type=int, default=30)
    ap.add_argument("--only", nargs="*")
    args = ap.parse_args()
    out, index_path, index = open_case_set(args.outdir)
    public = json.loads((Path(args.cases) / "index.json").read_text())
    for name, (function, half) in SURFACES.items():
        if args.only and name not in args.only:
            continue
        axis = np.linspace(-half, half, 2 * round(args.cells * half) + 1)
        h = axis[1] - axis[0]
        grid = np.meshgrid(axis, axis, axis, indexing="ij")
        vertices, faces, _, _ = marching_cubes(function(*grid), 0.0, spacing=(h, h, h))
        vertices -= half
        write_case(out / name, "mcraw", vertices, faces, Path(args.cases) / name)
        entry = index.setdefault(name, dict(public[name], meshes={}))
        entry["meshes"]["mcraw"] = dict(vertices=len(vertices), faces=len(faces))
        print(f"{name}: {len(vertices)} vertices, {len(faces)} faces, grid spacing {h:.4f}")
    index_path.write_text(json.dumps(index, indent=1))


if __name__ == "__main__":
    main()
