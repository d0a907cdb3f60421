#!/usr/bin/env bash
# Exit-face kernels outside tetwalk, judged through the answerer protocol (docs/answerers.md) as their
# users would: a C kernel (f32 Plücker with an epsilon and a face numbering of its own, found by
# `--faces auto`) in binary records, and a numpy one (ray-plane in float32). Each is stressed on every
# row (its contract stated: the C kernel's default, then origin inside with a unit direction and a
# given entry face, as photon-transport step functions assume), walked through the default scene step
# by step (`count --answerer`), campaigned, and its found cases shrunk inside the contract; the tables
# are printed as Markdown.
#
#   bash examples/kernels/tets.sh [CASES_PER_ROW] [CAMPAIGN_SECONDS]     (default 100000, 5)
set -euo pipefail
cd "$(dirname "$0")/../.."
cases=${1:-100000}
seconds=${2:-5}
TETWALK_BUILD=1 source scripts/tetwalk-bin.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cc -O2 -Wall -o "$work/plucker_eps" examples/kernels/c/plucker_eps.c
c_kernel=("--answerer" "$work/plucker_eps" "--answerer-format" "binary" "--answerer-name" "c-plucker-eps")
inside=("--origin" "inside" "--unit-direction" "--entry" "given")
python3 -c "import numpy" || { echo "examples/kernels/tets.sh: numpy is not installed (apt install python3-numpy)" >&2; exit 1; }
numpy_kernel=("--answerer" "python3 examples/kernels/python/ray_plane.py" "--answerer-format" "binary" "--answerer-name" "numpy-ray-plane")

echo "## c-plucker-eps (examples/kernels/c/plucker_eps.c), its face numbering found"
echo
"$tetwalk" stress "${c_kernel[@]}" --faces auto --cases "$cases"
echo
echo "## c-plucker-eps within a photon-transport contract ($(echo "${inside[@]}"))"
echo
"$tetwalk" stress "${c_kernel[@]}" --faces 3,0,1,2 "${inside[@]}" --cases "$cases"
echo
echo "## numpy-ray-plane (examples/kernels/python/ray_plane.py) beside tetwalk's ray-plane"
echo
"$tetwalk" stress "${numpy_kernel[@]}" --methods ray-plane --cases "$cases"
echo
echo "## Walked step by step (count --answerer) through the far Kuhn grid and the default scene, beside tetwalk's own"
echo
"$tetwalk" count --scene kuhn-far --views 4 --size 64x64 "${c_kernel[@]}" --faces 3,0,1,2 --methods plucker,ray-plane
"$tetwalk" count --views 4 --size 64x64 "${numpy_kernel[@]}" --methods ray-plane | tail -n +3
echo
walking=("--origin" "inside,entry" "--unit-direction" "--entry" "given")
echo "## c-plucker-eps walked step by step within a photon-transport contract ($(echo "${walking[@]}")), each step judged when asked"
echo
"$tetwalk" count --views 4 --size 64x64 "${c_kernel[@]}" --faces 3,0,1,2 "${walking[@]}" | tail -n +3
echo
echo "## A campaign of c-plucker-eps within that contract, its found cases shrunk inside it"
echo
"$tetwalk" stress "${c_kernel[@]}" --faces 3,0,1,2 "${inside[@]}" --cases 10000 --seconds "$seconds" --found "$work/found" --keep 1 | tail -n +2 | grep -v '^  /'
found=$(find "$work/found" -name '*.json' | sort | head -3)
[ -n "$found" ] || { echo "the campaign filed no found case"; exit 1; }
echo
echo '```'
# shellcheck disable=SC2086
"$tetwalk" shrink "${c_kernel[@]}" --faces 3,0,1,2 "${inside[@]}" $found 2>&1 | sed "s|$work/||g"
echo '```'
