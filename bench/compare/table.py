#!/usr/bin/env python3
"""Markdown tables from the results run.sh leaves in its output folder.

For every mesh and tool, run.sh leaves `<mesh>.<tool>.<run>.json` (the tool's JSON report on
stdout) and `<mesh>.<tool>.<run>.time` (`/usr/bin/time -v`). Of the repeated runs of a tool on
a mesh the one with the smallest wall time is reported, with its own stage times and peak RSS.

Usage: table.py RESULTS_DIR MESH... > table.md
"""

import json
import re
import sys
from pathlib import Path

TOOLS = [
    ("cgal", "CGAL Ridges_3 (jet 3, 2-ring, crest)"),
    ("hpw", "crestline (default: HPW)"),
    ("ybs", "crestline --method ybs"),
]


def wall_seconds(text):
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", text)
    parts = [float(p) for p in m.group(1).split(":")]
    seconds = 0.0
    for p in parts:
        seconds = seconds * 60 + p
    return seconds


def peak_rss_bytes(text):
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
    return int(m.group(1)) * 1024


def load_run(results, mesh, tool, run):
    report = json.loads((results / f"{mesh}.{tool}.{run}.json").read_text())
    timing = (results / f"{mesh}.{tool}.{run}.time").read_text()
    status = re.search(r"Exit status: (\d+)", timing)
    if status is None or status.group(1) != "0":
        raise SystemExit(f"{mesh} {tool} run {run} failed; see its .time and .err files")
    wall = wall_seconds(timing)
    rss = peak_rss_bytes(timing)
    if tool == "cgal":
        s = report["seconds"]
        stages = {
            "load": s["load"],
            "curvature": s["monge"],
            "smoothing": 0.0,
            "lines": s["ridges"],
            "write": s["output"],
        }
        faces = report["faces"]
        lines = report["lines"]
        length = report["length"]
        diagonal = report["bbox_diagonal"]
    else:
        st = report["stage_seconds"]
        stages = {
            "load": report["load_seconds"],
            "curvature": st.get("curvature", 0.0),
            "smoothing": st.get("extremality smoothing", 0.0) + st.get("pre-smoothing", 0.0),
            "lines": st.get("tracing", 0.0) + st.get("filtering", 0.0) + st.get("fairing", 0.0),
            "write": report["write_seconds"],
        }
        faces = report["triangles"]
        lines = report["lines"]
        length = report["total_length"]
        diagonal = report["diagonal"]
    return {
        "wall": wall,
        "rss": rss,
        "stages": stages,
        "faces": faces,
        "lines": lines,
        "length": length,
        "diagonal": diagonal,
    }


def best_run(results, mesh, tool):
    runs = sorted(results.glob(f"{mesh}.{tool}.*.json"))
    if not runs:
        return None
    candidates = [load_run(results, mesh, tool, p.name.split(".")[-2]) for p in runs]
    return min(candidates, key=lambda r: r["wall"])


def fmt_s(x, absent="—"):
    if x == 0.0:
        return absent
    return f"{x:.3f}" if x < 10 else f"{x:.1f}"


def main():
    results = Path(sys.argv[1])
    meshes = sys.argv[2:]
    rows = []
    rows.append(
        "| mesh | faces | tool | load s | curvature s | smoothing s | lines s | write s | other s "
        "| wall s | peak RSS MB | bytes/face | lines | total length | length / diagonal "
        "| CGAL wall / wall |"
    )
    rows.append("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: "
                "| ---: | ---: | ---: | ---: |")
    for mesh in meshes:
        cgal = best_run(results, mesh, "cgal")
        for tool, label in TOOLS:
            r = best_run(results, mesh, tool)
            if r is None:
                continue
            st = r["stages"]
            other = max(r["wall"] - sum(st.values()), 0.0)
            ratio = f"{cgal['wall'] / r['wall']:.1f}x" if cgal else "—"
            rows.append(
                f"| {mesh} | {r['faces']:,} | {label} | {fmt_s(st['load'])} | "
                f"{fmt_s(st['curvature'])} | {fmt_s(st['smoothing'])} | {fmt_s(st['lines'])} | "
                f"{fmt_s(st['write'])} | {fmt_s(other, '0')} | {fmt_s(r['wall'])} | "
                f"{r['rss'] / 1e6:.0f} | {r['rss'] / r['faces']:.0f} | {r['lines']:,} | "
                f"{r['length']:.4g} | {r['length'] / r['diagonal']:.2f} | {ratio} |"
            )
    rows.append("")
    rows.append(
        "Stages: *load* reads the OFF file and builds the mesh (CGAL: polygon soup, unreferenced "
        "vertices dropped, Surface_mesh); *curvature* is CGAL's per-vertex normal, 2-ring and "
        "degree-3 jet + Monge fit, crestline's curvature and extremality estimation; *smoothing* "
        "is HPW's sign-aware extremality smoothing (crestline's YBS applies it too by default; CGAL "
        "has none); *lines* is CGAL's "
        "compute_crest_ridges, crestline's tracing, filtering and fairing; *write* writes the OBJ "
        "polylines; *other* is the wall time (/usr/bin/time, 10 ms resolution) not in a stage: "
        "process start and exit, freeing memory, option set-up. Peak RSS from /usr/bin/time -v; "
        "bytes/face is peak RSS over faces. CGAL's lines are all crest lines it finds (Ridges_3 "
        "has no strength filter); crestline's are those kept by its default filters."
    )
    print("\n".join(rows))


if __name__ == "__main__":
    main()
