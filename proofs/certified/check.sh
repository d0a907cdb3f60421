#!/usr/bin/env bash
# Mechanical checks of certified's f32-stage bound (src/methods/certified.md): each lemma the derivation
# uses about f32 rounding, checked by z3's floating-point theory over every f32 input, and the
# constants' conditions, in exact rational arithmetic. Each file asserts the negation of its claim, so
# `unsat` proves the claim; gate_is_needed.smt2 shows the gate cannot be dropped (`sat`).
set -euo pipefail
cd "$(dirname "$0")"
command -v z3 >/dev/null || { echo "z3 is not installed (.ci/setup installs it)"; exit 1; }
expect() {
    local file=$1 want=$2 got
    got=$(timeout 600 z3 "$file" | tr '\n' ' ' | sed 's/ $//')
    if [ "$got" != "$want" ]; then
        echo "FAIL $file: z3 answered '$got', expected '$want'"
        exit 1
    fi
    echo "ok   $file: $got"
}
expect sub_underflow_exact.smt2 unsat
expect mul_underflow.smt2 unsat
expect gate.smt2 unsat
expect gate_is_needed.smt2 sat
expect monotone.smt2 unsat
expect constants.smt2 "unsat unsat unsat"
