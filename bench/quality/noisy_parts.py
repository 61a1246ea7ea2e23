#!/usr/bin/env python3
"""Noisy copies of the uniformly meshed CAD parts of ../shared/quality/cad, as a scan gives them.

Every vertex moves along its (area-weighted) normal by a normal number of standard deviation
`level` times the mean edge length; the exact sharp edges (`.fea`, mesh edges by vertex index)
stay valid and are copied beside each mesh, so that score_cad.py scores them:

    python3 bench/quality/noisy_parts.py /tmp/noisy-parts --levels 0.05,0.1 --seed 7
    python3 ../shared/quality/score_cad.py 'target/release/crestline extract {in} -o {out}' \
        --cases /tmp/noisy-parts

Needs numpy.
"""
import argparse
import glob
import os
import shutil

import numpy as np


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    return np.array(vertices), np.array(faces)


def along_normals(v, f, level, rng):
    """The vertices `v` moved along their area-weighted normals by normal numbers of standard
    deviation `level` times the mean edge length (all edges); vertices without faces stay."""
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    mean_edge = np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1).mean()
    area_normals = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    normals = np.zeros_like(v)
    for k in range(3):
        np.add.at(normals, f[:, k], area_normals)
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    return v + normals * rng.normal(0.0, level * mean_edge, len(v))[:, None]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="folder to write to")
    parser.add_argument("--levels", default="0.05,0.1", help="noise, fractions of the mean edge")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--parts", default=os.path.join(here, "../../../shared/quality/cad"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    levels = [float(x) for x in args.levels.split(",")]
    for path in sorted(glob.glob(os.path.join(args.parts, "*-uniform.obj"))):
        v, f = read_obj(path)
        name = os.path.basename(path)[:-4]
        for level in levels:
            rng = np.random.default_rng([args.seed, int(round(level * 1000))])
            moved = along_normals(v, f, level, rng)
            stem = os.path.join(args.out, f"{name}-n{int(round(level * 100)):02d}s{args.seed}")
            with open(stem + ".obj", "w") as out:
                out.writelines("v %.9g %.9g %.9g\n" % tuple(p) for p in moved)
                out.writelines("f %d %d %d\n" % tuple(t + 1) for t in f)
            shutil.copy(path[:-4] + ".fea", stem + ".fea")
            print(stem)


if __name__ == "__main__":
    main()
