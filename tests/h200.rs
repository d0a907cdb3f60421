//! The CPU models against a real GPU's answers: an NVIDIA H200's recorded answers
//! (`corpora/results/h200/`) to three case sets, and each CPU backend's on the same cases. `cpu-gpu`
//! (fused and flushed) agrees with the H200 at least as often as every other model on every set, and
//! no less often than recorded in `corpora/results/h200/agreement.md`.

mod common;

use common::run_tetwalk;
use serde_json::Value;
use std::collections::HashMap;
use tetwalk::choice::Choice;
use tetwalk::methods::Model;

/// A file of `corpora/results/h200/`, gzip-compressed (`gzip -n`), decompressed.
fn gunzip(name: &str) -> Vec<u8> {
    let path = format!(
        "{}/corpora/results/h200/{name}.gz",
        env!("CARGO_MANIFEST_DIR")
    );
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    assert_eq!(
        &bytes[..4],
        &[0x1f, 0x8b, 8, 0],
        "{path}: gzip, deflate, no header fields"
    );
    miniz_oxide::inflate::decompress_to_vec(&bytes[10..bytes.len() - 8])
        .unwrap_or_else(|e| panic!("{path}: {e:?}"))
}

/// Each answer of a JSON Lines answer file by (line, method), as the fields compared: those of the
/// backend `on` (the reference's lines, always on the CPU, are left out).
fn answers(text: &str, on: &str, fields: &[&str]) -> HashMap<(u64, String), String> {
    text.lines()
        .filter_map(|l| {
            let o: Value = serde_json::from_str(l).unwrap();
            (o["backend"] == on).then(|| {
                let key = (
                    o["line"].as_u64().unwrap(),
                    o["method"].as_str()?.to_string(),
                );
                Some((key, fields.iter().map(|f| o[f].to_string()).collect()))
            })?
        })
        .collect()
}

/// A recorded case set: its files' name, the command that answers it, the answer's fields
/// compared, and the least agreement of `cpu-gpu` recorded (`agreement.md`): answers agreeing, of
/// the H200's.
struct Set {
    name: &'static str,
    command: &'static str,
    fields: &'static [&'static str],
    recorded: (u64, u64),
}

const SETS: [Set; 3] = [
    Set {
        name: "exit-underflow",
        command: "exit",
        fields: &["face"],
        recorded: (27_467, 30_300),
    },
    // `t` is left out: WGSL's division is within 2.5 ulps on the GPU, correctly rounded on the CPU.
    Set {
        name: "triangle",
        command: "hit",
        fields: &["hit"],
        recorded: (17_254, 17_664),
    },
    Set {
        name: "octree-cell",
        command: "box-exit",
        fields: &["face", "quarter"],
        recorded: (5_660, 6_000),
    },
];

#[test]
fn cpu_gpu_agrees_with_the_h200_at_least_as_often_as_every_other_model() {
    for Set {
        name: set,
        command,
        fields,
        recorded,
    } in SETS
    {
        let cases = gunzip(&format!("{set}-cases.jsonl"));
        let h200 = answers(
            &String::from_utf8(gunzip(&format!("{set}-h200.jsonl"))).unwrap(),
            "gpu",
            fields,
        );
        assert!(h200.len() > 1000, "{set}: {} H200 answers", h200.len());
        let mut agreed = Vec::new();
        for model in Model::ALL {
            let backend = model.backend().name();
            let (code, out, err) = run_tetwalk(
                &[command, "--method", "all", "--backend", backend, "-"],
                &cases,
            );
            assert!(code == 0 || code == 1, "{set} on {backend}: {err}");
            let ours = answers(&out, backend, fields);
            let missing = h200.keys().filter(|k| !ours.contains_key(*k)).count();
            assert_eq!(missing, 0, "{set} on {backend}: every H200 answer has ours");
            let same = ours.iter().filter(|(k, v)| h200.get(*k) == Some(v)).count() as u64;
            eprintln!(
                "{set}: {backend} agrees with the H200 on {same} of {}",
                h200.len()
            );
            agreed.push((model, same));
        }
        let gpu_like = agreed
            .iter()
            .find(|(m, _)| *m == Model::FusedFlushed)
            .unwrap()
            .1;
        for (m, same) in &agreed {
            assert!(
                gpu_like >= *same,
                "{set}: {} agrees more often ({same}) than cpu-gpu ({gpu_like})",
                m.backend().name()
            );
        }
        assert_eq!(h200.len() as u64, recorded.1, "{set}: the recorded answers");
        assert!(
            gpu_like >= recorded.0,
            "{set}: cpu-gpu agrees on {gpu_like}, recorded {}",
            recorded.0
        );
    }
}
