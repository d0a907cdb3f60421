//! A user's WGSL exit-face function (`--wgsl FILE`), judged as method `user`: the example
//! `examples/conformance/wgsl/my_plucker.wgsl` (tetwalk's `plucker` rewritten by a user, same operation
//! order) gets exactly `plucker`'s verdicts on the GPU through `exit`, `stress` and `walk`, failures
//! included; a malformed or wrongly typed file gets the compiler's message with its own name and line
//! numbers (checked before any adapter is opened, so those tests need no GPU).

mod common;

use common::run_tetwalk;
use serde_json::Value;
use std::collections::HashMap;

const MY_PLUCKER: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/examples/conformance/wgsl/my_plucker.wgsl"
);

/// The example with one line edited, written to a temporary file.
fn edited(from: &str, to: &str) -> tempfile::NamedTempFile {
    let src = std::fs::read_to_string(MY_PLUCKER).unwrap();
    assert!(src.contains(from), "the example holds {from}");
    let f = tempfile::Builder::new().suffix(".wgsl").tempfile().unwrap();
    std::fs::write(f.path(), src.replacen(from, to, 1)).unwrap();
    f
}

fn near_edge_cases() -> Vec<u8> {
    let (code, out, err) = run_tetwalk(
        &[
            "gen-cases",
            "--family",
            "needle",
            "--rays",
            "near-edge",
            "--flatness",
            "0.001",
            "--count",
            "1000",
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    out.into_bytes()
}

#[test]
fn a_syntax_error_is_shown_at_the_users_line() {
    let f = edited("let e = b - a;", "let e = b - a");
    let path = f.path().to_str().unwrap();
    let (code, _, err) = run_tetwalk(&["exit", "--wgsl", path, "--backend", "gpu"], b"");
    assert_eq!(code, 2, "{err}");
    // The statement is on line 16; the parser stops at the next token, line 17, column 5.
    assert!(err.contains(&format!("{path}:17:5")), "{err}");
    assert!(err.contains("expected `;`"), "{err}");
}

#[test]
fn a_wrongly_typed_function_is_shown_at_the_users_lines() {
    let f = edited("return i32(f);", "return f;");
    let path = f.path().to_str().unwrap();
    let (code, _, err) = run_tetwalk(&["stress", "--wgsl", path, "--backend", "gpu"], b"");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!("{path}:27:1")) && err.contains("return"),
        "{err}"
    );
}

#[test]
fn a_signature_other_than_the_documented_one_is_named() {
    for (from, to) in [
        ("entry: i32) -> i32", "entry: u32) -> i32"),
        ("fn user_prepare", "fn my_prepare"),
    ] {
        let f = edited(from, to);
        let path = f.path().to_str().unwrap();
        let (code, _, err) = run_tetwalk(&["walk", "--wgsl", path, "--backend", "gpu"], b"");
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains(path)
                && err.contains(
                    "fn user_exit(t: ptr<function, array<vec3f, 4>>, r: R, entry: i32) -> i32"
                ),
            "{err}"
        );
    }
}

#[test]
fn wgsl_needs_the_gpu_backend_and_an_exit_face_command() {
    let (code, _, err) = run_tetwalk(&["count", "--wgsl", MY_PLUCKER], b"");
    assert_eq!(code, 2);
    assert!(err.contains("add --backend gpu"), "{err}");
    // `hit` judges ray-triangle methods: it takes no exit-face function, and its --help offers none.
    let (code, _, err) = run_tetwalk(&["hit", "--wgsl", MY_PLUCKER], b"");
    assert_eq!(code, 2);
    assert!(err.contains("unexpected argument '--wgsl'"), "{err}");
    let (_, help, _) = run_tetwalk(&["hit", "--help"], b"");
    assert!(!help.contains("--wgsl"), "{help}");
    let (code, _, err) = run_tetwalk(
        &["exit", "--wgsl", "/nonexistent.wgsl", "--backend", "gpu"],
        b"",
    );
    assert_eq!(code, 2);
    assert!(err.contains("/nonexistent.wgsl"), "{err}");
}

#[test]
fn exit_judges_the_users_wgsl_as_it_judges_plucker() {
    if common::gpu_or_skip().is_none() {
        return;
    }
    let cases = near_edge_cases();
    let (code, out, err) = run_tetwalk(
        &[
            "exit",
            "--wgsl",
            MY_PLUCKER,
            "--backend",
            "gpu",
            "--method",
            "plucker",
        ],
        &cases,
    );
    assert_eq!(code, 0, "{err}");
    let mut by_line: HashMap<u64, HashMap<String, Value>> = HashMap::new();
    for l in out.lines() {
        let mut v: Value = serde_json::from_str(l).unwrap();
        let m = v["method"].as_str().unwrap().to_string();
        v.as_object_mut().unwrap().remove("method");
        by_line
            .entry(v["line"].as_u64().unwrap())
            .or_default()
            .insert(m, v);
    }
    assert_eq!(by_line.len(), 1000);
    let mut wrong = 0;
    for (line, m) in &by_line {
        // Field for field: face, exact sets, verdict, backend.
        assert_eq!(m["user"], m["plucker"], "line {line}");
        wrong += (m["user"]["correct"] == Value::Bool(false)) as u32;
    }
    assert!(wrong > 0, "near-edge needles make f32 Plücker fail");
}

#[test]
fn the_users_names_may_be_tetwalks_own() {
    if common::gpu_or_skip().is_none() {
        return;
    }
    // The example with its names changed to names tetwalk's module uses itself.
    let src = std::fs::read_to_string(MY_PLUCKER)
        .unwrap()
        .replace("MyPluckerRay", "Ray")
        .replace("my_cross", "cross3")
        .replace("my_side", "side")
        .replace("MY_FACES", "NONE");
    let f = tempfile::Builder::new().suffix(".wgsl").tempfile().unwrap();
    std::fs::write(f.path(), src).unwrap();
    let (code, out, err) = run_tetwalk(
        &[
            "exit",
            "--wgsl",
            f.path().to_str().unwrap(),
            "--backend",
            "gpu",
            "--method",
            "plucker",
        ],
        &near_edge_cases(),
    );
    assert_eq!(code, 0, "{err}");
    let lines: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    for pair in lines.chunks(2) {
        assert_eq!(pair[0]["face"], pair[1]["face"], "{pair:?}");
    }
}

#[test]
fn stress_and_walk_tables_give_the_users_wgsl_pluckers_counts() {
    if common::gpu_or_skip().is_none() {
        return;
    }
    let json = tempfile::NamedTempFile::new().unwrap();
    let path = json.path().to_str().unwrap();
    let (code, _, err) = run_tetwalk(
        &[
            "stress",
            "--wgsl",
            MY_PLUCKER,
            "--backend",
            "gpu",
            "--methods",
            "plucker",
            "--cases",
            "2000",
            "--json",
            path,
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mut failed = 0;
    for row in r["rows"].as_array().unwrap() {
        let t = row["tallies"].as_array().unwrap();
        assert_eq!(t[0]["method"], "user");
        for k in ["judged", "wrong_face", "no_exit_face"] {
            assert_eq!(t[0][k], t[1][k], "{} {k}", row["row"]);
        }
        failed += t[0]["wrong_face"].as_u64().unwrap() + t[0]["no_exit_face"].as_u64().unwrap();
    }
    assert!(failed > 0);
    let (code, _, err) = run_tetwalk(
        &[
            "walk",
            "--mesh",
            "kuhn",
            "--wgsl",
            MY_PLUCKER,
            "--backend",
            "gpu",
            "--methods",
            "plucker",
            "--rays",
            "2000",
            "--json",
            path,
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let rows = r["methods"].as_array().unwrap();
    assert_eq!(rows[0]["method"], "user");
    for k in ["kinds", "wrong", "steps", "rays"] {
        assert_eq!(rows[0][k], rows[1][k], "{k}");
    }
}
