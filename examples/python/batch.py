"""Extract the feature lines of every mesh in a folder, one process per core.

    python examples/python/batch.py ../shared/data/meshes -o lines/ --method hpw

Each worker reads a mesh, extracts its lines and writes them next to the others as
`<name>-lines.obj`; the main process prints one summary row per mesh. crestline already
uses every core inside one extraction (rayon), so for a few large meshes a pool brings
little; for many small ones it keeps the cores busy through the sequential parts (reading,
tracing). Give the pool fewer workers than cores if memory is short: igea needs about 50 MB.

Larger than one machine: `process_mesh` is a plain function of a path, so it runs as it is
under Dask (`dask.bag.from_sequence(paths).map(process_mesh, out, method).compute()`, or
`client.map(process_mesh, paths, ...)` with `dask.distributed`) or Ray
(`ray.remote(process_mesh).remote(path, out, method)` per mesh, then `ray.get`). Install
crestline on every worker; write the lines to shared storage, or return the arrays
(`lines.points`, `lines.offsets`, `lines.kinds`) instead of a path.
"""

import argparse
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import crestline

MESH_EXTENSIONS = {".obj", ".ply", ".off", ".stl"}


def process_mesh(path, out_dir, method="hpw"):
    """Extracts the lines of one mesh file and writes them; returns a summary row."""
    start = time.perf_counter()
    vertices, faces = crestline.read_mesh(path)
    lines = crestline.extract(vertices, faces, method=method)
    output = Path(out_dir) / f"{Path(path).stem}-lines.obj"
    lines.write(output)
    return {
        "mesh": Path(path).name,
        "faces": len(faces),
        "lines": len(lines),
        "ridges": lines.kinds.count("ridge"),
        "valleys": lines.kinds.count("valley"),
        "creases": sum(kind.startswith("crease") for kind in lines.kinds),
        "seconds": time.perf_counter() - start,
        "output": str(output),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("-o", "--output", default="lines")
    parser.add_argument("--method", default="hpw", choices=["hpw", "ybs", "saliency"])
    parser.add_argument("--workers", type=int, default=os.cpu_count())
    args = parser.parse_args()

    paths = sorted(p for p in Path(args.folder).iterdir() if p.suffix.lower() in MESH_EXTENSIONS)
    Path(args.output).mkdir(parents=True, exist_ok=True)
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        futures = {p: pool.submit(process_mesh, p, args.output, args.method) for p in paths}
        for path, future in futures.items():
            try:
                row = future.result()
            except (ValueError, OSError) as error:  # a broken file does not stop the batch
                print(f"{path.name:24} failed: {error}")
                continue
            print(
                f"{row['mesh']:24} {row['faces']:>9} faces {row['lines']:>5} lines "
                f"({row['ridges']} ridges, {row['valleys']} valleys, {row['creases']} creases) "
                f"{row['seconds']:6.2f} s"
            )


if __name__ == "__main__":
    main()
