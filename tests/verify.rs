//! The register of claims: the table of `docs/results.md` is the one `tetwalk verify --register` generates, every
//! check names a registered method and an existing counterexample, and `verify` says PASS or FAIL per
//! claim with an exit status that holds the register to what it finds.

mod common;

use tetwalk::backend::CPU;
use tetwalk::engine::verify::{Check, Evidence, Expect, checks, pick, verify};
use tetwalk::family::{Kind, Scale};
use tetwalk::report::verify::register_table;

fn found() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("corpora/found")
}

#[test]
fn the_guide_holds_the_generated_register() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/results.md")).unwrap();
    assert!(
        readme.contains(&register_table()),
        "docs/results.md's register is stale: paste `cargo run --release -- verify --register`"
    );
}

#[test]
fn every_check_names_a_method_and_a_counterexample_that_exist() {
    let mut names = Vec::new();
    for c in checks() {
        assert!(c.known(), "{}: no method {}", c.name, c.method);
        assert!(!names.contains(&c.name), "{} twice", c.name);
        names.push(c.name);
        if let Evidence::Counterexample(f) = c.evidence {
            assert!(found().join(f).is_file(), "{}: {f}", c.name);
            assert_eq!(c.expect, Expect::Refuted, "{}", c.name);
        }
    }
    assert!(names.len() >= 15);
    assert_eq!(pick(&["woop-watertight".into()], &[]).unwrap().len(), 6);
    assert!(pick(&["nonsense".into()], &[]).is_err());
}

const ONE: &[Scale] = &[Scale::uniform(0)];
const SIXTY: &[Scale] = &[Scale::uniform(60)];

/// A check whose expectation is wrong is reported against the register; right ones as registered.
#[test]
fn verify_holds_the_register_to_what_it_finds() {
    let refuted = pick(&["maria17@cpu".into()], &[]).unwrap()[0];
    let r = verify(refuted, &CPU, 200, &found()).unwrap();
    assert!(!r.holds && r.as_registered == Some(true), "{r:?}");
    let wrong = Check {
        expect: Expect::Stands,
        ..*refuted
    };
    let r = verify(&wrong, &CPU, 200, &found()).unwrap();
    assert_eq!(r.as_registered, Some(false));
    // A domain whose stop does not stop is wider than the register says.
    let certified = Check {
        name: "certified-with-a-stop",
        family: Kind::ExitFace,
        method: "certified",
        backend: tetwalk::backend::BackendKind::Cpu,
        adapter: None,
        expect: Expect::Stands,
        evidence: Evidence::Domain {
            holds: ONE,
            stops: SIXTY,
        },
    };
    let r = verify(&certified, &CPU, 200, &found()).unwrap();
    assert!(!r.holds && r.seen.contains("wider"), "{r:?}");
}

/// The command: PASS / FAIL lines, status 0 when all goes as registered; status 1 when a counterexample
/// no longer fails (a corpus where it was replaced by a case the method gets right, or edited: its
/// case as found made right, or its recorded answer changed); status 2 for an unknown name.
#[test]
fn the_command_says_pass_or_fail_and_its_status_holds_the_register() {
    let (code, out, err) = common::run_tetwalk(
        &[
            "verify",
            "--run",
            "maria17@cpu,woop-watertight@cpu,exact-cells",
            "--cases",
            "200",
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("FAIL  maria17@cpu") && out.contains("as registered"),
        "{out}"
    );
    assert!(
        out.contains("PASS  woop-watertight@cpu") && out.contains("at 2^47"),
        "{out}"
    );
    assert!(out.contains("PASS  exact-cells@cpu"), "{out}");
    assert!(err.contains("every one as the register says"), "{err}");

    let dir = tempfile::tempdir().unwrap();
    let maria = dir.path().join("maria17");
    // `verify` of maria17's claim on the CPU against the corpus in `dir`.
    let verify = || {
        common::run_tetwalk(
            &[
                "verify",
                "--run",
                "maria17@cpu",
                "--found",
                dir.path().to_str().unwrap(),
            ],
            b"",
        )
    };
    std::fs::create_dir(&maria).unwrap();
    std::fs::write(
        maria.join("exit_face-wrong_face-50e741ec2f3d.json"),
        r#"{"tet":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"org":[0.2,0.2,-1],"dir":[0.01,0.02,1],"method":"maria17","backend":"cpu","kind":"wrong_face","answer":0}"#,
    )
    .unwrap();
    let (code, out, err) = verify();
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains("PASS  maria17@cpu") && out.contains("AGAINST THE REGISTER"),
        "{out}"
    );

    // Edited, not replaced: the case as found made one the method gets right (the shrunk one still
    // failing), or the recorded answer changed. Either is against the register.
    let real = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("corpora/found/maria17/exit_face-wrong_face-50e741ec2f3d.json"),
    )
    .unwrap();
    let mut v: serde_json::Value = serde_json::from_str(real.trim()).unwrap();
    let mut right_original = v.clone();
    right_original["original"] = serde_json::json!({"tet":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"org":[0.2,0.2,-1],"dir":[0.01,0.02,1],"entry":3});
    let recorded = v["answer"].as_u64().unwrap();
    v["answer"] = serde_json::json!((recorded + 1) % 4);
    for (edit, says) in [
        (right_original, "as found, right now"),
        (v, "records the answer"),
    ] {
        std::fs::write(
            maria.join("exit_face-wrong_face-50e741ec2f3d.json"),
            edit.to_string(),
        )
        .unwrap();
        let (code, out, err) = verify();
        assert_eq!(code, 1, "{out}{err}");
        assert!(
            out.contains("AGAINST THE REGISTER") && out.contains(says),
            "{out}"
        );
    }

    let (code, _, err) = common::run_tetwalk(&["verify", "--run", "nonsense"], b"");
    assert_eq!(code, 2);
    assert!(
        err.contains("no claim 'nonsense'") && err.contains("certified@cpu"),
        "{err}"
    );
}

/// A standing claim is checked against the found corpus too: a corpus holding a case that refutes it
/// (`woop-watertight` leaking where its products underflow, filed by a stress campaign at 2^-70) makes
/// `verify` report it refuted against the register, status 1; the shipped corpus does not.
#[test]
fn a_found_case_refuting_a_standing_claim_fails_verify() {
    let dir = tempfile::tempdir().unwrap();
    let corpus = dir.path().join("found");
    let (code, _, err) = common::run_tetwalk(
        &[
            "stress",
            "--family",
            "triangle",
            "--methods",
            "woop-watertight",
            "--scale",
            "-70",
            "--cases",
            "200",
            "--seconds",
            "1",
            "--found",
            corpus.to_str().unwrap(),
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = common::run_tetwalk(
        &[
            "verify",
            "--run",
            "woop-watertight@cpu",
            "--cases",
            "20",
            "--found",
            corpus.to_str().unwrap(),
        ],
        b"",
    );
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains("AGAINST THE REGISTER") && out.contains("refutes it"),
        "{out}"
    );
}

const H200: &str = "gpu: NVIDIA H200 (Vulkan, DiscreteGpu, driver NVIDIA 580.159.04)";
const LAVAPIPE: &str =
    "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, Cpu, driver llvmpipe Mesa 22.3.6)";

/// On a GPU the register speaks per adapter: on the H200 the NVIDIA checks run and lavapipe's are
/// left out, on lavapipe the reverse; on an adapter the register does not know, both run (and say
/// their word is for another adapter); CPU checks run everywhere.
#[test]
fn gpu_checks_are_registered_per_adapter() {
    let check = |name: &str| checks().find(|c| c.name == name).unwrap();
    let (lavapipe, nvidia) = (
        check("woop-watertight@gpu"),
        check("woop-watertight@gpu-nvidia"),
    );
    assert!(nvidia.registered_for(Some(H200)) && !nvidia.elsewhere(Some(H200)));
    assert!(!lavapipe.registered_for(Some(H200)) && lavapipe.elsewhere(Some(H200)));
    assert!(lavapipe.registered_for(Some(LAVAPIPE)) && nvidia.elsewhere(Some(LAVAPIPE)));
    let other = Some("AMD Radeon RX 7900 (Vulkan, DiscreteGpu, driver radv)");
    for c in [lavapipe, nvidia] {
        assert!(
            !c.registered_for(other) && !c.elsewhere(other),
            "{}",
            c.name
        );
    }
    let cpu = check("woop-watertight@cpu");
    assert!(cpu.registered_for(None) && cpu.registered_for(Some(H200)));
}

/// The NVIDIA checks say what `tetwalk verify` saw on the H200 (`corpora/results/h200/verify-gpu.txt`):
/// every claim it checked there has an NVIDIA check expecting what it found.
#[test]
fn the_nvidia_checks_say_what_the_h200_saw() {
    let seen = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/corpora/results/h200/verify-gpu.txt"
    ))
    .unwrap();
    let mut n = 0;
    for l in seen.lines() {
        let mut words = l.split_whitespace();
        let (Some(pass), Some(name), Some(word)) = (words.next(), words.next(), words.next())
        else {
            continue;
        };
        let nvidia = format!("{name}-nvidia");
        let c = checks()
            .find(|c| c.name == nvidia)
            .unwrap_or_else(|| panic!("no check {nvidia} for the H200's line: {l}"));
        let stood = word.trim_end_matches(',') == "stands";
        assert_eq!(stood, pass == "PASS", "{l}");
        let expect = if stood {
            Expect::Stands
        } else {
            Expect::Refuted
        };
        assert_eq!(c.expect, expect, "{nvidia}: the H200 saw {l}");
        assert!(c.registered_for(Some(H200)), "{nvidia}");
        n += 1;
    }
    assert_eq!(n, 4, "the H200's four checks");
}
