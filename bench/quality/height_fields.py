#!/usr/bin/env python3
"""Exact-answer cases that are not in ../shared: height fields with their exact crest lines.

usage: height_fields.py OUTDIR [--only NAME ...] [--grid 1201] [--seed 7]
       height_fields.py OUTDIR --surface NAME 'EXPRESSION IN x AND y' [--grid 1201] [--seed 7]

Writes, per surface z = f(x, y) over [-1, 1]^2, OUTDIR/NAME/{reg5k,reg20k,irr20k,noisy20k}.obj,
truth_lines.npz and truth_lines.obj in the layout of ../shared/quality/cases, and adds NAME to
OUTDIR/index.json, so that the public scorer runs on them unchanged:

    python3 ../shared/quality/score.py 'target/release/crestline extract {in} -o {out} -q' --cases OUTDIR

The public cases are five surfaces; a method tuned to them can pass them and fail on the next
surface. These are further surfaces of the kind of the public `ridge` case (an open height field)
whose crest lines are exact too, so that a change can be checked on shapes nobody tuned it to.

**Exact quantities.** The derivatives of f up to third order are taken symbolically (sympy). With
the normal pointing up (+z, the outward side of a height field), the first fundamental form
I = [[1 + fx^2, fx fy], [fx fy, 1 + fy^2]] and B = -II = -Hess(f) / W (W = sqrt(1 + fx^2 + fy^2)),
the principal curvatures k_max >= k_min are the eigenvalues of I^-1 B (a cap z = -x^2 has k > 0:
it bends away from its normal), t_max and t_min its eigenvectors of unit length in I, and the
extremalities the derivatives of the eigenvalues along their own directions,
e = (dB(t, t) - k dI(t, t)) / I(t, t) (the derivative of a Rayleigh quotient at an eigenvector).

**Crest lines.** On a grid of GRID x GRID cells the zero set of e is contoured cell by cell: the
corners' directions are turned to agree with the first corner's (e changes sign with t), a cell
whose directions disagree by more than 45 degrees is skipped (umbilics), and a cell with exactly
two sign changes on its edges gives one segment. It is a ridge when e_max decreases along t_max
across the cell and k_max > |k_min|, a valley when e_min increases along t_min and
k_min < -|k_max| (the sign conventions of README.md). GRID is odd by default so that no grid
node lies on an axis of symmetry, where e can be exactly zero and its crossing would be missed.
Each segment's strength is |k| of its family; `strong_min` is 1.5 times the area-weighted median
of max(|k_max|, |k_min|) over the grid (../shared/quality/README.md: "dominant |k| >= 1.5 x its
median"; for the public ridge this gives 1.514 where its file has 1.472, which leaves 21% of its
strong valley length out of recall).

**Check.** With the public ridge's function, `0.3*exp(-(x - 0.3*sin(2*y))**2/0.15)`, the lines
made here are the shared ones: they lie within a quarter of the scorer's tolerance of ../shared's truth_lines over 99.7% of
their length (ridges; valleys 100%) and within the tolerance over 100%, and ../shared's lie within
a quarter tolerance of these over 100%.

**Meshes** (the public ones' vertex and face counts; the diagonal is that of [-1, 1]^2, which the
public meshes overreach a little). reg5k and reg20k: grids of 51^2 and 101^2 vertices, diagonals
alternating; irr20k: 10,605 random points (the border sampled evenly) triangulated by Delaunay in
the plane, slivers and all; noisy20k: reg20k with every vertex moved along its exact normal by
N(0, 0.1 x mean edge length).
Needs numpy, scipy and sympy.
"""
import argparse
import json
from pathlib import Path

import numpy as np
import sympy as sp
from scipy.spatial import Delaunay

# Surfaces made for the session of 2026-11-28 (BENCHMARKS.md, "Height fields not in ../shared").
SURFACES = {
    # two Gaussian ridges crossing at an angle, of different widths
    "cross": "0.25*exp(-(x+0.2*y)**2/0.08) + 0.2*exp(-(y-0.3*x-0.2)**2/0.05)",
    # winding parallel ridges and valleys
    "dunes": "0.12*sin(4*x + 0.8*sin(3*y))",
    # an elliptic ring wall: closed ridge and valleys, a symmetric valley across the inner rim
    "crater": "0.25*exp(-((x**2 + 1.69*y**2 - 0.3)/0.25)**2)",
    # three elliptic bumps and a dent of different sizes, overlapping
    "blobs": "0.3*exp(-((x-0.3)**2 + 2*(y-0.2)**2)/0.08) - 0.2*exp(-(2*(x+0.4)**2 + (y+0.3)**2)/0.12)"
    " + 0.15*exp(-((x+0.3)**2 + (y-0.55)**2)/0.04)",
    # a rounded step winding across the square: a ridge along its top, a valley along its foot
    "step": "0.15*tanh(5*(x - 0.25*sin(2.5*y)))",
    # MATLAB's peaks, scaled into the square
    "peaks": "0.04*(3*(1-1.5*x)**2*exp(-(1.5*x)**2-(1.5*y+1)**2)"
    " - 10*(0.3*x-(1.5*x)**3-(1.5*y)**5)*exp(-(1.5*x)**2-(1.5*y)**2)"
    " - exp(-(1.5*x+1)**2-(1.5*y)**2)/3)",
}

x, y = sp.symbols("x y")


def surface_functions(px, py, pz):
    """Per (x, y): the point P, its unit normal n = P_x × P_y / |P_x × P_y|, E, F, G, L, M, N
    (B = -II, II against n) and the x and y derivatives of E, F, G, L, M, N, for the surface
    P(x, y) = (px, py, pz) given as sympy expressions in the parameters x and y."""
    point = sp.Matrix([px, py, pz])
    pu, pv = point.diff(x), point.diff(y)
    cross = pu.cross(pv)
    w = sp.sqrt(cross.dot(cross))
    normal = cross / w
    first = [pu.dot(pu), pu.dot(pv), pv.dot(pv)]
    second = [-point.diff(x, 2).dot(normal), -point.diff(x, y).dot(normal), -point.diff(y, 2).dot(normal)]
    terms = [*point, *normal, *first, *second]
    for q in first + second:
        terms += [sp.diff(q, x), sp.diff(q, y)]
    return sp.lambdify((x, y), terms, "numpy", cse=True)


def field_functions(expression):
    """surface_functions of the height field z = f(x, y)."""
    return surface_functions(x, y, sp.sympify(expression))


def evaluate(functions, u, v):
    return [np.broadcast_to(np.asarray(a, dtype=float), u.shape) for a in functions(u, v)]


def quantities(functions, u, v):
    """Exact k_max >= k_min, unit directions (parameter coordinates), extremalities, point, normal
    and area element."""
    values = evaluate(functions, u, v)
    E, F, G, L, M, N = values[6:12]
    dE, dF, dG, dL, dM, dN = [(values[12 + 2 * i], values[13 + 2 * i]) for i in range(6)]
    # det(B - k I) = 0
    a = E * G - F * F
    b = -(E * N + G * L - 2 * F * M)
    c = L * N - M * M
    root = np.sqrt(np.maximum(b * b - 4 * a * c, 0.0))
    out = {}
    for name, k in (("max", (-b + root) / (2 * a)), ("min", (-b - root) / (2 * a))):
        # (B - k I) t = 0: either row gives t; take the better conditioned one.
        first = np.stack([-(M - k * F), L - k * E], -1)
        second = np.stack([-(N - k * G), M - k * F], -1)
        t = np.where(((second**2).sum(-1) > (first**2).sum(-1))[..., None], second, first)
        tu, tv = t[..., 0], t[..., 1]
        norm = np.sqrt(E * tu * tu + 2 * F * tu * tv + G * tv * tv)
        tu, tv = tu / norm, tv / norm

        def along(pair):
            return pair[0] * tu + pair[1] * tv

        d_b = along(dL) * tu * tu + 2 * along(dM) * tu * tv + along(dN) * tv * tv
        d_i = along(dE) * tu * tu + 2 * along(dF) * tu * tv + along(dG) * tv * tv
        out["k_" + name] = k
        out["t_" + name] = np.stack([tu, tv], -1)
        out["e_" + name] = d_b - k * d_i
    out["p"] = np.stack(values[0:3], -1)
    out["n"] = np.stack(values[3:6], -1)
    out["area"] = np.sqrt(a)
    return out


def crest_lines(functions, grid):
    """Segments (n, 2, 3) and strengths of each family, and strong_min (module docs)."""
    out, dominant, area = chart_crest_lines(functions, grid)
    order = np.argsort(dominant)
    cumulative = np.cumsum(area[order])
    median = dominant[order][np.searchsorted(cumulative, cumulative[-1] / 2)]
    return out, 1.5 * median


def chart_crest_lines(functions, grid):
    """Segments (n, 2, 3) and strengths of each family over the parameter square [-1, 1]^2, and
    the dominant |k| and area element at the grid's nodes."""
    s = np.linspace(-1.0, 1.0, grid + 1)
    h = s[1] - s[0]
    u, v = np.meshgrid(s, s, indexing="ij")
    q = quantities(functions, u, v)
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]

    def at(field, corner):
        return field[corner[0] : grid + corner[0], corner[1] : grid + corner[1]]

    out = {}
    for kind, family, other in (("ridge", "max", "min"), ("valley", "min", "max")):
        t = [at(q["t_" + family], c) for c in corners]
        k = sum(at(q["k_" + family], c) for c in corners) / 4
        k_other = sum(at(q["k_" + other], c) for c in corners) / 4
        cosines = [(t[m] * t[0]).sum(-1) / np.linalg.norm(t[m], axis=-1) / np.linalg.norm(t[0], axis=-1)
                   for m in (1, 2, 3)]
        aligned = np.minimum.reduce([np.abs(c) for c in cosines]) > np.cos(np.pi / 4)
        e = [at(q["e_" + family], corners[0])] + [
            at(q["e_" + family], corners[m]) * np.sign(cosines[m - 1] + 1e-300) for m in (1, 2, 3)
        ]
        crossings = []
        for m in range(4):
            a, b = e[m], e[(m + 1) % 4]
            crossings.append((a * b < 0, a / (a - b + 1e-300), np.array(corners[m]), np.array(corners[(m + 1) % 4])))
        count = sum(c[0].astype(int) for c in crossings)
        # e's derivative along the cell's direction
        de_u = 0.5 * ((e[1] - e[0]) + (e[2] - e[3])) / h
        de_v = 0.5 * ((e[3] - e[0]) + (e[2] - e[1])) / h
        slope = de_u * t[0][..., 0] + de_v * t[0][..., 1]
        if kind == "ridge":
            crest = (slope < 0) & (k > np.abs(k_other))
        else:
            crest = (slope > 0) & (k < -np.abs(k_other))
        segments, strengths = [], []
        for i, j in np.argwhere((count == 2) & aligned & crest):
            ends = []
            for crossed, w, a, b in crossings:
                if crossed[i, j]:
                    p = (1 - w[i, j]) * a + w[i, j] * b
                    ends.append((s[i] + p[0] * h, s[j] + p[1] * h))
            segments.append(ends)
            strengths.append(abs(k[i, j]))
        plane = np.array(segments, dtype=float).reshape(-1, 2, 2)
        out[kind] = np.stack(evaluate(functions, plane[..., 0], plane[..., 1])[0:3], -1)
        out[kind + "_strength"] = np.array(strengths)
    dominant = np.maximum(np.abs(q["k_max"]), np.abs(q["k_min"])).ravel()
    return out, dominant, q["area"].ravel()


def grid_mesh(functions, n):
    s = np.linspace(-1.0, 1.0, n)
    u, v = np.meshgrid(s, s, indexing="ij")
    vertices = np.stack([u, v, evaluate(functions, u, v)[2]], -1).reshape(-1, 3)
    faces = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            faces += [(a, b, c), (a, c, d)] if (i + j) % 2 else [(a, b, d), (b, c, d)]
    return vertices, np.array(faces)


def irregular_mesh(functions, count, rng):
    m = int(np.sqrt(count)) + 1
    b = np.linspace(-1.0, 1.0, m)
    border = np.concatenate([
        np.c_[b, -np.ones(m)], np.c_[b, np.ones(m)],
        np.c_[-np.ones(m - 2), b[1:-1]], np.c_[np.ones(m - 2), b[1:-1]],
    ])
    points = np.concatenate([border, rng.uniform(-1.0, 1.0, size=(count - len(border), 2))])
    faces = Delaunay(points).simplices
    vertices = np.c_[points, evaluate(functions, points[:, 0], points[:, 1])[2]]
    p = vertices[faces]
    down = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])[:, 2] < 0
    faces[down] = faces[down][:, ::-1]
    return vertices, faces


def write_obj(path, vertices, faces):
    with open(path, "w") as out:
        out.write("".join(f"v {a:.10g} {b:.10g} {c:.10g}\n" for a, b, c in vertices))
        out.write("".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces))


def make_case(outdir, name, expression, grid, seed):
    rng = np.random.default_rng(seed)
    functions = field_functions(expression)
    folder = outdir / name
    folder.mkdir(parents=True, exist_ok=True)
    truth, strong_min = crest_lines(functions, grid)
    meshes = {}
    for mesh, n in (("reg5k", 51), ("reg20k", 101)):
        vertices, faces = grid_mesh(functions, n)
        write_obj(folder / f"{mesh}.obj", vertices, faces)
        meshes[mesh] = dict(vertices=len(vertices), faces=len(faces))
    vertices, faces = grid_mesh(functions, 101)
    normals = quantities(functions, vertices[:, 0], vertices[:, 1])["n"]
    edges = np.unique(np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0)
    edge = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1).mean()
    noisy = vertices + normals * rng.normal(0.0, 0.1 * edge, size=(len(vertices), 1))
    write_obj(folder / "noisy20k.obj", noisy, faces)
    meshes["noisy20k"] = meshes["reg20k"]
    vertices, faces = irregular_mesh(functions, 10605, rng)
    write_obj(folder / "irr20k.obj", vertices, faces)
    meshes["irr20k"] = dict(vertices=len(vertices), faces=len(faces))
    write_truth(outdir, name, "height", truth, strong_min, vertices, meshes)

def write_truth(outdir, name, kind, truth, strong_min, vertices, meshes):
    """truth_lines.npz and truth_lines.obj of case NAME (its diagonal over the lines and `vertices`),
    its entry in OUTDIR/index.json, and its lines' lengths on stdout."""
    folder = outdir / name
    points = np.concatenate([truth["ridge"].reshape(-1, 3), truth["valley"].reshape(-1, 3), vertices])
    diag = float(np.linalg.norm(points.max(0) - points.min(0)))
    np.savez(folder / "truth_lines.npz", diag=diag, strong_min=strong_min, **truth)
    with open(folder / "truth_lines.obj", "w") as out:
        index = 1
        for family in ("ridge", "valley"):
            out.write(f"g {family}\n")
            for a, b in truth[family]:
                out.write(f"v {a[0]} {a[1]} {a[2]}\nv {b[0]} {b[1]} {b[2]}\nl {index} {index + 1}\n")
                index += 2
    index_file = outdir / "index.json"
    index = json.loads(index_file.read_text()) if index_file.exists() else {}
    index[name] = dict(diag=diag, kind=kind, meshes=meshes)
    index_file.write_text(json.dumps(index, indent=1))
    for family in ("ridge", "valley"):
        length = np.linalg.norm(truth[family][:, 0] - truth[family][:, 1], axis=1)
        strong = truth[family + "_strength"] >= strong_min
        print(f"{name} {family}s: {length.sum() / diag:.3f} diagonals, strong {length[strong].sum() / diag:.3f}")


def command_line(doc, surfaces, make_case, grid, expression):
    """The scripts' command line: OUTDIR [--only NAME ...] | --surface NAME EXPRESSION, --grid, --seed."""
    parser = argparse.ArgumentParser(description=doc.split("\n")[0])
    parser.add_argument("outdir", type=Path)
    parser.add_argument("--only", nargs="+", choices=sorted(surfaces))
    parser.add_argument("--surface", nargs=2, metavar=("NAME", expression))
    parser.add_argument("--grid", type=int, default=grid, help="cells per side of a tracing grid")
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    if args.surface:
        chosen = {args.surface[0]: args.surface[1]}
    else:
        chosen = {k: surfaces[k] for k in (args.only or surfaces)}
    with np.errstate(invalid="ignore", divide="ignore"):
        for name, expression in chosen.items():
            make_case(args.outdir, name, expression, args.grid, args.seed)


def main():
    command_line(__doc__, SURFACES, make_case, 1201, "EXPRESSION")

if __name__ == "__main__":
    main()
