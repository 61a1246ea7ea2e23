#!/bin/sh
# Runs the fuzz targets one after the other, each for the given number of seconds, at the
# lowest priority, one process each (the machine is shared). Corpora grow in fuzz/corpus/<target>
# (seeded from fuzz/seeds/<target>), crashes land in fuzz/artifacts/<target>, and libFuzzer's
# last status line (executions, coverage) is appended to fuzz/runs.log.
#
#   cargo +nightly fuzz build --sanitizer none -a      # once (debug assertions on)
#   fuzz/run.sh 600 obj ply off stl lines mask extract
set -eu
here=$(cd "$(dirname "$0")" && pwd)
seconds=$1
shift
bin=${FUZZ_BIN:-$here/target/x86_64-unknown-linux-gnu/release}
for target in "$@"; do
    mkdir -p "$here/corpus/$target" "$here/artifacts/$target"
    start=$(date -u +%H:%M:%S)
    # -max_len: the pipeline target reads at most 3 KB anyway; parsers get room for headers
    # and a few records.
    case $target in extract) max_len=3001 ;; *) max_len=4096 ;; esac
    nice -n 19 "$bin/$target" "$here/corpus/$target" "$here/seeds/$target" \
        -max_total_time="$seconds" -max_len="$max_len" -rss_limit_mb=2048 -timeout="${FUZZ_TIMEOUT:-10}" \
        -artifact_prefix="$here/artifacts/$target/" -print_final_stats=1 \
        > "$here/corpus/$target.log" 2>&1 || true
    execs=$(grep -a 'stat::number_of_executed_units' "$here/corpus/$target.log" | awk '{print $2}')
    crashes=$(ls "$here/artifacts/$target" | wc -l)
    echo "$target start=$start seconds=$seconds executions=${execs:-?} artifacts=$crashes" >> "$here/runs.log"
done
