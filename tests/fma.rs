//! The fused model (`--backend cpu-fma`) runs on the processor's FMA instruction where it has one,
//! and through `f32::mul_add` with `TETWALK_NO_FMA=1`: both round each `a·b + c` once, so every
//! answer must be the same: the stress rows of every family (slivers, needles, far offsets, rays
//! exactly through and within ulps of edges and vertices), and a count of the built-in scene.

mod common;

use serde_json::Value;

/// A report without what only timing decides.
fn untimed(v: Value) -> Value {
    match v {
        Value::Object(o) => Value::Object(
            o.into_iter()
                .filter(|(k, _)| {
                    !k.contains("second") && !k.contains("per_s") && k != "date" && k != "elapsed"
                })
                .map(|(k, v)| (k, untimed(v)))
                .collect(),
        ),
        Value::Array(a) => Value::Array(a.into_iter().map(untimed).collect()),
        v => v,
    }
}

/// The answers a report judged and those it found wrong (every `judged` or `rays` number, and every
/// `wrong…` one).
fn tallied(v: &Value) -> (u64, u64) {
    match v {
        Value::Object(o) => o.iter().fold((0, 0), |(j, w), (k, v)| {
            let n = v.as_u64().unwrap_or(0);
            let (a, b) = tallied(v);
            (
                j + a + if k == "judged" || k == "rays" { n } else { 0 },
                w + b + if k.starts_with("wrong") { n } else { 0 },
            )
        }),
        Value::Array(a) => a
            .iter()
            .map(tallied)
            .fold((0, 0), |x, y| (x.0 + y.0, x.1 + y.1)),
        _ => (0, 0),
    }
}

/// Run `args` with `--json FILE` both ways; each report, untimed.
fn both(args: &[&str]) -> (Value, Value) {
    let dir = tempfile::tempdir().unwrap();
    let mut out = Vec::new();
    for (k, env) in [&[][..], &[("TETWALK_NO_FMA", "1")][..]].iter().enumerate() {
        let path = dir.path().join(format!("{k}.json"));
        let mut a = args.to_vec();
        a.extend(["--json", path.to_str().unwrap()]);
        let (code, _, err) = common::run_tetwalk_env(&a, b"", env);
        assert!(code == 0 || code == 1, "{args:?}: {err}");
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        out.push(untimed(v));
    }
    let b = out.pop().unwrap();
    (out.pop().unwrap(), b)
}

/// Both ways, the same answers; and `bench` says the two runs took the two paths.
#[test]
fn the_fma_instruction_answers_as_mul_add() {
    for (family, cases) in [
        ("exit-face", "400"),
        ("walk", "100"),
        ("triangle", "100"),
        ("octree", "200"),
    ] {
        let (fma, mul_add) = both(&[
            "stress",
            "--family",
            family,
            "--backend",
            "cpu-fma",
            "--cases",
            cases,
        ]);
        assert_eq!(fma, mul_add, "stress --family {family}");
        let (judged, wrong) = tallied(&fma);
        assert!(
            judged > 0 && wrong > 0,
            "stress --family {family} judged {judged} answers, {wrong} wrong: the rows compared hold wrong answers"
        );
    }
    let (fma, mul_add) = both(&[
        "count",
        "--backend",
        "cpu-fma",
        "--views",
        "4",
        "--size",
        "96x64",
    ]);
    assert_eq!(fma, mul_add, "count"); // The two runs took the two paths: `bench` says which.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bench.json");
    let said = |env: &[(&str, &str)]| {
        let (code, _, err) = common::run_tetwalk_env(
            &[
                "bench",
                "--views",
                "1",
                "--size",
                "8x8",
                "--backend",
                "cpu-fma",
                "--methods",
                "ray-plane",
                "--json",
                path.to_str().unwrap(),
            ],
            b"",
            env,
        );
        assert_eq!(code, 0, "{err}");
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        v["fma_instruction"]
            .as_bool()
            .expect("bench says how cpu-fma ran")
    };
    #[cfg(target_arch = "x86_64")]
    assert_eq!(said(&[]), std::arch::is_x86_feature_detected!("fma"));
    assert!(!said(&[("TETWALK_NO_FMA", "1")]));
}
