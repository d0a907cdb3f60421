#!/usr/bin/env bash
# The three routes of "Judging your own traversal" (docs/your-own.md), end to end, as the guide shows
# them (a test checks the guide holds these lines; CI runs this script). Needs a GPU adapter for route 2 (lavapipe).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$(mktemp -d)

# Route 1: a Rust method, judged from its own crate's cargo test (examples/conformance/tests/).
cargo test --release -p tetwalk-conformance-example

# Route 2: a WGSL function (user_prepare, user_exit), spliced into the GPU shader as method `user`.
cargo run --release -- gen-cases --tet-shape needle --rays near-edge --flatness 0.001 --count 1000 > "$out/cases.jsonl"
cargo run --release -- exit --wgsl examples/conformance/wgsl/my_plucker.wgsl --backend gpu --method plucker "$out/cases.jsonl" > "$out/verdicts.jsonl"
cargo run --release -- stress --wgsl examples/conformance/wgsl/my_plucker.wgsl --backend gpu --methods plucker --cases 2000
cargo run --release -- walk --mesh kuhn --wgsl examples/conformance/wgsl/my_plucker.wgsl --backend gpu --methods plucker

# Route 3: answers computed anywhere. tetwalk writes the inputs, your program writes one answer each.
cargo run --release -- count --scene kuhn-far --views 6 --size 24x24 --rays-out "$out/rays.jsonl"
cargo run --release -- scene export kuhn-far "$out/mesh.json"
cargo run --release -p tetwalk-conformance-example --bin answer-walks -- f32 "$out/mesh.json" "$out/rays.jsonl" > "$out/answers.jsonl"
cargo run --release -- judge "$out/rays.jsonl" "$out/answers.jsonl" --name my-f32-plucker --json "$out/judged.json"
cargo run --release -- count --scene kuhn-far --views 6 --size 24x24 --methods plucker --json "$out/counted.json"
cargo run --release -p tetwalk-conformance-example --bin answer-walks -- exact "$out/mesh.json" "$out/rays.jsonl" > "$out/exact.jsonl"
cargo run --release -- judge "$out/rays.jsonl" "$out/exact.jsonl" --name my-exact-plucker --json "$out/exact.json"

# Checks: route 2's `user` answers every case as `plucker` does; route 3's f32 walks are wrong exactly
# as often as tetwalk's `plucker` walks (the same arithmetic), its exact walks never.
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
by = {}
for l in open(f"{out}/verdicts.jsonl"):
    v = json.loads(l)
    by.setdefault(v.pop("line"), {})[v.pop("method")] = v
assert all(d["user"] == d["plucker"] for d in by.values()), "user and plucker differ"
wrong = sum(d["user"]["correct"] is False for d in by.values())
judged = json.load(open(f"{out}/judged.json"))["methods"][1]
counted = json.load(open(f"{out}/counted.json"))["methods"][1]
assert judged["wrong_total"] == counted["wrong_total"], (judged["wrong_total"], counted["wrong_total"])
assert json.load(open(f"{out}/exact.json"))["methods"][1]["wrong_total"] == 0, "the exact walker is wrong"
print(f"routes: user = plucker on {len(by)} cases ({wrong} wrong); given f32 walks wrong {judged['wrong_total']} = plucker's {counted['wrong_total']}, exact walks 0")
PY
