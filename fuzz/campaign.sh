#!/usr/bin/env bash
# A fuzz campaign: every target for SECONDS each (default 600) holding `exact` and the methods that claim
# robustness to exactness, then each other method on its own (TRIANGLE_METHODS for triangle_hit); every failure is minimised, filed as a
# readable case under corpora/found/<method>/ (replayed by `cargo test`), and a table printed: executions,
# time to first failure, failures by kind. Usage: fuzz/campaign.sh [SECONDS] [METHODS...]
# TETWALK_FUZZ_BACKEND=gpu holds the methods on the GPU instead (WGPU_ADAPTER_NAME picks the adapter):
# each input is checked with its neighbours a few ulps away in one batch, and findings record the
# adapter and driver.
set -uo pipefail
# No sanitizer: AddressSanitizer's allocation tracking made the walk target 7.5x slower (800 against
# 6,060 executions per second); CI's brief runs use it (ClusterFuzzLite's build).
cd "$(dirname "$0")/.."
secs=${1:-600}
shift || true
others=${*:-ray-plane halfspace plucker stp ms06 aman20 aman20-scaled}
TETWALK_BUILD=1 source scripts/tetwalk-bin.sh
cargo +nightly fuzz build -O -s none >/dev/null
log=$(mktemp -d)
backend=${TETWALK_FUZZ_BACKEND:-cpu}
printf '| target | backend | methods held exact | executions | seconds to first failure | found |\n|---|---|---|---|---|---|\n' > "$log/table"
run() { # target selection
    local target=$1 sel=$2 out="$log/$1-$2" start end execs found kinds
    mkdir -p "corpora/$target" "$out"
    start=$(date +%s.%N)
    TETWALK_FUZZ_METHOD=$sel cargo +nightly fuzz run -O -s none "$target" "corpora/$target" -- \
        -max_total_time="$secs" -print_final_stats=1 -artifact_prefix="$out/" >"$out/log" 2>&1
    end=$(date +%s.%N)
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$out/log" | grep -o '[0-9]*$' || echo "?")
    found="-"
    if ls "$out"/crash-* >/dev/null 2>&1; then
        for c in "$out"/crash-*; do
            if [ "$target" = mesh_load ]; then
                echo "BUG: a reader panicked or hung on $c" | tee -a "$out/found"
                continue
            fi
            TETWALK_FUZZ_METHOD=$sel cargo +nightly fuzz tmin -O -s none "$target" "$c" -- -runs=5000 >/dev/null 2>&1
            m="fuzz/artifacts/$target/minimized-from-${c##*crash-}"
            [ -f "$m" ] || m=$c
            TETWALK_FUZZ_METHOD=$sel "$tetwalk" fuzz-import --target "$target" "$m" >>"$out/found"
        done
        found="$(cut -d' ' -f2- "$out/found" | sort | uniq -c | tr '\n' ';')"
        printf '| %s | %s | %s | %s | %.1f | %s |\n' "$target" "$backend" "$sel" "$execs" "$(echo "$end - $start" | bc)" "$found" >> "$log/table"
    else
        printf '| %s | %s | %s | %s | none in %s s | - |\n' "$target" "$backend" "$sel" "$execs" "$secs" >> "$log/table"
    fi
}
run mesh_load robust
for target in exit_face walk; do
    run "$target" robust
    for m in $others; do run "$target" "$m"; done
done
# The ray-triangle target: woop-watertight held to its claim (no leak), then each method on its own.
run triangle_hit robust
for m in ${TRIANGLE_METHODS:-mt mt-two-sided mt-precomputed komatsu-packet plucker-packet woop-watertight}; do
    run triangle_hit "$m"
done
# The octree cell target: each octree method on its own (no paper claims robustness).
for m in portalez16 portalez16-direction; do
    run octree_cell "$m"
    run octree_walk "$m"
done
cat "$log/table"
echo "found cases: corpora/found/ (replayed by cargo test); logs: $log"
