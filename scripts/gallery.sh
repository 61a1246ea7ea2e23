#!/usr/bin/env bash
# Regenerates the README gallery (docs/gallery/*.png) from the shared meshes.
# Usage: scripts/gallery.sh [MESH_DIR]   (default: ../shared/data/meshes beside the repository)
set -euo pipefail
cd "$(dirname "$0")/.."
meshes=${1:-../shared/data/meshes}
out=docs/gallery
mkdir -p "$out"
cargo build --release -q -p crestline-cli
bin=target/release/crestline
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# name  mesh  method  view  extra extract options
while read -r name mesh method view extra; do
  "$bin" extract "$meshes/$mesh" --method "$method" -o "$tmp/$name.obj" -q $extra
  "$bin" render "$meshes/$mesh" --lines "$tmp/$name.obj" -o "$out/$name.png" --size 640 --view "$view"
done <<'LIST'
fandisk-hpw   fandisk.obj         hpw  30,20
fandisk-ybs   fandisk.obj         ybs  30,20   --rings=1
bunny-hpw     stanford-bunny.obj  hpw  30,20
igea-hpw      igea.ply            hpw  20,10   --threshold=auto
igea-saliency igea.ply            saliency 20,10
rocker-ybs    rocker-arm.obj      ybs  30,30   --rings=2
teapot-hpw    teapot.obj          hpw  30,20
LIST
echo "gallery written to $out"
