#!/usr/bin/env bash
# kernels/c/certified.h judged by tetwalk as any kernel is (docs/fix.md): built with each C compiler
# present (gcc, clang) at -O0 and -O3, contraction off and fused (-mfma -ffp-contract=fast, where the
# processor has FMA), and with subnormals flushed (TETWALK_FTZ=1: FTZ and DAZ), each asked through
# the answerer protocol with its claim held (--answerer-claims --fail-on claims): every exit-face row
# at scales from 2^-140 to 2^110 (the direction at its own scale too), a campaign, and walks through
# the built-in scenes and the lattice-tie meshes step by step; and once from numpy through a shared
# library built from it. Any wrong answer fails it.
#
#   bash scripts/certified-c.sh [CASES_PER_ROW] [CAMPAIGN_SECONDS]     (default 2000, 2)
set -euo pipefail
cd "$(dirname "$0")/.."
cases=${1:-2000}
seconds=${2:-2}
TETWALK_BUILD=1 source scripts/tetwalk-bin.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# A run's lines and standings are shown only where it fails.
quiet() {
    "$@" >"$work/out" 2>&1 || { cat "$work/out"; echo "certified.h failed: $*"; exit 1; }
}
flags=("-O0 -ffp-contract=off" "-O3 -ffp-contract=off")
grep -qw fma /proc/cpuinfo 2>/dev/null && flags+=("-O3 -mfma -ffp-contract=fast")
builds=0
for cc in gcc clang; do
    command -v "$cc" >/dev/null || { echo "SKIPPED: $cc is not installed"; continue; }
    for f in "${flags[@]}"; do
        exe="$work/certified-$cc-$builds"
        # shellcheck disable=SC2086
        "$cc" $f -std=c99 -Wall -Werror -I kernels/c -o "$exe" kernels/c/answerer.c
        builds=$((builds + 1))
        for env in "" "TETWALK_FTZ=1 "; do
            ask=("--answerer" "$env$exe" "--answerer-format" "binary" "--answerer-name" "c-certified"
                "--answerer-claims" "--fail-on" "claims")
            for scale in 0 -140 -100 -60 60 110 0/-60 0/40; do
                quiet "$tetwalk" stress "${ask[@]}" --cases "$cases" --scale "$scale"
            done
        done
        quiet "$tetwalk" stress "${ask[@]}" --seconds "$seconds" --found "$work/found"
        for scene in bunny-quality kuhn-far jitter-far fan; do
            quiet "$tetwalk" count --scene "$scene" --views 2 --size 32x32 "${ask[@]}"
        done
        echo "certified.h, $cc $f: never wrong (8 scales, flushed and not, a ${seconds} s campaign, 4 scenes walked)"
    done
done
[ "$builds" -gt 0 ] || { echo "no C compiler built certified.h"; exit 1; }
# From numpy: a shared library built from the header (kernels/c/batch.c), called through ctypes.
cc -O3 -shared -fPIC -Wall -Werror -I kernels/c -o "$work/libtetwalk_certified.so" kernels/c/batch.c
quiet "$tetwalk" stress --answerer "python3 kernels/python/certified.py $work/libtetwalk_certified.so" \
    --answerer-format binary --answerer-name numpy-certified --answerer-claims --fail-on claims --cases "$cases"
echo "certified.h from numpy (kernels/python/certified.py): never wrong"
