#!/usr/bin/env bash
# Line and estimator quality on the exact-answer cases of ../shared/quality (issue 19).
#
# Builds the release binary, runs every method with default settings through score.py, both
# estimators' default and the papers' exact variants through score_fields.py (the noisy meshes
# are graded against the exact fields of the regular mesh they were made from), and prints
# Markdown tables. Needs python3 with numpy and scipy (pip install numpy scipy).
#
#   bench/quality/run.sh            # tables on stdout
#   bench/quality/run.sh > q.md     # keep them; BENCHMARKS.md quotes them with the commit
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SHARED=${SHARED:-$ROOT/../shared}
Q=$SHARED/quality
[ -d "$Q/cases" ] || { echo "no $Q/cases (put shared/ beside the repository)" >&2; exit 1; }
python3 -c "import numpy, scipy" 2>/dev/null || { echo "needs numpy and scipy: pip install numpy scipy" >&2; exit 1; }
(cd "$ROOT" && cargo build --release -q -p crestline-cli)
BIN=$ROOT/target/release/crestline
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

# The noisy meshes moved the vertices of reg20k along the exact normals: grade their fields
# against reg20k's exact values.
NOISY=$OUT/noisy-cases
for s in "$Q"/cases/*/; do
  s=$(basename "$s")
  if [ -f "$Q/cases/$s/noisy20k.obj" ] && [ -f "$Q/cases/$s/reg20k_truth.npz" ]; then
    mkdir -p "$NOISY/$s"
    ln -s "$Q/cases/$s/noisy20k.obj" "$NOISY/$s/noisy20k.obj"
    ln -s "$Q/cases/$s/reg20k_truth.npz" "$NOISY/$s/noisy20k_truth.npz"
  fi
done

echo "## Lines (score.py, default settings, tolerance 1% of the diagonal)"
echo
for m in hpw ybs saliency; do
  python3 "$Q/score.py" "$BIN extract {in} -o {out} --method $m -q" --json "$OUT/$m.json" > /dev/null
done
python3 - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
res = {m: json.load(open(f"{out}/{m}.json")) for m in ("hpw", "ybs", "saliency")}
cases = list(res["hpw"]["cases"])
print("| case | HPW P / R / F1 | YBS P / R / F1 | saliency P / R / F1 |")
print("| --- | --- | --- | --- |")
def cell(r):
    if "error" in r: return "failed"
    if "spurious" in r: return f"spurious {r['spurious']:.3f} diagonals"
    return f"{r['precision']:.3f} / {r['recall']:.3f} / **{r['f1']:.3f}**"
for c in cases:
    print(f"| {c} | " + " | ".join(cell(res[m]["cases"][c]) for m in res) + " |")
print()
print("| method | mean F1 (19 cases) | clean meshes | worst noisy | worst ring spurious |")
print("| --- | ---: | ---: | ---: | ---: |")
for m, r in res.items():
    s = r["summary"]
    print(f"| {m} | {s['mean_f1']:.3f} | {s['mean_f1_clean']:.3f} | {s['min_f1_noisy']:.3f} | {s['max_spurious']:.3f} |")
PY
echo
echo "## Estimators (score_fields.py: RMS error of k / max |k|, of e / 95th percentile |e|)"
echo
for e in "jet-fit" "shape-operator" "cubic-fit"; do
  python3 "$Q/score_fields.py" "$BIN curvature {in} -o {out} --estimator $e" --json "$OUT/f-$e.json" > /dev/null
  python3 "$Q/score_fields.py" "$BIN curvature {in} -o {out} --estimator $e" --cases "$NOISY" --json "$OUT/fn-$e.json" > /dev/null
done
python3 - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
names = ("jet-fit", "shape-operator", "cubic-fit")
res = {e: {**json.load(open(f"{out}/f-{e}.json"))["cases"], **json.load(open(f"{out}/fn-{e}.json"))["cases"]} for e in names}
print("| case | " + " | ".join(f"{e}: k max/min, e max/min" for e in names) + " |")
print("| --- | " + " | ".join("---" for _ in names) + " |")
for c in sorted(res["jet-fit"]):
    cells = []
    for e in names:
        r = res[e][c]
        cells.append("failed" if "error" in r else
                     f"{r['kmax_rms']:.4f}/{r['kmin_rms']:.4f}, {r['emax_rms']:.3f}/{r['emin_rms']:.3f}")
    print(f"| {c} | " + " | ".join(cells) + " |")
print()
print("| estimator | worst k RMS, non-noisy | worst e RMS, non-noisy | worst k RMS, noisy | worst e RMS, noisy |")
print("| --- | ---: | ---: | ---: | ---: |")
for e in names:
    ok = {c: r for c, r in res[e].items() if "error" not in r}
    clean = [r for c, r in ok.items() if "noisy" not in c]
    noisy = [r for c, r in ok.items() if "noisy" in c]
    w = lambda rs, k: max(max(r[k + "max_rms"], r[k + "min_rms"]) for r in rs) if rs else float("nan")
    print(f"| {e} | {w(clean, 'k'):.4f} | {w(clean, 'e'):.3f} | {w(noisy, 'k'):.4f} | {w(noisy, 'e'):.3f} |")
PY
