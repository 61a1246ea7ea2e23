#!/usr/bin/env python3
"""Exact-answer cases that are not in ../shared: closed star-shaped surfaces with their exact crest lines.

usage: closed_surfaces.py OUTDIR [--only NAME ...] [--grid 501] [--seed 7]
       closed_surfaces.py OUTDIR --surface NAME 'RADIUS IN dx, dy AND dz' [--grid 501] [--seed 7]

Writes, per surface |p| = r(p / |p|), OUTDIR/NAME/{reg5k,reg20k,irr20k,mc,noisy20k}.obj,
truth_lines.npz and truth_lines.obj in the layout of ../shared/quality/cases, and adds NAME to
OUTDIR/index.json, so that the public scorer runs on them unchanged:

    python3 ../shared/quality/score.py 'target/release/crestline extract {in} -o {out} -q' --cases OUTDIR

The public closed cases are an ellipsoid, a superquadric and a bumpy sphere; these are further
surfaces of the same kinds (other axes, exponents and bumps), meshed the same five ways, so that a
change can be checked on shapes nobody tuned it to. `height_fields.py` does the same for open
height fields.

**Exact quantities and crest lines** as in `height_fields.py` (its `surface_functions` and
`chart_crest_lines`), on six charts: each face of the cube [-1, 1]^3 maps to the surface by
c -> r(c / |c|) c / |c|, its parameters (u, v) ordered so that P_u x P_v points outward. Each
chart is contoured on GRID x GRID cells. `strong_min` is 1.5 times the median of the dominant |k|
over the vertices of the reference mesh, an icosahedron subdivided seven times (327,680 faces)
projected radially, as in ../shared (this gives its strong_min of the ovoid and the superquadric,
2.042 and 1.723 against 2.044 and 1.723; an area-weighted median would give 2.54 and 1.98). GRID is odd so that no grid node lies on
the charts' middle lines, the surfaces' planes of symmetry, where e can be exactly zero.

**Meshes** (the public ones' sizes). reg5k and reg20k: an icosahedron subdivided four and five
times, projected radially onto the surface; irr20k: 10,242 random directions (uniform on the
sphere), their convex hull, projected; mc: marching cubes (scikit-image) of |p| - r(p / |p|) on a
grid of spacing 0.053, vertices projected radially; noisy20k: reg20k with every vertex moved along
its exact normal by N(0, 0.1 x mean edge length).
Needs numpy, scipy, sympy and scikit-image.
"""
import numpy as np
import sympy as sp
from scipy.spatial import ConvexHull
from skimage.measure import marching_cubes

from height_fields import (chart_crest_lines, command_line, quantities, surface_functions, write_obj,
                           write_truth, x, y)

dx, dy, dz = sp.symbols("dx dy dz")

# Radius r(dx, dy, dz) of the surface along the unit direction d.
SURFACES = {
    # an ellipsoid flatter than the public ovoid (axes 1, 0.75, 0.5)
    "ovoid2": "1/sqrt(dx**2 + dy**2/0.36 + dz**2/0.16)",
    # x^4 + (y/0.8)^4 + (z/0.6)^4 = 1: the public superquadric's rounded edges, unequal
    "superquadric2": "(dx**4 + (dy/0.8)**4 + (dz/0.6)**4)**(-1/4)",
    # x^6 + y^6 + z^6 = 1: sharper edges than the public x^4 + y^4 + z^4 = 1
    "superquadric6": "(dx**6 + dy**6 + dz**6)**(-1/6)",
    # a sphere with six elliptic Gaussian bumps and dents of other sizes than the public bumpy's
    # (elliptic, each 1.7 to 2.6 times wider one way than the other in its tangent plane: on a
    # bump of revolution one family's extremality is zero all over it, and its crest lines are
    # not defined)
    "bumpy2": "1 + 0.18*exp(-((dx-0.8)**2/0.05 + (dy-0.6)**2/0.12 + dz**2/0.04))"
    " - 0.12*exp(-((dx+0.6)**2/0.2 + (dy-0.64)**2/0.1 + (dz-0.48)**2/0.06))"
    " + 0.1*exp(-(dx**2/0.1 + (dy+0.6)**2/0.03 + (dz-0.8)**2/0.08))"
    " + 0.15*exp(-((dx+0.48)**2/0.1 + (dy+0.36)**2/0.2 + (dz+0.8)**2/0.15))"
    " - 0.1*exp(-((dx-0.36)**2/0.04 + (dy+0.48)**2/0.08 + (dz+0.8)**2/0.06))"
    " + 0.12*exp(-((dx-0.6)**2/0.06 + dy**2/0.03 + (dz+0.8)**2/0.04))",
}


def chart(radius, axis, sign):
    """surface_functions of the cube face `sign` x_axis = 1, parameters ordered outward."""
    b, c = (axis + 1) % 3, (axis + 2) % 3
    cube = [None] * 3
    cube[axis] = sign
    cube[b], cube[c] = (x, y) if sign > 0 else (y, x)
    norm = sp.sqrt(sum(q**2 for q in cube))
    d = [q / norm for q in cube]
    r = radius.subs({dx: d[0], dy: d[1], dz: d[2]}, simultaneous=True)
    return surface_functions(*(r * q for q in d))


def icosphere(levels):
    t = (1 + 5**0.5) / 2
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    vertices = [np.array(v, float) / np.linalg.norm(v) for v in vertices]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = vertices[a] + vertices[b]
                vertices.append(m / np.linalg.norm(m))
                middle[key] = len(vertices) - 1
            return middle[key]

        faces = [f for a, b, c in faces for f in
                 ((a, mid(a, b), mid(c, a)), (b, mid(b, c), mid(a, b)), (c, mid(c, a), mid(b, c)),
                  (mid(a, b), mid(b, c), mid(c, a)))]
    return np.array(vertices), np.array(faces)


def outward(vertices, faces):
    p = vertices[faces]
    inward = (np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) * p.mean(1)).sum(1) < 0
    faces = faces.copy()
    faces[inward] = faces[inward][:, ::-1]
    return faces


def make_case(outdir, name, expression, grid, seed):
    rng = np.random.default_rng(seed)
    radius = sp.sympify(expression)
    r_of = sp.lambdify((dx, dy, dz), radius, "numpy")
    px, py, pz = sp.symbols("px py pz")
    length = sp.sqrt(px**2 + py**2 + pz**2)
    implicit = length - radius.subs({dx: px / length, dy: py / length, dz: pz / length},
                                    simultaneous=True)
    gradient = sp.lambdify((px, py, pz), [sp.diff(implicit, q) for q in (px, py, pz)], "numpy")

    def project(directions):
        d = directions / np.linalg.norm(directions, axis=1)[:, None]
        return d * np.asarray(r_of(*d.T))[:, None]

    folder = outdir / name
    folder.mkdir(parents=True, exist_ok=True)
    truth = {"ridge": [], "ridge_strength": [], "valley": [], "valley_strength": []}
    reference, _ = icosphere(7)
    dominant = []
    for axis in range(3):
        for sign in (1, -1):
            functions = chart(radius, axis, sign)
            lines, _, _ = chart_crest_lines(functions, grid)
            for key in truth:
                truth[key].append(lines[key])
            # The reference mesh's vertices on this chart, at their parameters.
            on = (np.abs(reference).argmax(1) == axis) & (np.sign(reference[:, axis]) == sign)
            cube = reference[on] / np.abs(reference[on, axis])[:, None]
            b, c = (axis + 1) % 3, (axis + 2) % 3
            u, v = (cube[:, b], cube[:, c]) if sign > 0 else (cube[:, c], cube[:, b])
            q = quantities(functions, u, v)
            dominant.append(np.maximum(np.abs(q["k_max"]), np.abs(q["k_min"])))
    truth = {key: np.concatenate(parts) for key, parts in truth.items()}
    strong_min = 1.5 * np.median(np.concatenate(dominant))

    meshes = {}
    for mesh, levels in (("reg5k", 4), ("reg20k", 5)):
        directions, faces = icosphere(levels)
        vertices = project(directions)
        write_obj(folder / f"{mesh}.obj", vertices, faces)
        meshes[mesh] = dict(vertices=len(vertices), faces=len(faces))
    normals = np.stack(np.broadcast_arrays(*gradient(*vertices.T)), -1)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    edges = np.unique(np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0)
    edge = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1).mean()
    noisy = vertices + normals * rng.normal(0.0, 0.1 * edge, size=(len(vertices), 1))
    write_obj(folder / "noisy20k.obj", noisy, faces)
    meshes["noisy20k"] = meshes["reg20k"]
    directions = rng.normal(size=(10242, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    faces = outward(directions, ConvexHull(directions).simplices)
    vertices = project(directions)
    write_obj(folder / "irr20k.obj", vertices, faces)
    meshes["irr20k"] = dict(vertices=len(vertices), faces=len(faces))
    spacing = 0.053
    top = 1.1 * np.abs(vertices).max()
    axis_values = np.arange(-top, top + spacing, spacing)
    gx, gy, gz = np.meshgrid(axis_values, axis_values, axis_values, indexing="ij")
    field = np.sqrt(gx**2 + gy**2 + gz**2)
    field = field - r_of(gx / field, gy / field, gz / field)
    cube_vertices, faces, _, _ = marching_cubes(field, 0.0, spacing=(spacing,) * 3)
    vertices = project(cube_vertices - top)
    write_obj(folder / "mc.obj", vertices, outward(vertices, faces))
    meshes["mc"] = dict(vertices=len(vertices), faces=len(faces))

    write_truth(outdir, name, "star", truth, strong_min, vertices, meshes)

def main():
    command_line(__doc__, SURFACES, make_case, 501, "RADIUS")

if __name__ == "__main__":
    main()
