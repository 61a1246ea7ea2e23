"""Times `crestline.extract` from Python against `crestline extract` on the same mesh.

    python crates/crestline-py/bench/extract_vs_cli.py ../shared/data/meshes/igea.ply \
        --cli target/release/crestline --repeats 5

Like with like: each run is a fresh process doing the same work, read the mesh, extract with
the default options, write the lines as OBJ. For the CLI, its own `--stats json` times (load,
stages, write) and the process's wall time; for Python, the same work timed inside the
process (`read_mesh` + `extract` + `Lines.write`, interpreter start and `import crestline`
excluded) and the process's wall time (both included). The runs alternate, so that a change
in the machine's load touches both; the median of each column is printed.
"""

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PYTHON_RUN = """
import sys, time
import crestline
start = time.perf_counter()
vertices, faces = crestline.read_mesh(sys.argv[1])
lines = crestline.extract(vertices, faces)
lines.write(sys.argv[2])
print(time.perf_counter() - start)
"""


def run_cli(cli, mesh, out):
    start = time.perf_counter()
    result = subprocess.run(
        [cli, "extract", mesh, "-o", out, "-q", "--stats", "json"],
        check=True,
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - start
    stats = json.loads(result.stdout)
    work = stats["load_seconds"] + sum(
        t for stage, t in stats["stage_seconds"].items() if stage not in ("load", "write")
    ) + stats["write_seconds"]
    return work, wall


def run_python(mesh, out):
    start = time.perf_counter()
    result = subprocess.run(
        [sys.executable, "-c", PYTHON_RUN, mesh, out], check=True, capture_output=True, text=True
    )
    wall = time.perf_counter() - start
    return float(result.stdout), wall


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("--cli", default="target/release/crestline")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()

    times = {"cli": [], "python": []}
    with tempfile.TemporaryDirectory() as tmp:
        cli_out, py_out = str(Path(tmp) / "cli.obj"), str(Path(tmp) / "py.obj")
        for _ in range(args.repeats):
            times["cli"].append(run_cli(args.cli, args.mesh, cli_out))
            times["python"].append(run_python(args.mesh, py_out))
        same = Path(cli_out).read_bytes() == Path(py_out).read_bytes()

    print(f"{Path(args.mesh).name}, {args.repeats} runs each, medians (all runs in brackets)")
    for name in ("cli", "python"):
        work = [w for w, _ in times[name]]
        wall = [w for _, w in times[name]]
        print(
            f"{name:7} work {statistics.median(work):7.3f} s  wall {statistics.median(wall):7.3f} s"
            f"   work [{', '.join(f'{w:.3f}' for w in work)}]"
        )
    cli_work = statistics.median(w for w, _ in times["cli"])
    py_work = statistics.median(w for w, _ in times["python"])
    cli_wall = statistics.median(w for _, w in times["cli"])
    py_wall = statistics.median(w for _, w in times["python"])
    print(f"python / cli: work {py_work / cli_work:.3f}, wall {py_wall / cli_wall:.3f}")
    print(f"same lines file: {same}")


if __name__ == "__main__":
    main()
