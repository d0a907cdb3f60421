#!/usr/bin/env bash
# Builds the paper-scale scene `bunny-paper` (seed 000's order of size) from the shipped f32 bunny:
# Loop subdivision twice (`scene subdivide --levels 2`, f64 rounded once to f32), then a quality CDT
# (`scene build --quality`). Two runs write the same four files byte for byte; their sha256 sums are
# printed. Written beside this script (corpora/scenes/bunny-paper.{node,ele,neigh,face}), or into
# TETWALK_SCENES when set, the folder tetwalk looks in for it. The program: scripts/tetwalk-bin.sh
# (TETWALK, else the release build where cargo puts it, built first).
#
#   bash corpora/scenes/bunny-paper.sh
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
TETWALK_BUILD=1 source "$here/../../scripts/tetwalk-bin.sh"
out=${TETWALK_SCENES:-$here}
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$tetwalk" scene subdivide "$here/bunny.off" --levels 2 --out "$work/bunny-paper.off" >/dev/null
"$tetwalk" scene build "$work/bunny-paper.off" --quality --out "$work/bunny-paper" >/dev/null
for ext in node ele neigh face; do
    mv "$work/bunny-paper.$ext" "$out/bunny-paper.$ext"
done
(cd "$out" && sha256sum bunny-paper.node bunny-paper.ele bunny-paper.neigh bunny-paper.face)
echo "built bunny-paper in $out"
