#!/usr/bin/env bash
# The device check: on whatever GPU wgpu finds first, what a real GPU must show, in one command and
# (on an H100/H200 class GPU) at most 8 minutes, written into corpora/results/ADAPTER/:
#
#   adapter.md    the adapter and driver (gpu-info, nvidia-smi where present), the date, the commit
#   count-gpu.*   the default count on the GPU: judged rays per second per method, its transfer table
#                 (goal: at least 1 G judged rays per second per method on an H100/H200)
#   paper-gpu.*   `paper --full --backend gpu --scene bunny-paper`, timed (goal: at most 2 minutes)
#   verify-gpu.txt  the register's GPU claims checked on that adapter
#   agreement.md  every CPU model's agreement with this GPU's answers on the shared case sets
#                 (corpora/results/h200/*-cases.jsonl.gz), beside the H200's recorded answers
#   timings.md    each step's wall seconds
#
# Each file is written whole or not at all; a step that cannot run here says SKIPPED and why. Run it
# first whenever a real GPU is at hand (docs/gpu.md). The program: scripts/tetwalk-bin.sh (TETWALK,
# else the release build, built first). `--quick` runs each step small (a check of this script on
# lavapipe; its numbers are not the goals').
#
#   bash scripts/device-check.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
TETWALK_BUILD=${TETWALK_BUILD:-1} source scripts/tetwalk-bin.sh
quick=0
case "${1:-}" in
    --quick) quick=1 ;;
    "") ;;
    *) echo "usage: bash scripts/device-check.sh [--quick]" >&2; exit 2 ;;
esac
command -v python3 >/dev/null || { echo "scripts/device-check.sh: needs python3 (to compare answers)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$tetwalk" gpu-info --json "$work/gpu.json" >"$work/gpu.txt"
adapter=$(python3 -c 'import json, sys; a = json.load(open(sys.argv[1]))["adapters"]; print(a[0] if a else "")' "$work/gpu.json")
[ -n "$adapter" ] || { echo "scripts/device-check.sh: wgpu finds no adapter here" >&2; exit 2; }
# The folder: the adapter's name up to its first parenthesis, lower case, words joined by '-'.
name=$(sed 's/ (.*//' <<<"$adapter" | tr 'A-Z' 'a-z' | tr -cs 'a-z0-9' '-' | sed 's/^-*//; s/-*$//')
[ "$quick" = 1 ] && name="$name-quick"
out=corpora/results/$name
mkdir -p "$out"
staged() { mv "$work/$1" "$out/$1"; }

{
    echo "# Device check on $adapter"
    echo
    echo "- date: $(date -u +%Y-%m-%dT%H:%MZ)"
    echo "- tetwalk: $(git rev-parse --short HEAD 2>/dev/null || echo 'not a checkout') ($("$tetwalk" --version))"
    echo "- CPU threads: $(nproc)"
    echo "- mode: $([ "$quick" = 1 ] && echo 'quick (small steps: not the goals'"'"' sizes)' || echo full)"
    echo
    echo '```'
    cat "$work/gpu.txt"
    if command -v nvidia-smi >/dev/null; then
        nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv || true
    fi
    echo '```'
} >"$work/adapter.md"
staged adapter.md
echo "device check: $adapter -> $out"

timings="| step | wall seconds |\n|---|---|\n"
step() {
    local what=$1
    shift
    local t0=$SECONDS
    if "$@"; then
        timings+="| $what | $((SECONDS - t0)) |\n"
        echo "  $what: $((SECONDS - t0)) s"
    else
        timings+="| $what | failed |\n"
        echo "  $what: FAILED" >&2
        failed=1
    fi
}
failed=0

# 1. The default count on the GPU, every method, with its transfer table.
count() {
    local size=()
    [ "$quick" = 1 ] && size=(--views 2 --size 64x64)
    "$tetwalk" count --backend gpu "${size[@]}" --json "$work/count-gpu.json" >"$work/count-gpu.md"
    staged count-gpu.md
    staged count-gpu.json
}
step "count --backend gpu" count

# 2. The paper's tables at the papers' sizes on the GPU.
paper() {
    if ! "$tetwalk" scene check bunny-paper >/dev/null 2>&1; then
        bash corpora/scenes/bunny-paper.sh >/dev/null 2>&1 || {
            echo "SKIPPED paper: the bunny-paper scene cannot be built here (corpora/scenes/bunny-paper.sh needs tetgen)"
            return 0
        }
    fi
    local size=(--full)
    [ "$quick" = 1 ] && size=(--views 1 --side 64)
    "$tetwalk" paper "${size[@]}" --backend gpu --scene bunny-paper --json "$work/paper-gpu.json" >"$work/paper-gpu.md"
    staged paper-gpu.md
    staged paper-gpu.json
}
step "paper --backend gpu --scene bunny-paper" paper

# 3. The register's GPU claims on this adapter (status 1 where one does not go as registered).
verify() {
    local cases=()
    [ "$quick" = 1 ] && cases=(--cases 100)
    local status=0
    "$tetwalk" verify --run maria17@gpu,woop-watertight@gpu,certified@gpu,certified-walks@gpu "${cases[@]}" >"$work/verify-gpu.txt" 2>&1 || status=$?
    staged verify-gpu.txt
    return "$status"
}
step "verify (the GPU claims)" verify

# 4. Every CPU model's agreement with this GPU's answers on the shared case sets.
agreement() {
    local sets=("exit-underflow exit face" "triangle hit hit" "octree-cell box-exit face,quarter")
    {
        echo "Answers agreeing with this GPU's ($adapter), of its answers, per CPU model; the H200's recorded"
        echo "answers (corpora/results/h200/) beside."
        echo
        echo "| case set | model | agree with this GPU | agree with the H200 |"
        echo "|---|---|---|---|"
    } >"$work/agreement.md"
    for s in "${sets[@]}"; do
        read -r set command fields <<<"$s"
        gzip -dc "corpora/results/h200/$set-cases.jsonl.gz" >"$work/$set-cases.jsonl"
        gzip -dc "corpora/results/h200/$set-h200.jsonl.gz" >"$work/$set-h200.jsonl"
        [ "$quick" = 1 ] && head -n 300 "$work/$set-cases.jsonl" >"$work/x" && mv "$work/x" "$work/$set-cases.jsonl"
        "$tetwalk" "$command" --method all --backend gpu "$work/$set-cases.jsonl" >"$work/$set-gpu.jsonl" || [ $? = 1 ]
        for backend in cpu cpu-fma cpu-ftz cpu-gpu; do
            "$tetwalk" "$command" --method all --backend "$backend" "$work/$set-cases.jsonl" >"$work/$set-$backend.jsonl" || [ $? = 1 ]
            python3 - "$work/$set-gpu.jsonl" "$work/$set-h200.jsonl" "$work/$set-$backend.jsonl" "$backend" "$fields" "$set" >>"$work/agreement.md" <<'EOF'
import json, sys
gpu, h200, ours, backend, fields, name = sys.argv[1:]
fields = fields.split(",")
def answers(path, on):
    out = {}
    for line in open(path):
        o = json.loads(line)
        if o.get("backend") == on and "method" in o:
            out[(o["line"], o["method"])] = [json.dumps(o.get(f)) for f in fields]
    return out
g, h, c = answers(gpu, "gpu"), answers(h200, "gpu"), answers(ours, backend)
if not g:
    sys.exit(f"{name}: no answer from the GPU")
same = sum(c.get(k) == v for k, v in g.items())
held = {k: v for k, v in h.items() if k in g}
same_h = sum(c.get(k) == v for k, v in held.items())
print(f"| {name} | {backend} | {same} of {len(g)} | {same_h} of {len(held)} |")
EOF
        done
    done
    staged agreement.md
}
step "agreement of the CPU models" agreement

printf "%b" "$timings" >"$work/timings.md"
staged timings.md
ls "$out"
exit "$failed"
