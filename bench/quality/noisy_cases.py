#!/usr/bin/env python3
"""Noisy copies of exact-answer cases, with other noise draws and levels than ../shared's.

usage: noisy_cases.py OUTDIR --cases DIR [--cases DIR ...] [--mesh reg20k] [--level 0.1]
                      [--seeds 1,2,3] [--only NAME ...]

For every surface of each case folder (../shared/quality/cases, or one written by
height_fields.py) and every seed, the mesh MESH moved along its area-weighted vertex normals
by normal numbers of standard deviation LEVEL times its mean edge length (all edges) is written
as OUTDIR/NAME-sSEED/noisy20k.obj, beside links to the surface's truth_lines.npz and .obj, and
listed in OUTDIR/index.json, so that the public scorer runs on them unchanged:

    python3 bench/quality/noisy_cases.py /tmp/nz --cases ../shared/quality/cases --seeds 1,2,3
    python3 ../shared/quality/score.py 'target/release/crestline extract {in} -o {out} -q' \\
        --cases /tmp/nz

The public noisy20k meshes are one draw at one level; a change to how noise is handled can
pass them by luck. These are further draws (the seed of each mesh is derived from SEED and the
surface's name, so one surface's draws do not depend on which others are made), also at other
levels and on the irregular meshes (`--mesh irr20k`). The clean mesh's normals stand in for the
exact ones, which differ from them by the mesh's discretisation error only. Surfaces without
lines (the torus) are scored by their spurious length, as in the public set.
Needs numpy.
"""
import argparse
import json
import os
import zlib
from pathlib import Path

import numpy as np

from noisy_parts import along_normals, read_obj


def write_case(folder, mesh, vertices, faces, surface):
    """Writes `folder/mesh.obj` and links the truth files of the case folder `surface` beside
    it, so that the public scorer reads `folder` as a case."""
    folder.mkdir(exist_ok=True)
    with open(folder / f"{mesh}.obj", "w") as f:
        f.writelines(f"v {x:.9f} {y:.9f} {z:.9f}\n" for x, y, z in vertices)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
    for truth in ("truth_lines.npz", "truth_lines.obj"):
        source, link = surface / truth, folder / truth
        if source.exists() and not link.exists():
            os.symlink(source, link)


def case_set_parser(doc):
    """The arguments every script that makes a set of cases from case folders takes: OUTDIR,
    --cases (repeated), --mesh and --only."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("--cases", action="append", required=True)
    ap.add_argument("--mesh", default="reg20k")
    ap.add_argument("--only", nargs="*")
    return ap


def open_case_set(outdir):
    """The folder `outdir` (made if needed), its index.json's path and what it lists so far."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    index_path = out / "index.json"
    index = json.loads(index_path.read_text()) if index_path.exists() else {}
    return out, index_path, index


def main():
    ap = case_set_parser(__doc__)
    ap.add_argument("--level", type=float, default=0.1)
    ap.add_argument("--seeds", default="1,2,3")
    args = ap.parse_args()
    out, index_path, index = open_case_set(args.outdir)
    seeds = [int(s) for s in args.seeds.split(",")]
    for cases in args.cases:
        cases = Path(cases).resolve()
        for name, entry in json.loads((cases / "index.json").read_text()).items():
            if args.only and name not in args.only:
                continue
            vertices, faces = read_obj(cases / name / f"{args.mesh}.obj")
            for seed in seeds:
                rng = np.random.default_rng([seed, zlib.crc32(name.encode())])
                moved = along_normals(vertices, faces, args.level, rng)
                write_case(out / f"{name}-s{seed}", "noisy20k", moved, faces, cases / name)
                index[f"{name}-s{seed}"] = dict(entry, meshes={"noisy20k": entry["meshes"][args.mesh]})
            print(f"{name}: {len(seeds)} draws at {args.level} of the mean edge ({args.mesh})")
    index_path.write_text(json.dumps(index, indent=1))


if __name__ == "__main__":
    main()
