//! The constants z3 checks (proofs/certified/constants.smt2, run by proofs/certified/check.sh in CI)
//! are the ones certified's code uses, model by model.

use tetwalk::methods::certified::{Bound, FLUSHING, GPU, GRADUAL, TINY};

/// The exponent of a normal power of two.
fn log2(v: f32) -> i32 {
    assert!(
        v.is_normal() && v.to_bits() & 0x7f_ffff == 0,
        "{v} is not a power of two"
    );
    (v.to_bits() >> 23) as i32 - 127
}

#[test]
fn the_checked_constants_are_the_codes() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/proofs/certified/constants.smt2"
    ))
    .unwrap();
    let stated: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("; bound constants:"))
        .collect();
    let want: Vec<String> = [GRADUAL, FLUSHING, GPU]
        .iter()
        .map(|b: &Bound| {
            format!(
                "; bound constants: a = 2^{}, mu = 2^{}, c = 2^{}",
                log2(b.a),
                log2(b.mu),
                log2(b.c)
            )
        })
        .collect();
    assert_eq!(stated, want);
    // The gate's threshold is the one gate.smt2 checks (2^-102).
    assert_eq!(log2(TINY), -102);
    let gate = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/proofs/certified/gate.smt2"
    ))
    .unwrap();
    assert!(gate.contains(&format!("(/ 1.0 {}.0)", 1u128 << 102)));
}
