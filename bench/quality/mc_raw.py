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

With --project, writes OUTDIR/NAME/mcproj.obj as well: the same meshes with every vertex moved
onto the surface (Newton steps along the gradient), as the public `mc` meshes are, but on a grid
whose planes pass through the surfaces' planes of symmetry (crests through vertices).

With --model, also checks the interpolation's error model on each mesh: every vertex has two
coordinates on the grid and one, its free axis a, at a fraction t of a grid edge, and is off the
exact crossing along a by -(f_aa / 2 f_a) t (1 - t) h^2 (printed: the correlation of the two, and
the RMS error; BENCHMARKS.md, "Open: raw marching cubes").

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


def check_model(vertices, function, half, h):
    """Prints how many vertices have two coordinates on the grid, and how well the linear
    interpolation's error along the free axis matches the exact crossing's distance."""
    grid = (vertices + half) / h
    on = np.abs(grid - np.round(grid)) < 1e-6
    free = np.argmin(on, axis=1)
    along = np.eye(3)[free]
    f = lambda p: function(p[:, 0], p[:, 1], p[:, 2])
    exact, eps = vertices.copy(), 1e-6
    for _ in range(30):  # Newton along the free axis
        slope = (f(exact + eps * along) - f(exact - eps * along)) / (2 * eps)
        exact -= (f(exact) / slope)[:, None] * along
    error = ((vertices - exact) * along).sum(1)
    rows = np.arange(len(vertices))
    t = grid[rows, free] - np.floor(grid[rows, free])
    eps = 1e-4
    first = (f(exact + eps * along) - f(exact - eps * along)) / (2 * eps)
    second = (f(exact + eps * along) - 2 * f(exact) + f(exact - eps * along)) / eps**2
    model = -second / (2 * first) * t * (1 - t) * h * h
    print(f"  {np.count_nonzero(on.sum(1) == 2)} of {len(vertices)} vertices with two coordinates "
          f"on the grid; error RMS {np.sqrt(np.mean(error**2)) / h:.4f} h, correlation with the "
          f"model {np.corrcoef(error, model)[0, 1]:.4f}, left {np.sqrt(np.mean((error - model)**2)) / h:.4f} h")


def project(vertices, function):
    """The vertices moved onto the zero set of `function` by Newton steps along its gradient."""
    f = lambda p: function(p[:, 0], p[:, 1], p[:, 2])
    p, eps = vertices.astype(np.float64), 1e-6
    for _ in range(30):
        gradient = np.stack([(f(p + eps * e) - f(p - eps * e)) / (2 * eps) for e in np.eye(3)], 1)
        p -= (f(p) / np.maximum((gradient * gradient).sum(1), 1e-300))[:, None] * gradient
    return p


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("--cases", default=str(Path(__file__).resolve().parents[3] / "shared/quality/cases"))
    ap.add_argument("--cells", type=int, default=30)
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--model", action="store_true")
    ap.add_argument("--project", action="store_true")
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
        if args.project:
            on_surface = project(vertices, function)
            write_case(out / name, "mcproj", on_surface, faces, Path(args.cases) / name)
            entry["meshes"]["mcproj"] = dict(vertices=len(vertices), faces=len(faces))
        print(f"{name}: {len(vertices)} vertices, {len(faces)} faces, grid spacing {h:.4f}")
        if args.model:
            check_model(vertices, function, half, h)
    index_path.write_text(json.dumps(index, indent=1))


if __name__ == "__main__":
    main()
