#!/usr/bin/env bash
# Other people's ray-triangle kernels judged by tetwalk, as a user would: every triangle stress row's
# cases (5 shapes x 5 aims x 3 placements, `gen-cases --shape`), answered by a program calling the
# library, judged by `tetwalk judge`; a table of leaks and misses beside per million rays, per aim and
# placement. Kernels: Embree 4 through the Python binding `embreex` (Embree's default scene flags, and
# RTC_SCENE_FLAG_ROBUST), and the Rust crate parry3d (f32), each where it installs (a loud SKIPPED
# where it does not).
#
#   bash examples/kernels/run.sh [CASES_PER_ROW] [OUT.md]     (default 2000, standard output)
set -euo pipefail
cd "$(dirname "$0")/../.."
cases=${1:-2000}
out=${2:-}
# The table to OUT.md, or onto standard output as it is (never reopened: a log that standard output
# and error share would be truncated, its SKIPPED lines lost).
table() { if [ -n "$out" ]; then cat >"$out"; else cat; fi; }
TETWALK_BUILD=1 source scripts/tetwalk-bin.sh
kernels=()
if python3 -c "import embreex" 2>/dev/null; then
    kernels+=(embree embree-robust)
else
    echo "SKIPPED Embree: the Python package embreex is not installed (pip install embreex)" >&2
fi
# Built where cargo builds this checkout (CARGO_TARGET_DIR honoured), in a folder of its own.
kernels_target=${CARGO_TARGET_DIR:-target}/kernels
parry=$kernels_target/release/tetwalk-parry-answers
if cargo build --release --quiet --manifest-path examples/kernels/parry/Cargo.toml --target-dir "$kernels_target"; then
    kernels+=(parry3d)
else
    echo "SKIPPED parry3d: examples/kernels/parry does not build here" >&2
fi
if [ ${#kernels[@]} -eq 0 ]; then
    echo "SKIPPED examples/kernels: no kernel installs here" >&2
    exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for shape in octahedron icosahedron tetrahedron sliver needle; do
    for aim in edge vertex near-edge near-vertex grazing; do
        for place in origin far embree; do
            row="$shape $aim $place"
            cases_file="$work/cases.jsonl"
            "$tetwalk" gen-cases --shape "$shape" --aim "$aim" --place "$place" --count "$cases" > "$cases_file"
            for kernel in "${kernels[@]}"; do
                case "$kernel" in
                    embree) python3 examples/kernels/embree_answers.py < "$cases_file" ;;
                    embree-robust) python3 examples/kernels/embree_answers.py --robust < "$cases_file" ;;
                    parry3d) "$parry" < "$cases_file" ;;
                esac > "$work/answers.jsonl"
                "$tetwalk" judge "$cases_file" "$work/answers.jsonl" --name "$kernel" \
                    --json "$work/judged.json" > /dev/null 2> /dev/null || true
                python3 - "$work/judged.json" "$row" "$kernel" >> "$work/rows.tsv" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
m = j["methods"][0]
k = m.get("kinds", {})
print("\t".join([sys.argv[2], sys.argv[3], str(j["lines"] - j["errors"]), str(k.get("leak", 0)), str(k.get("miss_beside", 0)), str(m["wrong"])]))
PY
            done
        done
    done
done
# woop-watertight, tetwalk's own, on the same rows for comparison.
"$tetwalk" stress --family triangle --cases "$cases" --methods woop-watertight --json "$work/woop.json" > /dev/null
python3 - "$work/rows.tsv" "$work/woop.json" "$cases" <<'PY' | table
import json, sys
from collections import defaultdict
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])]
woop = json.load(open(sys.argv[2]))
per = lambda n, of: f"{1e6 * n / of:,.0f}" if of else "—"
tot = defaultdict(lambda: [0, 0, 0])
for row, kernel, judged, leaks, beside, wrong in rows:
    shape, aim, place = row.split()
    for key in [(kernel, aim, place), (kernel, aim, "all"), (kernel, "all", "all")]:
        t = tot[key]
        t[0] += int(judged); t[1] += int(leaks); t[2] += int(beside)
wt = defaultdict(lambda: [0, 0])
for r in woop["rows"]:
    for key in [(r["aim"], r["place"]), (r["aim"], "all"), ("all", "all")]:
        wt[key][0] += r["rays"]
        wt[key][1] += r["tallies"][0]["leaks"]
aims = ["edge", "vertex", "near-edge", "near-vertex", "grazing", "all"]
places = ["origin", "far", "embree"]
print(f"Leaks (and misses beside) per million rays, {sys.argv[3]} rays per row, 5 closed shapes per aim and placement (tetwalk's triangle stress rows, `gen-cases --shape`), judged by `tetwalk judge`.\n")
names = {"embree": "Embree 4, default flags", "embree-robust": "Embree 4, RTC_SCENE_FLAG_ROBUST", "parry3d": "parry3d 0.17 (f32)"}
kernels = [k for k in names if any(r[1] == k for r in rows)]
print("| aim | placement | " + " | ".join(names[k] for k in kernels) + " | woop-watertight (tetwalk) |")
print("|---|---|" + "---|" * (len(kernels) + 1))
for aim in aims:
    for place in (places if aim != "all" else ["all"]):
        cells = []
        for kernel in kernels:
            j, l, b = tot[(kernel, aim, place)]
            cells.append(f"{per(l, j)} ({per(b, j)})")
        w = wt[(aim, place)]
        cells.append(per(w[1], w[0]))
        print(f"| {aim} | {place} | " + " | ".join(cells) + " |")
PY
