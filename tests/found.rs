//! Replays every case the fuzzers found (corpora/found/<method>/*.json): it must still fail for the
//! method that failed — it documents that method's weakness — and must pass for `exact` and for every
//! other method that claims robustness; where there is a GPU adapter, the robust methods are replayed
//! there too.

mod common;

use tetwalk::cases::{answers_gpu, classify, judged};
use tetwalk::found::Finding;
use tetwalk::methods::{METHODS, by_name};

fn findings() -> Vec<(String, Finding)> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/found");
    let mut out = Vec::new();
    for dir in std::fs::read_dir(root).unwrap().flatten() {
        for file in std::fs::read_dir(dir.path()).unwrap().flatten() {
            let text = std::fs::read_to_string(file.path()).unwrap();
            let f = Finding::from_json(&text)
                .unwrap_or_else(|e| panic!("{}: {e}", file.path().display()));
            out.push((file.path().display().to_string(), f));
        }
    }
    out
}

#[test]
fn found_cases_still_fail_for_their_method_and_pass_for_the_robust_ones() {
    let found = findings();
    assert!(
        found.len() >= 8,
        "the corpus of found cases is kept, not lost ({})",
        found.len()
    );
    for (name, f) in &found {
        let failed =
            by_name(&f.failure().method).unwrap_or_else(|| panic!("{name}: unknown method"));
        assert!(
            f.check(&[failed]).is_some(),
            "{name}: no longer fails for {}",
            failed.name
        );
        // A method that claims robustness must be right here, unless its failure here is filed too.
        for m in METHODS
            .iter()
            .filter(|m| m.claims_robust && m.name != failed.name)
        {
            let filed = found
                .iter()
                .any(|(_, g)| g.failure().method == m.name && g.key() == f.key());
            if !filed {
                assert_eq!(f.check(&[m]), None, "{name}: {} must be right here", m.name);
            }
        }
    }
}

#[test]
fn found_cases_replay_on_the_gpu() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    let found = findings();
    for (name, f) in &found {
        let Some(case) = f.case() else { continue };
        let failure = f.failure();
        let c = classify(&case).unwrap();
        for m in METHODS.iter().filter(|m| m.name != "exact") {
            let face = answers_gpu(&gpu, &[case], m).unwrap()[0];
            let right = judged(&c, face).correct;
            let filed = found
                .iter()
                .any(|(_, g)| g.failure().method == m.name && g.key() == f.key());
            if m.name == failure.method || filed {
                println!("{name}: {} on {}: {:?}", m.name, gpu.describe(), right);
            } else if m.claims_robust {
                assert_ne!(right, Some(false), "{name}: {} on the GPU", m.name);
            }
        }
    }
}
