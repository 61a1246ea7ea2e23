#!/usr/bin/env python3
"""Exact-answer cases with stray vertices (spikes), as scans have them.

usage: spikes.py OUTDIR --cases DIR [--cases DIR ...] [--mesh reg20k] [--fraction 0.005]
                 [--height 3] [--seed 3] [--only NAME ...]

For every surface of each case folder (../shared/quality/cases, or one written by
height_fields.py or closed_surfaces.py), its mesh MESH with a random FRACTION of the vertices
moved HEIGHT mean edge lengths along their area-weighted normals, outward or inward at random,
is written as OUTDIR/NAME/spiky20k.obj beside links to the surface's truth_lines.npz and .obj,
and listed in OUTDIR/index.json, so that the public scorer runs on it unchanged:

    python3 bench/quality/spikes.py /tmp/sp --cases ../shared/quality/cases
    python3 bench/quality/spikes.py /tmp/sp-noisy --cases ../shared/quality/cases --mesh noisy20k
    python3 ../shared/quality/score.py 'target/release/crestline extract {in} -o {out} -q' \\
        --cases /tmp/sp

The spikes are single vertices (or, by chance, a few side by side) far off the surface the
others sample: what `mesh/outliers.rs` puts back before anything is estimated
(`--keep-outliers` keeps them). Needs numpy.
"""
import json
import zlib
from pathlib import Path

import numpy as np

from noisy_cases import case_set_parser, open_case_set, write_case
from noisy_parts import read_obj


def main():
    ap = case_set_parser(__doc__)
    ap.add_argument("--fraction", type=float, default=0.005)
    ap.add_argument("--height", type=float, default=3.0, help="in mean edge lengths")
    ap.add_argument("--seed", type=int, default=3)
    args = ap.parse_args()
    out, index_path, index = open_case_set(args.outdir)
    for cases in args.cases:
        cases = Path(cases).resolve()
        for name, entry in json.loads((cases / "index.json").read_text()).items():
            if args.only and name not in args.only:
                continue
            path = cases / name / f"{args.mesh}.obj"
            if not path.exists():
                print(f"{name}: no {args.mesh} mesh, skipped")
                continue
            v, f = read_obj(path)
            rng = np.random.default_rng([args.seed, zlib.crc32(name.encode())])
            area = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
            normals = np.zeros_like(v)
            for k in range(3):
                np.add.at(normals, f[:, k], area)
            length = np.linalg.norm(normals, axis=1)
            edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
            edge = np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1).mean()
            pick = (rng.random(len(v)) < args.fraction) & (length > 0)
            signs = rng.choice([-1.0, 1.0], size=pick.sum())
            v = v.copy()
            v[pick] += normals[pick] / length[pick, None] * (args.height * edge * signs)[:, None]
            write_case(out / name, "spiky20k", v, f, cases / name)
            index[name] = dict(entry, meshes={"spiky20k": entry["meshes"][args.mesh]})
            print(f"{name}: {pick.sum()} spikes of {args.height} mean edges ({args.mesh})")
    index_path.write_text(json.dumps(index, indent=1))


if __name__ == "__main__":
    main()
