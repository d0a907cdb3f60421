//! Shrinking: a failure's case made as simple as it can be while its method still fails it the same
//! way — by the engine for every family, by `tetwalk shrink` on found cases and a count's dump, and in
//! the kit's report.

mod common;

use tetwalk::backend::CPU;
use tetwalk::engine::found::{Found, Replay, replay};
use tetwalk::engine::shrink::{bits, shrink, shrink_found};
use tetwalk::family::{ExitFace, Family, OctreeCells, Triangle, Verdict};

/// The register's counterexample as it was found (README, "What the papers claim"), maria17's.
const MARIA17: &str = r#"{"tet":[[6.5,-5.583333,1.0],[15.5,15.0,15.5],[-5.5,-16.0,-16.0],[-16.0,-16.0,-16.0]],"org":[-64.0,-64.0,-64.0],"dir":[70.5,58.416668,65.0],"entry":1,"method":"maria17","backend":"cpu","kind":"wrong_face","answer":2}"#;

/// A found case of each family from the corpus (shrunk already; shrinking its original again).
fn corpus_case<F: Family>(method: &str, holds: &str) -> Found<F> {
    let dir = format!("{}/corpora/found/{method}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| std::fs::read_to_string(e.path()).unwrap())
        .find(|t| t.contains(holds) && !t.contains("\"adapter\""))
        .map(|t| Found::<F>::parse(t.trim()).unwrap())
        .unwrap_or_else(|| panic!("a found case of {method} holding {holds}"))
}

/// Shrinking a found case of family `F` (its case as found): fewer significant bits, the original
/// kept, still wrong the same way (it replays with its new answer), and right for the family's
/// reference.
fn shrinks<F: Family>(found: &Found<F>) {
    let as_found = Found {
        case: found.original.unwrap_or(found.case),
        original: None,
        failure: found.failure.clone(),
    };
    let as_found = Found::<F>::parse(&as_found.to_json()).unwrap();
    // The recorded answer of the case as found is the method's answer there.
    let (shrunk, s) = shrink_found(&as_found, 20_000).unwrap().unwrap();
    assert_eq!(shrunk.original, Some(as_found.case));
    let (before, _) = bits::<F>(&as_found.case);
    let (after, _) = bits::<F>(&shrunk.case);
    assert!(after < before, "{}: {before} -> {after} bits", F::NAME);
    assert!(s.checks > 0 && !s.exhausted);
    let back = Found::<F>::parse(&shrunk.to_json()).unwrap();
    assert_eq!(
        back.to_json(),
        shrunk.to_json(),
        "the shrunk line reads back, its original too"
    );
    assert_eq!(replay(&back).unwrap(), Replay::Holds, "{}", F::NAME);
    let kind = |f: &Found<F>| f.failure.as_ref().unwrap().kind();
    assert_eq!(
        kind(&shrunk),
        kind(&as_found),
        "the same kind of wrong ending"
    );
    if let Some(r) = tetwalk::family::reference::<F>() {
        let truth = F::truth(&shrunk.case).unwrap();
        let a = F::answers(&CPU, r, &[shrunk.case]).unwrap()[0];
        assert_eq!(F::verdict(&shrunk.case, &truth, &a), Verdict::Right);
    }
}

#[test]
fn a_found_case_of_every_family_shrinks_and_still_fails_the_same_way() {
    shrinks::<ExitFace>(&Found::parse(MARIA17).unwrap());
    shrinks::<tetwalk::family::Walks>(&corpus_case("maria17", "\"mesh\""));
    shrinks::<Triangle>(&corpus_case("mt", "\"tris\""));
    shrinks::<OctreeCells>(&corpus_case("portalez16", "\"box\""));
}

/// A shrink keeps the kind of wrong answer: a cell test that finds no exit face is not shrunk into one
/// that finds a wrong one, nor a walk that misses the hit into one that ends elsewhere.
#[test]
fn a_shrink_keeps_the_kind_of_wrong_answer() {
    shrinks::<OctreeCells>(&corpus_case(
        "portalez16-direction",
        "\"kind\":\"no_exit_face\"",
    ));
    shrinks::<tetwalk::family::Walks>(&corpus_case("maria17", "\"kind\":\"false_miss\""));
}

/// The register's counterexample shrinks to integers but where the near-tie is (a vertex within
/// rounding of the line): 93 significant bits in 18 numbers before.
#[test]
fn the_registers_counterexample_shrinks_to_small_integers_around_its_tie() {
    let found = Found::<ExitFace>::parse(MARIA17).unwrap();
    let (shrunk, _) = shrink_found(&found, 20_000).unwrap().unwrap();
    let (before, _) = bits::<ExitFace>(&found.case);
    let (after, _) = bits::<ExitFace>(&shrunk.case);
    assert_eq!(before, 93);
    assert!(after <= 60, "{after}");
    let integers = ExitFace::numbers(&shrunk.case)
        .iter()
        .filter(|x| x.fract() == 0.0)
        .count();
    assert!(integers >= 14, "{}", shrunk.to_json());
}

/// A case its method answers rightly has nothing to shrink: an error saying so.
#[test]
fn a_case_answered_rightly_is_refused() {
    let right = Found::<ExitFace>::parse(
        r#"{"tet":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"org":[0.2,0.2,-1],"dir":[0.01,0.02,1]}"#,
    )
    .unwrap()
    .case;
    let m = tetwalk::registry::by_name("maria17").unwrap();
    let e = shrink::<ExitFace>(m, &CPU, &right, &[], 1000).unwrap_err();
    assert!(e.to_string().contains("answers it rightly"), "{e}");
}

/// `woop-watertight`'s leak, found fused, stays a leak when shrunk: the claim it refutes is refuted on
/// the shrunk case too.
#[test]
fn a_refuted_claim_stays_refuted() {
    let found = corpus_case::<Triangle>("woop-watertight", "cpu-fma");
    let as_found = Found {
        case: found.original.unwrap(),
        original: None,
        failure: found.failure.clone(),
    };
    let as_found = Found::<Triangle>::parse(&as_found.to_json()).unwrap();
    let (shrunk, _) = shrink_found(&as_found, 20_000).unwrap().unwrap();
    let woop = tetwalk::family::by_name::<Triangle>("woop-watertight").unwrap();
    let fused = &tetwalk::backend::CPU_FMA;
    let truth = Triangle::truth(&shrunk.case).unwrap();
    let a = Triangle::answers(fused, woop, &[shrunk.case]).unwrap()[0];
    assert!(Triangle::refutes_claim(&shrunk.case, &truth, &a));
}

fn tetwalk(args: &[&str]) -> (i32, String, String) {
    common::run_tetwalk(args, b"")
}

/// `tetwalk shrink FILE`: prints the shrunk case and a command that reproduces it, and leaves the file
/// as it was; `--in-place` writes it back with the original kept, and shrinking again keeps that
/// original.
#[test]
fn shrink_prints_a_reproducing_command_and_writes_only_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("maria17.json");
    std::fs::write(&file, format!("{MARIA17}\n")).unwrap();
    let path = file.to_str().unwrap();
    let (code, out, err) = tetwalk(&["shrink", path]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        format!("{MARIA17}\n")
    );
    assert!(err.contains("1 case shrunk"), "{err}");
    let reproduce = out
        .lines()
        .find_map(|l| l.trim().strip_prefix("reproduce: "))
        .expect("a reproducing command");
    // The command: `echo 'CASE' | tetwalk exit --method maria17 --backend cpu`.
    let case = reproduce.split('\'').nth(1).unwrap();
    assert!(reproduce.ends_with("| tetwalk exit --method maria17 --backend cpu"));
    let (_, verdict, _) = common::run_tetwalk(
        &["exit", "--method", "maria17", "--backend", "cpu"],
        case.as_bytes(),
    );
    let v: serde_json::Value = serde_json::from_str(verdict.trim()).unwrap();
    assert_eq!(v["correct"], false, "{verdict}");

    let (code, _, err) = tetwalk(&["shrink", "--in-place", path]);
    assert_eq!(code, 0, "{err}");
    let written = Found::<ExitFace>::parse(std::fs::read_to_string(&file).unwrap().trim()).unwrap();
    let found = Found::<ExitFace>::parse(MARIA17).unwrap();
    assert_eq!(written.original, Some(found.case));
    assert_eq!(written.case_line(), case);
    let (code, _, err) = tetwalk(&["shrink", "--in-place", path]);
    assert_eq!(code, 0, "{err}");
    let again = Found::<ExitFace>::parse(std::fs::read_to_string(&file).unwrap().trim()).unwrap();
    assert_eq!(
        again.original,
        Some(found.case),
        "the original stays the case as found"
    );
}

/// `plucker`'s wrong rays on one 4×4 view of `kuhn-far`, dumped by `count --dump` into `dir`.
fn counts_dump(dir: &std::path::Path) -> std::path::PathBuf {
    let dump = dir.join("dump.jsonl");
    let (code, _, err) = tetwalk(&[
        "count",
        "--scene",
        "kuhn-far",
        "--views",
        "1",
        "--size",
        "4x4",
        "--methods",
        "plucker",
        "--dump",
        dump.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    dump
}

/// A count's dump: each wrong ray's diverging step is a one-tetrahedron case its method fails, which
/// `shrink` shrinks; a dump is never rewritten in place.
#[test]
fn shrink_takes_a_counts_dump_but_never_rewrites_it() {
    let dir = tempfile::tempdir().unwrap();
    let dump = counts_dump(dir.path());
    let dump = dump.to_str().unwrap();
    let lines = std::fs::read_to_string(dump).unwrap();
    assert!(!lines.is_empty() && lines.lines().all(|l| l.contains("\"case\":{\"tet\"")));
    let json = dir.path().join("shrunk.json");
    let (code, _, err) = tetwalk(&["shrink", dump, "--json", json.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let cases = report["cases"].as_array().unwrap();
    assert_eq!(cases.len(), lines.lines().count());
    for c in cases {
        let f = Found::<ExitFace>::parse(&c["shrunk"].to_string()).unwrap();
        assert_eq!(replay(&f).unwrap(), Replay::Holds);
        assert!(c["bits_after"].as_u64() < c["bits_before"].as_u64());
    }
    let (code, _, err) = tetwalk(&["shrink", "--in-place", dump]);
    assert_eq!(code, 2);
    assert!(err.contains("not rewritten"), "{err}");
    assert_eq!(std::fs::read_to_string(dump).unwrap(), lines);
}

/// A dump line that is not a wrong ray as `count --dump` writes it is an error naming its line, and
/// nothing is shrunk; a wrong ray whose diverging step was not observed (a GPU walk's) is left as it
/// is with its reason, and a run that shrank nothing reports no mean of bits.
#[test]
fn shrink_refuses_a_malformed_dump_line_and_says_why_a_ray_is_left() {
    let dir = tempfile::tempdir().unwrap();
    let dump = counts_dump(dir.path());
    let first = std::fs::read_to_string(&dump).unwrap();
    let ray: serde_json::Value = serde_json::from_str(first.lines().next().unwrap()).unwrap();
    let edited = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut r = ray.clone();
        edit(&mut r);
        let f = dir.path().join("edited.jsonl");
        std::fs::write(&f, format!("{r}\n")).unwrap();
        tetwalk(&["shrink", f.to_str().unwrap()])
    };
    let (code, out, err) = edited(&|r| r["steps"] = "x".into());
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("line 1: wrong ray:"), "{err}");
    assert!(out.is_empty(), "{out}");
    let (code, _, err) = edited(&|r| {
        r.as_object_mut().unwrap().remove("case");
        r["divergence"] = serde_json::Value::Null;
    });
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("left as it is: no diverging step was observed"),
        "{err}"
    );
    assert!(
        err.contains("1 left as they were") && !err.contains("mean"),
        "{err}"
    );
}

/// An answerer speaking the protocol (docs/answerers.md) in a shell loop: for each case line, `say`
/// run with `$n` its line number.
fn answering_with(say: &str) -> String {
    format!(
        r#"while IFS= read -r l; do [ -z "$l" ] && continue; n=${{l##*\"line\":}}; n=${{n%%[!0-9]*}}; {say}; done"#
    )
}

/// An answerer answering every case with `fields` (JSON), by its line number.
fn answering(fields: &str) -> String {
    answering_with(&format!(
        r#"echo "{{\"line\": $n, {}}}""#,
        fields.replace('"', "\\\"")
    ))
}

/// `shrink --answerer CMD` shrinks for a program outside tetwalk: here one that answers every case
/// with a miss; the shrunk case is still one it answers wrongly the same way, and the printed line
/// reproduces it (run as printed, `tetwalk` on the path: the program asked, its answer judged
/// wrong).
#[test]
fn shrink_shrinks_for_a_program_outside_tetwalk() {
    let (_, cases, _) = tetwalk(&["gen-cases", "--shape", "octahedron", "--count", "1"]);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("case.jsonl");
    std::fs::write(&file, &cases).unwrap();
    let miss = &answering(r#""tri": null"#);
    let (code, out, err) = tetwalk(&[
        "shrink",
        "--answerer",
        miss,
        "--checks",
        "200",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("on outside"), "{out}");
    let reproduce = out
        .lines()
        .find_map(|l| l.trim().strip_prefix("reproduce: "))
        .expect("a reproducing command");
    assert!(
        reproduce.contains("| tetwalk hit --answerer"),
        "{reproduce}"
    );
    let bin = std::path::Path::new(env!("CARGO_BIN_EXE_tetwalk"));
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let run = std::process::Command::new("sh")
        .args(["-c", reproduce])
        .env("PATH", path)
        .output()
        .unwrap();
    let verdict = String::from_utf8_lossy(&run.stdout);
    assert!(verdict.contains("\"correct\":false"), "{verdict}");
    let (code, _, err) = tetwalk(&[
        "shrink",
        "--answerer",
        miss,
        "--in-place",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--in-place"), "{err}");
}

/// An answerer that never answers is stopped at `--answerer-seconds`, with everything it started (no
/// process of it is left running), and the shrink fails saying so; SIGTERM to tetwalk ends a running
/// answerer's processes too.
#[test]
fn an_answerer_that_hangs_is_stopped_with_everything_it_started() {
    let (_, cases, _) = tetwalk(&["gen-cases", "--shape", "octahedron", "--count", "1"]);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("case.jsonl");
    std::fs::write(&file, &cases).unwrap();
    let marker = dir.path().join("alive");
    // The answerer starts a background process that keeps a file fresh, then hangs itself.
    let hang = format!(
        "(while true; do touch {0}; sleep 0.05; done) & sleep 1000",
        marker.display()
    );
    let start = std::time::Instant::now();
    let (code, _, err) = tetwalk(&[
        "shrink",
        "--answerer",
        &hang,
        "--answerer-seconds",
        "1",
        file.to_str().unwrap(),
    ]);
    assert!(start.elapsed().as_secs() < 30, "{:?}", start.elapsed());
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("time limit"), "{err}");
    let still_touched = |m: &std::path::Path| {
        let before = std::fs::metadata(m).and_then(|x| x.modified()).ok();
        std::thread::sleep(std::time::Duration::from_millis(400));
        let after = std::fs::metadata(m).and_then(|x| x.modified()).ok();
        before != after
    };
    assert!(
        !still_touched(&marker),
        "the answerer's background process runs on"
    );
    // Interrupted while the answerer runs.
    let marker2 = dir.path().join("alive2");
    let hang2 = format!(
        "(while true; do touch {0}; sleep 0.05; done) & sleep 1000",
        marker2.display()
    );
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(["shrink", "--answerer", &hang2, file.to_str().unwrap()])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    while !marker2.exists() {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    // SAFETY: kill sends SIGTERM to the child tetwalk.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    assert!(
        !still_touched(&marker2),
        "SIGTERM left the answerer's processes running"
    );
}

/// An answerer is read as strictly as `judge` reads answers: two lines for one case, an answer for
/// another line, or one without its line number are refused, naming why, so that the reproducing line
/// printed for a shrink always works in `judge`.
#[test]
fn an_answerer_is_read_as_judge_reads_answers() {
    let (_, cases, _) = tetwalk(&["gen-cases", "--shape", "octahedron", "--count", "1"]);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("case.jsonl");
    std::fs::write(&file, &cases).unwrap();
    let twice = format!("{0}; {0}", r#"echo "{\"line\": $n, \"tri\": null}""#);
    for (answerer, says) in [
        (answering_with(&twice), "a second answer for line 1"),
        (
            answering_with(r#"echo "{\"line\": $((n + 1)), \"tri\": null}""#),
            "for line 2, which is not in the batch",
        ),
        (
            answering_with(r#"echo '{"tri": null}'"#),
            "without \"line\"",
        ),
    ] {
        let answerer = answerer.as_str();
        let (code, _, err) = tetwalk(&["shrink", "--answerer", answerer, file.to_str().unwrap()]);
        assert_eq!(code, 2, "{answerer}: {err}");
        assert!(err.contains(says), "{answerer}: {err}");
        // judge refuses the same answers.
        let answers = dir.path().join("a.jsonl");
        let mut asked: serde_json::Value = serde_json::from_str(cases.trim()).unwrap();
        asked["line"] = 1.into();
        let mut run = std::process::Command::new("sh")
            .args(["-c", answerer])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        use std::io::Write;
        writeln!(run.stdin.take().unwrap(), "{asked}\n").unwrap();
        let text = run.wait_with_output().unwrap().stdout;
        std::fs::write(&answers, text).unwrap();
        let (code, _, _) = tetwalk(&["judge", file.to_str().unwrap(), answers.to_str().unwrap()]);
        assert_ne!(code, 0, "{answerer}: judge accepted it");
    }
}

/// A shrunk case keeps its failure as clear as found: for a program answering face 0 to everything,
/// failures deep in other faces shrink to cases with the same exact exit face (judged here by the
/// oracle), the same answer, and at least half the original's clearance (the exit point's least
/// barycentric coordinate), fewer bits in all, as `shrink --json` reports.
#[test]
fn a_shrunk_case_stays_as_deep_in_its_face_as_the_one_found() {
    let (_, cases, _) = tetwalk(&["gen-cases", "--row", "well", "--count", "40"]);
    let dir = tempfile::tempdir().unwrap();
    let deep: Vec<&str> = cases
        .lines()
        .filter(|l| {
            let c = tetwalk::engine::found::Found::<tetwalk::family::ExitFace>::parse(l)
                .unwrap()
                .case;
            !tetwalk::cases::classify(&c).unwrap().exit.contains(0)
        })
        .take(6)
        .collect();
    assert_eq!(deep.len(), 6);
    let file = dir.path().join("cases.jsonl");
    std::fs::write(&file, deep.join("\n") + "\n").unwrap();
    let json = dir.path().join("shrunk.json");
    let (code, _, err) = tetwalk(&[
        "shrink",
        "--answerer",
        &answering(r#""face": 0"#),
        "--checks",
        "2000",
        file.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let shrunk = report["cases"].as_array().unwrap();
    assert_eq!(shrunk.len(), 6, "{report}");
    for (d, line) in shrunk.iter().zip(&deep) {
        let f = |k: &str| d[k].as_f64().unwrap();
        assert!(f("clearance_before") > 0.0, "{d}");
        assert!(f("clearance_after") >= f("clearance_before") / 2.0, "{d}");
        assert!(f("bits_after") < f("bits_before"), "{d}");
        let parse = |s: &str| {
            let c = tetwalk::engine::found::Found::<tetwalk::family::ExitFace>::parse(s)
                .unwrap()
                .case;
            tetwalk::cases::classify(&c).unwrap().exit
        };
        assert_eq!(parse(&d["shrunk"].to_string()), parse(line), "{d}");
    }
}
