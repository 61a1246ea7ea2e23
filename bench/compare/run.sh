#!/usr/bin/env bash
# Side-by-side benchmark: `crestline extract` against CGAL's Monge_via_jet_fitting + Ridges_3
# (issue #9). Not part of the test suite.
#
#   bench/compare/run.sh            # from anywhere inside the repository
#
# Steps: (a) install libcgal-dev, libeigen3-dev, g++ and GNU time with apt-get when missing;
# (b) build the CGAL driver ridges_cgal.cpp (-O3 -DNDEBUG); (c) build crestline with the dist profile (fat LTO);
# (d) convert the shared meshes to OFF (`crestline subdivide --levels 0`) and make the
# ~1.6M-face mesh by two levels of Loop subdivision of horse (96,966 -> 1,551,456 faces);
# (e) run CGAL, crestline (default method, HPW) and crestline --method ybs on every mesh
# under /usr/bin/time -v, REPEATS times each; (f) write the markdown table (table.py) to
# $OUT/table.md and print it.
#
# Both tools read the same OFF file, so they see the same vertices and faces (CGAL cannot read
# igea's triangle-strip PLY). Environment:
#   MESHES_DIR  the shared meshes (default: ../shared/data/meshes beside the repository)
#   OUT         results folder (default: target/bench-compare in the repository)
#   REPEATS     runs per tool and mesh; the fastest is reported (default: 1)
#   MESHES      mesh names to run (default: "fandisk stanford-bunny horse igea horse-x16")
set -euo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
MESHES_DIR=${MESHES_DIR:-$ROOT/../shared/data/meshes}
OUT=${OUT:-$ROOT/target/bench-compare}
REPEATS=${REPEATS:-1}
MESHES=${MESHES:-fandisk stanford-bunny horse igea horse-x16}
mkdir -p "$OUT/inputs" "$OUT/results" "$OUT/lines"

# (a) System packages.
missing=()
for pkg in libcgal-dev libeigen3-dev g++ time; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if ((${#missing[@]})); then
    echo "installing ${missing[*]}" >&2
    sudo_cmd=()
    [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
    "${sudo_cmd[@]}" apt-get update
    DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
fi
cgal_version=$(dpkg-query -W -f='${Version}' libcgal-dev)
eigen_version=$(dpkg-query -W -f='${Version}' libeigen3-dev)

# (b) The CGAL driver (header-only CGAL; Eigen provides the SVD of the jet fit).
DRIVER=$OUT/ridges_cgal
if [[ ! -x $DRIVER || $HERE/ridges_cgal.cpp -nt $DRIVER ]]; then
    echo "building $DRIVER" >&2
    g++ -std=c++17 -O3 -DNDEBUG -DCGAL_EIGEN3_ENABLED -I/usr/include/eigen3 \
        "$HERE/ridges_cgal.cpp" -o "$DRIVER" -lgmp -lmpfr
fi

# (c) crestline, dist profile.
(cd "$ROOT" && cargo build --profile dist -p crestline-cli)
CRESTLINE=$ROOT/target/dist/crestline

# (d) Inputs as OFF.
source_file() {
    local name=$1
    for ext in obj ply off stl; do
        if [[ -f $MESHES_DIR/$name.$ext ]]; then
            echo "$MESHES_DIR/$name.$ext"
            return
        fi
    done
    echo "no mesh named $name in $MESHES_DIR" >&2
    exit 1
}
for name in $MESHES; do
    off=$OUT/inputs/$name.off
    [[ -f $off ]] && continue
    if [[ $name == horse-x16 ]]; then
        "$CRESTLINE" subdivide "$(source_file horse)" -o "$off" --levels 2
    else
        "$CRESTLINE" subdivide "$(source_file "$name")" -o "$off" --levels 0
    fi
done

# (e) Runs.
run_one() {
    local name=$1 tool=$2 run=$3
    local base=$OUT/results/$name.$tool.$run input=$OUT/inputs/$name.off
    local lines=$OUT/lines/$name.$tool.obj
    local cmd
    case $tool in
        cgal) cmd=("$DRIVER" "$input" -o "$lines") ;;
        hpw) cmd=("$CRESTLINE" extract "$input" -o "$lines" --stats=json -q) ;;
        ybs) cmd=("$CRESTLINE" extract "$input" -o "$lines" --stats=json -q --method ybs) ;;
    esac
    echo "$name $tool run $run: ${cmd[*]}" >&2
    if ! /usr/bin/time -v -o "$base.time" "${cmd[@]}" >"$base.json" 2>"$base.err"; then
        echo "failed: ${cmd[*]} (see $base.err)" >&2
        cat "$base.err" >&2
        exit 1
    fi
}
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
rm -f "$OUT"/results/*.json "$OUT"/results/*.time "$OUT"/results/*.err
for name in $MESHES; do
    for run in $(seq 1 "$REPEATS"); do
        for tool in cgal hpw ybs; do
            run_one "$name" "$tool" "$run"
        done
    done
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

# (f) The table.
{
    echo "CGAL $cgal_version (Debian libcgal-dev), Eigen $eigen_version, g++ $(g++ -dumpfullversion)," \
        "$(rustc --version | cut -d' ' -f1-2), $(nproc) cores, $(date -u +%Y-%m-%d)," \
        "load average $load_before before and $load_after after, fastest of $REPEATS run(s)."
    echo
    python3 "$HERE/table.py" "$OUT/results" $MESHES
} >"$OUT/table.md"
cat "$OUT/table.md"
