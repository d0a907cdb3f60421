//! The command line as a user runs it.

use std::process::Command;

mod common;

fn tetwalk(args: &[&str], stdin: &str) -> (i32, String, String) {
    common::run_tetwalk(args, stdin.as_bytes())
}

fn json_lines(s: &str) -> Vec<serde_json::Value> {
    s.lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// Run `tetwalk ARGS --json FILE`: it must succeed and print `says`; the JSON it wrote.
fn json_run(args: &[&str], says: &str) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("report.json");
    let mut all = args.to_vec();
    all.extend(["--json", json.to_str().unwrap()]);
    let (code, out, err) = tetwalk(&all, "");
    assert_eq!(code, 0, "tetwalk {args:?}: {err}");
    assert!(out.contains(says), "tetwalk {args:?}: {out}");
    serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap()
}

/// A JSON array of counts.
fn counts(v: &serde_json::Value) -> Vec<u64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect()
}

const UNIT: &str = r#""tet": [[0,0,0],[0,1,0],[1,0,0],[0,0,1]]"#;

#[test]
fn exit_answers_each_case_with_each_method() {
    let input = format!(
        "{{{UNIT}, \"org\": [0.2,0.2,-1], \"dir\": [0,0,1], \"entry\": 3}}\n\n\
         {{{UNIT}, \"org\": [0.25,0.25,0.25], \"dir\": [-0.25,0.25,0.25], \"entry\": null}}\n\
         {{{UNIT}, \"org\": [5,5,5], \"dir\": [1,0,0]}}\n"
    );
    let (code, out, _) = tetwalk(&["exit", "--method", "all"], &input);
    assert_eq!(code, 0);
    let v = json_lines(&out);
    let methods = tetwalk::registry::METHODS.len();
    assert_eq!(v.len(), 3 * methods);
    assert!(
        v[..methods]
            .iter()
            .all(|x| x["line"] == 1 && x["exact_exit"] == serde_json::json!([0]))
    );
    assert!(
        v[..methods]
            .iter()
            .all(|x| x["exact_entry"] == serde_json::json!([3]) && x["correct"] == true)
    );
    // Line 2 was blank; line 3 goes exactly through edge v1 v3: faces 0 and 2 are both right.
    let through_edge = &v[methods..2 * methods];
    assert!(
        through_edge
            .iter()
            .all(|x| x["line"] == 3 && x["exact_exit"] == serde_json::json!([0, 2]))
    );
    let exact = through_edge
        .iter()
        .find(|x| x["method"] == "exact")
        .unwrap();
    assert_eq!(exact["correct"], true);
    // Line 4 misses: no exact faces, correct is null.
    assert!(
        v[2 * methods..]
            .iter()
            .all(|x| x["line"] == 4 && x["correct"].is_null())
    );
    assert!(
        v[2 * methods..]
            .iter()
            .all(|x| x["exact_exit"] == serde_json::json!([]))
    );
}

#[test]
fn bad_lines_get_errors_and_the_rest_are_answered() {
    let input = format!(
        "not json\n\
         {{\"tet\": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]], \"org\": [0,0,1], \"dir\": [0,0,1]}}\n\
         {{{UNIT}, \"org\": [0.2,0.2,-1], \"dir\": [0,0,1], \"entry\": 0}}\n\
         {{{UNIT}, \"org\": [0.2,0.2,-1], \"dir\": [0,0,0]}}\n\
         {{{UNIT}, \"org\": [0.2,0.2,1e39], \"dir\": [0,0,1]}}\n\
         {{{UNIT}, \"org\": [0.2,0.2,-1], \"dir\": [0,0,1], \"entry\": 7}}\n\
         {{{UNIT}, \"org\": [0.2,0.2,-1], \"dir\": [0,0,1]}}\n"
    );
    let (code, out, err) = tetwalk(&["exit", "--method", "maria17"], &input);
    assert_ne!(code, 0, "errors give a non-zero exit status");
    assert!(err.contains("6 lines"), "{err}");
    let v = json_lines(&out);
    assert_eq!(v.len(), 7);
    let expect = [
        "malformed JSON",
        "flat",
        "not an exact entry face",
        "direction is zero",
        "not finite",
        "entry: must be",
    ];
    for (i, e) in expect.iter().enumerate() {
        assert_eq!(v[i]["line"], i + 1);
        assert!(
            v[i]["error"].as_str().unwrap().contains(e),
            "line {}: {} lacks '{e}'",
            i + 1,
            v[i]["error"]
        );
    }
    assert_eq!(v[6]["face"], 0);
    assert_eq!(v[6]["correct"], true);
}

#[test]
fn negatively_oriented_cases_are_answered_in_their_own_numbering() {
    // The unit tetrahedron with vertices 0 and 1 swapped: faces 0 and 1 swap too.
    let input = r#"{"tet": [[0,1,0],[0,0,0],[1,0,0],[0,0,1]], "org": [0.2,0.2,-1], "dir": [0,0,1], "entry": 3}"#;
    let (code, out, _) = tetwalk(&["exit", "--method", "all"], input);
    assert_eq!(code, 0);
    for v in json_lines(&out) {
        assert_eq!(v["exact_exit"], serde_json::json!([1]));
        assert_eq!(v["face"], 1, "{v}");
    }
}

#[test]
fn decimal_numbers_round_once_to_the_nearest_f32() {
    // 1 + 2^-24 + 2^-60: just above the midpoint of two f32 values, so it rounds up; through f64 it
    // would first land on the midpoint and then round down to 1 (ties to even).
    let x = "1.00000005960464477625798673798840354720596";
    assert_eq!(
        x.parse::<f64>().unwrap() as f32,
        1.0,
        "the double rounding this test guards against"
    );
    let line = format!("{{{UNIT}, \"org\": [{x},0,0], \"dir\": [0,0,1]}}");
    let Ok(found) = tetwalk::engine::found::Found::<tetwalk::family::ExitFace>::parse(&line) else {
        panic!("{line} is a one-tetrahedron case");
    };
    let case = found.case;
    assert_eq!(case.org.x, 1.0f32.next_up());
}

#[test]
fn generated_cases_run_through_exit_and_methods_are_listed() {
    let (code, cases, _) = tetwalk(
        &[
            "gen-cases",
            "--tet-shape",
            "sliver",
            "--rays",
            "edge",
            "--count",
            "50",
            "--with-entry",
        ],
        "",
    );
    assert_eq!(code, 0);
    assert_eq!(cases.lines().count(), 50);
    let (code, out, _) = tetwalk(&["exit", "--method", "exact"], &cases);
    assert_eq!(code, 0);
    assert!(json_lines(&out).iter().all(|v| v["correct"] == true));
    let (code, out, _) = tetwalk(&["methods"], "");
    assert_eq!(code, 0);
    assert!(out.contains("maria17") && out.contains("exact"));
    assert!(out.contains("| portalez16-direction | octree |"), "{out}");
    let (code, _, err) = tetwalk(&["exit", "--method", "nope"], "");
    assert_eq!(code, 2);
    assert!(err.contains("unknown method 'nope'"), "{err}");
}

#[test]
fn walk_reports_a_table_with_exact_never_wrong() {
    let (code, out, _) = tetwalk(
        &["walk", "--mesh", "kuhn", "--size", "4", "--rays", "300"],
        "",
    );
    assert_eq!(code, 0);
    // "... (N tetrahedra), R rays, ..." then the table; rays starting outside the mesh are skipped.
    let rays: u32 = out
        .split(" rays,")
        .next()
        .unwrap()
        .rsplit(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(rays > 250, "{out}");
    let exact = out.lines().find(|l| l.starts_with("| exact |")).unwrap();
    let cols: Vec<&str> = exact.split('|').map(str::trim).collect();
    assert_eq!(&cols[4..9], &["0", "0", "0", "0", "0"], "{exact}");
    assert_eq!(
        cols[2].parse::<u32>().unwrap() + cols[3].parse::<u32>().unwrap(),
        rays
    );
}

#[test]
fn stress_is_deterministic_whatever_the_threads_and_exact_never_fails() {
    let dir = tempfile::tempdir().unwrap();
    let run = |threads: &str, name: &str| {
        let path = dir.path().join(name);
        let out = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
            .args([
                "stress",
                "--cases",
                "3000",
                "--json",
                path.to_str().unwrap(),
            ])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(out.status.success());
        let table = String::from_utf8(out.stdout).unwrap();
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        (table, json)
    };
    let (table, one) = run("1", "one.json");
    let (_, two) = run("2", "two.json");
    assert_eq!(one, two, "results must not depend on the thread count");
    let methods: Vec<&str> = one["methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_str().unwrap())
        .collect();
    assert_eq!(methods.len(), tetwalk::registry::METHODS.len());
    let exact = methods.iter().position(|&m| m == "exact").unwrap();
    let rows = one["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 11, "every family and ray kind is a row");
    let mut failures = 0;
    for r in rows {
        let t = &r["tallies"][exact];
        assert!(t["judged"].as_u64().unwrap() > 2500, "{r}");
        assert_eq!(
            (t["wrong_face"].as_u64(), t["no_exit_face"].as_u64()),
            (Some(0), Some(0)),
            "{r}"
        );
        failures += r["tallies"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t["wrong_face"].as_u64().unwrap())
            .sum::<u64>();
    }
    assert!(
        failures > 0,
        "the adversarial rows must make some f32 method fail"
    );
    assert!(table.contains("| through-vertex |"), "{table}");
}

#[test]
fn asking_for_a_gpu_that_is_not_there_fails_clearly() {
    let out = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args([
            "count",
            "--scene",
            "fan",
            "--views",
            "1",
            "--size",
            "8x8",
            "--backend",
            "gpu",
        ])
        .env("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no GPU adapter found named 'no-such-adapter-anywhere'"),
        "{err}"
    );
}

/// `bench` times every method on each backend over the same rays: every row walks every ray of the
/// views inside the mesh, CPU rows have no kernel time, and `certified` (whose walks equal `exact`'s
/// wherever it runs) traverses the same tetrahedra plain and fused.
#[test]
fn bench_times_each_method_on_each_backend_over_the_same_rays() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("bench.json");
    let (code, out, err) = tetwalk(
        &[
            "bench",
            "--scene",
            "kuhn",
            "--views",
            "3",
            "--size",
            "32x32",
            "--backend",
            "cpu,cpu-fma",
            "--methods",
            "maria17,certified,aman20",
            "--layouts",
            "--json",
            json.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("| certified | cells | cpu-fma |"), "{out}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let timed = r["views_timed"].as_u64().unwrap();
    assert!(timed >= 1);
    let rows = r["rows"].as_array().unwrap();
    // Three methods over the cells and aman20 over Tet32, Tet20 and Tet16, on both backends.
    assert_eq!(rows.len(), 12);
    for row in rows {
        assert_eq!(row["rays"].as_u64(), Some(timed * 32 * 32), "{row}");
        assert!(
            row["tetrahedra"].as_u64().unwrap() >= timed * 32 * 32,
            "{row}"
        );
        assert!(row["kernel_seconds"].is_null(), "{row}");
        assert!(row["seconds"].as_f64().unwrap() > 0.0, "{row}");
    }
    let steps = |backend: &str| {
        rows.iter()
            .find(|x| x["method"] == "certified" && x["backend"] == backend)
            .unwrap()["tetrahedra"]
            .as_u64()
    };
    assert_eq!(steps("cpu"), steps("cpu-fma"));
    // aman20 traverses the same tetrahedra over the cells and over each layout.
    let aman20: Vec<_> = rows
        .iter()
        .filter(|x| x["method"] == "aman20" && x["backend"] == "cpu")
        .map(|x| (x["layout"].as_str().unwrap(), x["tetrahedra"].as_u64()))
        .collect();
    assert_eq!(aman20.len(), 4, "{aman20:?}");
    assert!(aman20.iter().all(|a| a.1 == aman20[0].1), "{aman20:?}");
}

/// `stress --seconds` is a differential campaign: it files new failures as found cases (at most
/// `--keep` per method, row and kind), each of which replays with its recorded answer; a second
/// campaign files only cases not filed already.
#[test]
fn a_stress_campaign_files_new_failures_that_replay() {
    let dir = tempfile::tempdir().unwrap();
    let found = dir.path().join("found");
    let run = || {
        let (code, out, err) = tetwalk(
            &[
                "stress",
                "--seconds",
                "0",
                "--cases",
                "400",
                "--families",
                "near-edge,near-vertex",
                "--methods",
                "maria17",
                "--keep",
                "2",
                "--found",
                found.to_str().unwrap(),
            ],
            "",
        );
        assert_eq!(code, 0, "{err}");
        assert!(out.contains("new found cases filed"), "{out}");
        let mut files: Vec<_> = std::fs::read_dir(found.join("maria17"))
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .collect();
        files.sort();
        files
    };
    let first = run();
    assert!(!first.is_empty() && first.len() <= 4, "{first:?}");
    for f in &first {
        use tetwalk::engine::found::{Found, Replay, replay};
        let text = std::fs::read_to_string(f).unwrap();
        let holds = match Found::<tetwalk::family::ExitFace>::parse(text.trim()) {
            Ok(r) => replay(&r).unwrap(),
            Err(_) => {
                replay(&Found::<tetwalk::family::Walks>::parse(text.trim()).unwrap()).unwrap()
            }
        };
        assert_eq!(holds, Replay::Holds, "{f:?}");
    }
    let second = run();
    assert!(
        second.len() > first.len(),
        "the second campaign files new cases"
    );
    assert!(first.iter().all(|f| second.contains(f)));
}

/// `replay --found` replays found cases: every kept one fails again with its recorded answer (exit
/// status 0, "N of N"), and one whose recorded answer is changed is reported (exit status 1).
#[test]
fn replay_found_cases_says_whether_each_fails_again() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/found/maria17");
    let mut files: Vec<String> = std::fs::read_dir(root)
        .unwrap()
        .flatten()
        .map(|e| e.path().display().to_string())
        .filter(|p| !std::fs::read_to_string(p).unwrap().contains("\"adapter\""))
        .collect();
    files.sort();
    files.truncate(5);
    let mut args = vec!["replay", "--found"];
    args.extend(files.iter().map(String::as_str));
    let (code, _, err) = tetwalk(&args, "");
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains(&format!(
            "{} of {} found cases fail again",
            files.len(),
            files.len()
        )),
        "{err}"
    );
    let dir = tempfile::tempdir().unwrap();
    let changed = dir.path().join("changed.json");
    // A one-tetrahedron case among them, its recorded face changed.
    let Some(mut r) = files.iter().find_map(|f| {
        let text = std::fs::read_to_string(f).unwrap();
        tetwalk::engine::found::Found::<tetwalk::family::ExitFace>::parse(text.trim()).ok()
    }) else {
        panic!("maria17 has one-tetrahedron found cases among {files:?}");
    };
    let f = r.failure.as_mut().unwrap();
    f.answer = f.answer.map(|x| (x + 1) % 4);
    std::fs::write(&changed, r.to_json()).unwrap();
    let (code, out, err) = tetwalk(&["replay", "--found", changed.to_str().unwrap()], "");
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains("other answer") || out.contains("right now"),
        "{out}"
    );
}

/// `replay` answers a count's wrong rays again for every counted family (walks, an octree's cells,
/// the triangles in packets, whose answers come from the whole view): each fails again the same
/// way, each answer line naming its file and line; the three dumps replayed at once give every
/// line of each, in order; a recorded ending changed is reported (status 1); a ray edited by one
/// ulp, views and settings no count takes, and a line that records no count are refused, naming
/// the file and the line.
#[test]
fn replay_answers_every_familys_dumped_wrong_rays_again() {
    let dir = tempfile::tempdir().unwrap();
    let mut dumps = Vec::new();
    let runs: [&[&str]; 3] = [
        &[
            "--scene",
            "kuhn-far",
            "--views",
            "2",
            "--size",
            "16x16",
            "--methods",
            "plucker",
        ],
        &[
            "--family", "octree", "--scene", "kuhn-far", "--views", "2", "--size", "16x16",
        ],
        &["--family", "triangle", "--packet", "2"],
    ];
    for (k, run) in runs.iter().enumerate() {
        let dump = dir.path().join(format!("dump-{k}.jsonl"));
        let mut args = vec!["count"];
        args.extend(*run);
        args.extend(["--dump", dump.to_str().unwrap()]);
        let (code, _, err) = tetwalk(&args, "");
        assert_eq!(code, 0, "{args:?}: {err}");
        let text = std::fs::read_to_string(&dump).unwrap();
        let lines = json_lines(&text);
        assert!(!lines.is_empty(), "{args:?} finds wrong rays");
        let family = lines[0]["count"]["family"].as_str().unwrap().to_string();
        let (code, out, err) = tetwalk(&["replay", dump.to_str().unwrap()], "");
        assert_eq!(code, 0, "{family}: {err}");
        let n = lines.len();
        assert!(
            err.contains(&format!("{n} of {n} wrong rays fail again the same way")),
            "{family}: {err}"
        );
        let replayed = json_lines(&out);
        assert_eq!(replayed.len(), n);
        for (r, l) in replayed.iter().zip(&lines) {
            assert_eq!(r["same"], true, "{family}: {r}");
            assert_eq!(r["now"], l["stopped"]["outcome"], "{family}");
            assert_eq!(r["file"], dump.to_str().unwrap(), "{family}");
        }
        dumps.push((dump.clone(), replayed));
        // One line alone, with its recorded ending changed: it no longer fails the same way.
        let one = dir.path().join(format!("one-{k}.jsonl"));
        let mut changed = lines[0].clone();
        changed["stopped"]["outcome"] = serde_json::json!({"kind": "step_limit", "tet": 0});
        std::fs::write(&one, format!("{changed}\n")).unwrap();
        let (code, out, err) = tetwalk(&["replay", one.to_str().unwrap()], "");
        assert_eq!(code, 1, "{family}: {out}{err}");
        assert!(
            err.contains("0 of 1 wrong rays fail again the same way (1 changed"),
            "{err}"
        );
        // Refused: the ray one ulp off its pixel's, settings no count takes, no count recorded.
        let mut edited = lines[0].clone();
        let x = edited["dir"][0].as_f64().unwrap() as f32;
        edited["dir"][0] = serde_json::json!(x.next_up());
        let mut settings = lines[0].clone();
        settings["count"]["settings"] = serde_json::json!({"packet": "many"});
        let mut none = lines[0].clone();
        none.as_object_mut().unwrap().remove("count");
        // Views no count takes: placed one by one they would never end.
        let mut views = lines[0].clone();
        views["count"]["views"]["views"] = serde_json::json!(1u64 << 50);
        views["view"] = serde_json::json!((1u64 << 50) - 1);
        for (bad, says) in [
            (edited, "is not view"),
            (views, "more than a count takes"),
            (settings, "settings are not"),
            (none, "records no count"),
        ] {
            std::fs::write(&one, format!("{bad}\n")).unwrap();
            let (code, _, err) = tetwalk(&["replay", one.to_str().unwrap()], "");
            assert_eq!(code, 2, "{family} {says}: {err}");
            assert!(
                err.contains(&format!("{} line 1", one.display())) && err.contains(says),
                "{family}: {err}"
            );
        }
    }
    let mut args = vec!["replay"];
    args.extend(dumps.iter().map(|(d, _)| d.to_str().unwrap()));
    let (code, out, err) = tetwalk(&args, "");
    assert_eq!(code, 0, "{err}");
    let alone: Vec<serde_json::Value> = dumps.into_iter().flat_map(|(_, r)| r).collect();
    let n = alone.len();
    assert_eq!(
        json_lines(&out),
        alone,
        "each file's lines as replayed alone"
    );
    assert!(
        err.contains(&format!("{n} of {n} wrong rays fail again the same way")),
        "{err}"
    );
}

/// `walk --relabel all` walks under the 12 orientation-preserving relabellings: the own labelling's
/// wrong results and cycles are the main table's, `certified` is right under every one, and maria17's
/// cycles on the Kuhn grid depend on the labelling.
#[test]
fn walk_relabel_all_reports_each_methods_spread() {
    let r = json_run(
        &[
            "walk",
            "--mesh",
            "kuhn",
            "--size",
            "4",
            "--rays",
            "2000",
            "--methods",
            "maria17,certified",
            "--relabel",
            "all",
        ],
        "cycles, own",
    );
    let cycle = tetwalk::walk::OutcomeKind::Cycle.code() as usize;
    let rows = r["methods"].as_array().unwrap();
    for (m, x) in rows.iter().zip(r["relabellings"].as_array().unwrap()) {
        assert_eq!(m["method"], x["method"]);
        assert_eq!(m["wrong"], x["wrong"][0], "{m} {x}");
        assert_eq!(m["kinds"][cycle], x["cycles"][0], "{m} {x}");
        if m["method"] == "certified" {
            assert!(counts(&x["wrong"]).iter().all(|&w| w == 0), "{x}");
        } else {
            let c = counts(&x["cycles"]);
            assert!(
                c.iter().max() > c.iter().min(),
                "maria17's cycles depend on the labelling: {c:?}"
            );
        }
    }
    let (code, _, err) = tetwalk(&["walk", "--relabel", "all", "--layout", "tet20"], "");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--relabel") && err.contains("--layout"),
        "{err}"
    );
}

/// `count --relabel all` counts again under the 12 orientation-preserving relabellings: the own
/// labelling's column is the count itself, and the reference is right under every one.
#[test]
fn count_relabel_all_counts_under_every_labelling() {
    let r = json_run(
        &[
            "count",
            "--scene",
            "jitter",
            "--views",
            "2",
            "--size",
            "32x32",
            "--methods",
            "maria17,maria17-translated",
            "--relabel",
            "all",
        ],
        "under the 12 orientation-preserving relabellings",
    );
    let methods = r["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 3);
    for m in methods {
        let c = counts(&m["relabelled"]);
        assert_eq!(c.len(), 12);
        assert_eq!(c[0], m["wrong_total"].as_u64().unwrap(), "{m}");
        if m["method"] == "certified" {
            assert!(c.iter().all(|&w| w == 0), "{m}");
        }
    }
}

/// `stress --relabel all`: each row and method under the 12 relabellings of every case's tetrahedron;
/// the own labelling's column is the table's, and `exact` and `certified` are right under all 12.
#[test]
fn stress_relabel_all_reruns_every_row_under_every_labelling() {
    let r = json_run(
        &[
            "stress",
            "--cases",
            "600",
            "--families",
            "needle,near-edge",
            "--methods",
            "exact,maria17,certified",
            "--relabel",
            "all",
        ],
        "under the 12 orientation-preserving relabellings",
    );
    let relabelled = r["relabelled"].as_array().unwrap();
    assert_eq!(relabelled.len(), 2 * 3);
    for x in relabelled {
        let row = r["rows"]
            .as_array()
            .unwrap()
            .iter()
            .find(|y| y["row"] == x["row"])
            .unwrap();
        let t = row["tallies"]
            .as_array()
            .unwrap()
            .iter()
            .find(|t| t["method"] == x["method"])
            .unwrap();
        let own = t["wrong_face"].as_u64().unwrap() + t["no_exit_face"].as_u64().unwrap();
        assert_eq!(counts(&x["wrong"])[0], own, "{x}");
        if x["method"] != "maria17" {
            assert!(counts(&x["wrong"]).iter().all(|&w| w == 0), "{x}");
        }
    }
    let (code, _, err) = tetwalk(&["stress", "--relabel", "all", "--seconds", "1"], "");
    assert_eq!(code, 2, "{err}");
}

/// `tetwalk paper` writes the seeds' tables beside ours, whole: seed 000 Tables 3, 4 (one column per
/// backend) and 5, seed 003 Tables 1–4 (walks timed on the CPU, not on cpu-fma), seed 004 Figure 5,
/// seed 001 Tables 1 and 3 and its octree walk's count; the file holds what was printed, and a bad
/// backend writes nothing.
#[test]
fn paper_writes_the_seeds_tables_beside_ours() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("paper.md");
    let r = json_run(
        &[
            "paper",
            "--scene",
            "kuhn",
            "--backend",
            "cpu,cpu-fma",
            "--views",
            "8",
            "--side",
            "64",
            "--out",
            out.to_str().unwrap(),
        ],
        "## Seed 000 Table 5",
    );
    let text = std::fs::read_to_string(&out).unwrap();
    for title in [
        "## Seed 000 Table 3",
        "## Seed 000 Table 4",
        "## Seed 000 Table 5",
        "## Seed 003 Table 4",
        "## Seed 003 Tables 1–3",
        "| Tet-mesh-20 | aman20 over tet20 |",
        "## Seed 004 Figure 5",
        "## Seed 001 Tables 1 and 3",
        "## Seed 001: the octree walk",
        "| ours, cpu | ours, cpu-fma |",
    ] {
        assert!(text.contains(title), "{title} missing from\n{text}");
    }
    assert_eq!(r["counts"].as_array().unwrap().len(), 2);
    assert!(
        r["timings"]["table5_gpu"].as_array().unwrap().is_empty(),
        "no GPU"
    );
    let timed: Vec<_> = r["timings"]["speed"]["rows"]
        .as_array()
        .unwrap()
        .iter()
        .collect();
    assert!(!timed.is_empty());
    assert!(
        timed
            .iter()
            .all(|x| x["backend"] == "cpu" && x["rays"].as_u64() > Some(0)),
        "cpu-fma is not timed: {timed:?}"
    );
    let octrees = r["octrees"].as_array().unwrap();
    assert_eq!(octrees.len(), 2, "an octree count per backend");
    assert_eq!(octrees[1]["backend"], "cpu-fma");
    assert_eq!(octrees[0]["methods"].as_array().unwrap().len(), 2);
    assert!(r["scene_info"]["octree"]["leaves"].as_u64().unwrap() > 0);
    let maria17 = r["timings"]["table5"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["method"] == "maria17")
        .unwrap();
    assert!(maria17["ns_per_query"].as_f64().unwrap() > 0.0);
    let figure5 = r["timings"]["figure5"]["rows"].as_array().unwrap();
    let methods = tetwalk::registry::TRIANGLE_METHODS;
    let wide = methods.iter().filter(|m| m.wide.is_some()).count();
    assert_eq!(
        figure5.len(),
        (methods.len() + wide) * 4,
        "each method and each 4-wide version, packets of 1, 4, 16 and 64 rays"
    );
    assert_eq!(
        figure5.iter().filter(|x| x["wide"] == true).count(),
        wide * 4
    );
    let elsewhere = dir.path().join("nothing.md");
    let (code, _, err) = tetwalk(
        &[
            "paper",
            "--backend",
            "tpu",
            "--out",
            elsewhere.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("'tpu'"), "{err}");
    assert!(!elsewhere.exists(), "nothing half-written");
}

/// `tetwalk judge`: answers computed elsewhere, dumped one JSON line per case, get the verdict lines
/// tetwalk's own methods get — the same, field for field, as `exit` and `hit` write for a method that
/// answered the same; a case without an answer is an error line, an answer without a case an error.
#[test]
fn judge_gives_answers_from_anywhere_the_verdicts_of_exit_and_hit() {
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("cases.jsonl");
    let mut text = String::new();
    for line in tetwalk(
        &[
            "gen-cases",
            // The older name of --tet-shape, still read.
            "--family",
            "sliver",
            "--rays",
            "near-edge",
            "--count",
            "40",
        ],
        "",
    )
    .1
    .lines()
    .chain(
        tetwalk(
            &[
                "gen-cases",
                "--shape",
                "tetrahedron",
                "--aim",
                "edge",
                "--count",
                "20",
            ],
            "",
        )
        .1
        .lines(),
    ) {
        text += line;
        text.push('\n');
    }
    std::fs::write(&cases, &text).unwrap();
    // maria17's and mt's own answers, written out as a user's kernel would dump them.
    let exit = json_lines(
        &tetwalk(
            &["exit", "--method", "maria17", cases.to_str().unwrap()],
            "",
        )
        .1,
    );
    let hit = json_lines(&tetwalk(&["hit", "--method", "mt", cases.to_str().unwrap()], "").1);
    let mut answers = String::new();
    for v in exit.iter().filter(|v| v.get("face").is_some()) {
        answers += &format!(
            "{}\n",
            serde_json::json!({"line": v["line"], "face": v["face"]})
        );
    }
    for v in hit.iter().filter(|v| v.get("tri").is_some()) {
        answers += &format!(
            "{}\n",
            serde_json::json!({"line": v["line"], "tri": v["tri"], "t": v["t"]})
        );
    }
    let given = dir.path().join("answers.jsonl");
    std::fs::write(&given, &answers).unwrap();
    let (code, out, err) = tetwalk(
        &["judge", cases.to_str().unwrap(), given.to_str().unwrap()],
        "",
    );
    assert_eq!(code, 0, "{err}");
    let judged = json_lines(&out);
    assert_eq!(judged.len(), 60);
    let own = exit
        .iter()
        .filter(|v| v.get("face").is_some())
        .chain(hit.iter().filter(|v| v.get("tri").is_some()));
    for (mine, theirs) in judged.iter().zip(own) {
        let mut mine = mine.clone();
        let mut theirs = theirs.clone();
        for v in [&mut mine, &mut theirs] {
            let o = v.as_object_mut().unwrap();
            o.remove("method");
            o.remove("backend");
        }
        assert_eq!(mine, theirs);
    }
    // One answer fewer: that case is an error line; one for a line with no case: an error.
    let fewer: String = answers.lines().skip(1).map(|l| format!("{l}\n")).collect();
    std::fs::write(&given, &fewer).unwrap();
    let (code, out, _) = tetwalk(
        &["judge", cases.to_str().unwrap(), given.to_str().unwrap()],
        "",
    );
    assert_eq!(code, 1);
    assert!(out.contains("no answer for this line"), "{out}");
    std::fs::write(&given, answers.clone() + "{\"line\": 999, \"face\": 1}\n").unwrap();
    let (code, _, err) = tetwalk(
        &["judge", cases.to_str().unwrap(), given.to_str().unwrap()],
        "",
    );
    assert_eq!(code, 2);
    assert!(err.contains("answers for line 999, with no case"), "{err}");
    // Many lines with no case are named in runs, not one by one.
    let far: String = (101..=3000)
        .chain([3005])
        .map(|n| format!("{{\"line\": {n}, \"face\": 1}}\n"))
        .collect();
    std::fs::write(&given, answers + &far).unwrap();
    let (code, _, err) = tetwalk(
        &["judge", cases.to_str().unwrap(), given.to_str().unwrap()],
        "",
    );
    assert_eq!(code, 2);
    assert!(
        err.contains("answers for lines 101-3000 and 3005, with"),
        "{err}"
    );
    assert!(err.len() < 400, "{err}");
    // A missing answers file is named once.
    let missing = dir.path().join("missing.jsonl");
    let (code, _, err) = tetwalk(
        &["judge", cases.to_str().unwrap(), missing.to_str().unwrap()],
        "",
    );
    assert_eq!(code, 2);
    assert_eq!(err.matches("missing.jsonl").count(), 1, "{err}");
}

/// Every kind of picture writes the file `--out` names: predicate and leak maps a sheet of every
/// method's sheet (each titled, its panels titled, its legend drawn in), and each method's beside it.
#[test]
fn render_writes_the_out_file_for_every_kind() {
    let dir = tempfile::tempdir().unwrap();
    for (what, methods) in [
        ("predicate", "maria17,plucker"),
        ("leak", "mt,woop-watertight"),
    ] {
        let out = dir.path().join(format!("{what}.png"));
        let (code, _, err) = tetwalk(
            &[
                "render",
                what,
                "--size",
                "32",
                "--methods",
                methods,
                "--out",
                out.to_str().unwrap(),
            ],
            "",
        );
        assert_eq!(code, 0, "{err}");
        let sheet = std::fs::read(&out).unwrap();
        for m in methods.split(',') {
            let one = std::fs::read(dir.path().join(format!("{what}-{m}.png"))).unwrap();
            assert!(
                sheet.len() > one.len(),
                "{what}: the sheet holds every method's"
            );
        }
    }
}

/// Without a terminal (a CI log) a long run still shows it is alive: a progress line every
/// `TETWALK_PROGRESS_SECONDS` (here every step).
#[test]
fn progress_lines_go_to_a_log_when_there_is_no_terminal() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(["stress", "--cases", "50", "--rows", "well,sliver"])
        .env("TETWALK_PROGRESS_SECONDS", "0")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("tetwalk stress: cases: 100 of 100 (100%)"),
        "{err}"
    );
}

/// `exit`, `hit` and `box-exit` end with a line per method on standard error: cases, right, wrong,
/// not judged.
#[test]
fn answering_commands_end_with_a_summary_per_method() {
    let (_, cases, _) = tetwalk(
        &[
            "gen-cases",
            "--tet-shape",
            "needle",
            "--rays",
            "near-edge",
            "--count",
            "40",
        ],
        "",
    );
    let (code, _, err) = tetwalk(&["exit", "--method", "maria17,exact"], &cases);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("tetwalk exit: exact: 40 cases, 40 right, 0 wrong, 0 not judged"),
        "{err}"
    );
    assert!(err.contains("tetwalk exit: maria17: 40 cases, "), "{err}");
}

/// `gen-cases` writes one family's cases: a flag of one family given with a flag of another is
/// refused, the error naming both, and nothing is written — `--single` (ray–triangle) beside
/// `--rays` (exit faces), `--cell-place` (octree) beside `--row`, `--shape` beside `--cell-aim`.
#[test]
fn gen_cases_refuses_two_families_flags_together() {
    for (args, both) in [
        (&["--single", "--rays", "edge"][..], ["--single", "--rays"]),
        (
            &["--cell-place", "far", "--row", "well"][..],
            ["--cell-place", "--row"],
        ),
        (
            &["--shape", "octahedron", "--cell-aim", "edge"][..],
            ["--shape", "--cell-aim"],
        ),
    ] {
        let mut all = vec!["gen-cases", "--count", "5"];
        all.extend(args);
        let (code, out, err) = tetwalk(&all, "");
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?} wrote {out}");
        assert!(err.contains("cannot be used with"), "{args:?}: {err}");
        for flag in both {
            assert!(err.contains(flag), "{args:?}: {err}");
        }
    }
}

/// `gen-cases` with a stress row's arguments writes that row's cases: `hit`, `box-exit` and `exit`
/// count on them exactly what `stress` counts; `--single` writes the triangle each ray first crosses, alone.
#[test]
fn gen_cases_writes_a_stress_rows_cases() {
    let (_, tris, _) = tetwalk(
        &[
            "gen-cases",
            "--shape",
            "tetrahedron",
            "--aim",
            "edge",
            "--place",
            "far",
            "--count",
            "300",
        ],
        "",
    );
    let dir = tempfile::tempdir().unwrap();
    let hit = dir.path().join("hit.json");
    let (code, _, err) = tetwalk(
        &["hit", "--method", "mt", "--json", hit.to_str().unwrap()],
        &tris,
    );
    assert_eq!(code, 0, "{err}");
    let hit: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&hit).unwrap()).unwrap();
    let stress = json_run(
        &[
            "stress",
            "--family",
            "triangle",
            "--shapes",
            "tetrahedron",
            "--aims",
            "edge",
            "--places",
            "far",
            "--cases",
            "300",
            "--methods",
            "mt",
        ],
        "tetrahedron",
    );
    assert_eq!(
        hit["methods"][0]["leaks"],
        stress["rows"][0]["tallies"][0]["leaks"]
    );
    assert!(hit["methods"][0]["leaks"].as_u64().unwrap() > 0);
    // Each wrong triangle has one kind, by the stress rows' rules: they add up to the row's wrong
    // first hits, the leaks among them to its leaks.
    let kinds = hit["methods"][0]["kinds"].as_object().unwrap();
    let tally = &stress["rows"][0]["tallies"][0];
    assert_eq!(kinds.get("leak"), tally.get("leaks"), "{kinds:?}");
    assert_eq!(
        kinds.values().map(|n| n.as_u64().unwrap()).sum::<u64>(),
        tally["wrong_first_hits"].as_u64().unwrap(),
        "{kinds:?}"
    );

    let (_, cells, _) = tetwalk(
        &[
            "gen-cases",
            "--cell-aim",
            "corner",
            "--cell-place",
            "far",
            "--count",
            "200",
        ],
        "",
    );
    let boxes = dir.path().join("box.json");
    tetwalk(
        &[
            "box-exit",
            "--method",
            "portalez16",
            "--json",
            boxes.to_str().unwrap(),
        ],
        &cells,
    );
    let boxes: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&boxes).unwrap()).unwrap();
    let stress = json_run(
        &[
            "stress",
            "--family",
            "octree",
            "--cell-aims",
            "corner",
            "--cell-places",
            "far",
            "--cases",
            "200",
            "--methods",
            "portalez16",
        ],
        "corner",
    );
    assert_eq!(
        boxes["methods"][0]["wrong"],
        stress["rows"][0]["tallies"][0]["wrong"]
    );
    assert!(boxes["methods"][0]["wrong"].as_u64().unwrap() > 0);

    let (_, tets, _) = tetwalk(&["gen-cases", "--row", "near-vertex", "--count", "300"], "");
    let exit = dir.path().join("exit.json");
    tetwalk(
        &[
            "exit",
            "--method",
            "maria17",
            "--json",
            exit.to_str().unwrap(),
        ],
        &tets,
    );
    let exit: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&exit).unwrap()).unwrap();
    let stress = json_run(
        &[
            "stress",
            "--rows",
            "near-vertex",
            "--cases",
            "300",
            "--methods",
            "maria17",
        ],
        "near-vertex",
    );
    let tally = &stress["rows"][0]["tallies"][0];
    assert_eq!(
        exit["methods"][0]["wrong"].as_u64(),
        Some(tally["wrong_face"].as_u64().unwrap() + tally["no_exit_face"].as_u64().unwrap())
    );
    assert!(exit["methods"][0]["wrong"].as_u64().unwrap() > 0);

    let (_, single, _) = tetwalk(
        &[
            "gen-cases",
            "--shape",
            "octahedron",
            "--aim",
            "vertex",
            "--single",
            "--count",
            "20",
        ],
        "",
    );
    // Of the row's first 20 cases, those whose ray crosses the mesh.
    assert!((15..=20).contains(&single.lines().count()), "{single}");
    assert!(single.lines().all(|l| l.starts_with("{\"tri\":")));
    let (code, _, err) = tetwalk(&["hit", "--method", "woop-watertight"], &single);
    assert_eq!(code, 0, "{err}");
}

/// `paper` prints its tables and writes a file only where `--out` names one: the repository's
/// record is never written unasked.
#[test]
fn paper_writes_only_where_asked() {
    let record = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/results/paper.md");
    let before = std::fs::read(record).unwrap();
    let (code, out, err) = tetwalk(
        &[
            "paper",
            "--scene",
            "kuhn",
            "--backend",
            "cpu",
            "--views",
            "2",
            "--side",
            "16",
        ],
        "",
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("## Seed 000 Table 4"), "{out}");
    assert_eq!(std::fs::read(record).unwrap(), before);
}

/// `bench` takes samples (each batch, `--repeat` times) and gives each row's median and range, and
/// compares them with an earlier run's of the same settings (`--baseline`), batch by batch.
#[test]
fn bench_gives_medians_of_samples_and_compares_with_a_baseline() {
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first.json");
    let args = |json: &str| {
        vec![
            "bench".to_string(),
            "--scene".into(),
            "kuhn".into(),
            "--views".into(),
            "2".into(),
            "--size".into(),
            "32x32".into(),
            "--batch".into(),
            "1024".into(),
            "--methods".into(),
            "maria17".into(),
            "--repeat".into(),
            "2".into(),
            "--json".into(),
            json.into(),
        ]
    };
    let run = |a: Vec<String>| {
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        tetwalk(&a, "")
    };
    let (code, _, err) = run(args(first.to_str().unwrap()));
    assert_eq!(code, 0, "{err}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&first).unwrap()).unwrap();
    let row = &r["rows"][0];
    assert_eq!(
        row["samples"].as_array().unwrap().len(),
        4,
        "2 batches, each timed twice"
    );
    assert!(row["spread"]["low"].as_f64() <= row["spread"]["median"].as_f64());
    let second = dir.path().join("second.json");
    let mut a = args(second.to_str().unwrap());
    a.extend(["--baseline".to_string(), first.display().to_string()]);
    let (code, out, err) = run(a);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("vs baseline"), "{out}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&second).unwrap()).unwrap();
    let verdict = r["rows"][0]["change"]["verdict"].as_str().unwrap();
    assert!(
        ["faster", "slower", "within noise"].contains(&verdict),
        "{verdict}"
    );
    // Like with like: a baseline whose every batch ran a hundred times as fast reads "slower", batch
    // by batch, however far apart the views' own speeds lie (and however busy this machine is).
    let mut fast: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&first).unwrap()).unwrap();
    for row in fast["rows"].as_array_mut().unwrap() {
        for x in row["samples"].as_array_mut().unwrap() {
            *x = serde_json::json!(x.as_f64().unwrap() * 100.0);
        }
        for k in ["median", "low", "high"] {
            row["spread"][k] = serde_json::json!(row["spread"][k].as_f64().unwrap() * 100.0);
        }
    }
    let fast_file = dir.path().join("fast.json");
    std::fs::write(&fast_file, fast.to_string()).unwrap();
    let mut a = args(second.to_str().unwrap());
    a.extend(["--baseline".to_string(), fast_file.display().to_string()]);
    let (code, _, err) = run(a);
    assert_eq!(code, 0, "{err}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&second).unwrap()).unwrap();
    assert_eq!(
        r["rows"][0]["change"]["verdict"], "slower",
        "{}",
        r["rows"][0]
    );
    // A baseline of other settings, or without one of this run's rows, is refused.
    let mut a = args(second.to_str().unwrap());
    a[6] = "16x16".into();
    a.extend(["--baseline".to_string(), first.display().to_string()]);
    let (code, _, err) = run(a);
    assert_eq!(code, 2);
    assert!(
        err.contains("other settings") && err.contains("views"),
        "{err}"
    );
    let mut a = args(second.to_str().unwrap());
    a[10] = "plucker".into();
    a.extend(["--baseline".to_string(), first.display().to_string()]);
    let (code, _, err) = run(a);
    assert_eq!(code, 2);
    assert!(err.contains("none of its rows"), "{err}");
}

/// `fuzz-import` files a finding as a stress campaign does, by the hash of the case as found: the
/// same case from two artifacts is filed once, under `<method>/<target>-<kind>-<hash>.json`, shrunk,
/// its case as found kept in `original`; an unknown `TETWALK_FUZZ_METHOD` names what it may be.
#[test]
fn fuzz_import_files_a_case_once_by_the_hash_of_it_as_found() {
    let dir = tempfile::tempdir().unwrap();
    let case = r#"{"tet":[[0.4583335,1.9583334,6.208334],[10.0,-7.75,15.5],[-6.5,15.5,-8.75],[-15.75,-11.0,-16.0]],"org":[-64.0,-64.0,-64.0],"dir":[64.458336,65.958336,70.208336],"entry":2}"#;
    let (a, b) = (
        dir.path().join("crash-1.json"),
        dir.path().join("crash-2.json"),
    );
    std::fs::write(&a, case).unwrap();
    std::fs::write(&b, case).unwrap();
    let out = dir.path().join("found");
    let args = [
        "fuzz-import",
        "--target",
        "exit_face",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let env = [("TETWALK_FUZZ_METHOD", "maria17")];
    let (code, printed, err) = common::run_tetwalk_env(&args, b"", &env);
    assert_eq!(code, 0, "{err}");
    let filed: Vec<_> = std::fs::read_dir(out.join("maria17"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(filed.len(), 1, "{filed:?}\n{printed}");
    assert_eq!(
        printed.matches("maria17 wrong face").count(),
        1,
        "{printed}"
    );
    let name = &filed[0];
    let hash = name
        .strip_prefix("exit_face-wrong_face-")
        .and_then(|n| n.strip_suffix(".json"))
        .unwrap_or_else(|| panic!("{name}"));
    assert!(
        hash.len() == 16 && hash.chars().all(|c| c.is_ascii_hexdigit()),
        "{name}"
    );
    let line: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("maria17").join(name)).unwrap())
            .unwrap();
    let as_found: serde_json::Value = serde_json::from_str(case).unwrap();
    assert_eq!(line["original"], as_found);
    assert_eq!(line["method"], "maria17");
    let env = [("TETWALK_FUZZ_METHOD", "all")];
    let (code, _, err) = common::run_tetwalk_env(&args, b"", &env);
    assert_eq!(code, 2);
    assert!(
        err.contains("or `robust`") && !err.contains("certified, or all"),
        "{err}"
    );
}
