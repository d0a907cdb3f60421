//! The answerer protocol (docs/answerers.md): programs outside tetwalk — the C and numpy kernels of
//! `examples/kernels/`, and small shell and Python ones here — stressed, campaigned and shrunk through
//! it, within their contracts.

mod common;

use common::run_tetwalk;
use serde_json::Value;
use tetwalk::cases::classify;
use tetwalk::tet::{Case, FACE_VERTICES, orientation};

fn tetwalk(args: &[&str]) -> (i32, String, String) {
    run_tetwalk(args, b"")
}

/// The stress report `args` writes with `--json`.
fn stress(args: &[&str]) -> (Value, String) {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("r.json");
    let mut all = vec!["stress"];
    all.extend(args);
    all.extend(["--json", json.to_str().unwrap()]);
    let (code, _, err) = tetwalk(&all);
    assert_eq!(code, 0, "{args:?}: {err}");
    (
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap(),
        err,
    )
}

/// Every row's tally of the `k`-th judged (answerer or method), as written.
fn tallies(r: &Value, k: usize) -> Vec<Value> {
    r["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            let mut t = row["tallies"][k].clone();
            t.as_object_mut().unwrap().remove("method");
            t
        })
        .collect()
}

/// `judge`'s summary of `answers` (one line each) to `cases`, written in `dir`.
fn judged(dir: &std::path::Path, cases: &str, answers: &str) -> Value {
    let (c, a, j) = (dir.join("c.jsonl"), dir.join("a.jsonl"), dir.join("j.json"));
    std::fs::write(&c, cases).unwrap();
    std::fs::write(&a, answers).unwrap();
    tetwalk(&[
        "judge",
        c.to_str().unwrap(),
        a.to_str().unwrap(),
        "--json",
        j.to_str().unwrap(),
    ]);
    serde_json::from_str(&std::fs::read_to_string(&j).unwrap()).unwrap()
}

/// The C kernel (examples/kernels/c/plucker_eps.c) built here.
fn c_kernel(dir: &std::path::Path) -> String {
    let exe = dir.join("plucker_eps");
    let built = std::process::Command::new("cc")
        .args(["-O2", "-o"])
        .arg(&exe)
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/kernels/c/plucker_eps.c"
        ))
        .status()
        .expect("a C compiler, cc (.ci/setup installs it)");
    assert!(built.success());
    exe.to_str().unwrap().to_string()
}

/// The arguments that ask the C kernel `exe`, its face numbering given.
fn c_args(exe: &str) -> [&str; 6] {
    [
        "--answerer",
        exe,
        "--answerer-format",
        "binary",
        "--faces",
        "3,0,1,2",
    ]
}

/// A C kernel in binary records, numbering faces its own way: `--faces auto` finds its numbering
/// (face j opposite vertex j + 3), and the table is then the one the numbering given by hand makes;
/// the identity numbering makes nearly every well-shaped case wrong.
#[test]
fn a_c_kernel_in_binary_records_is_judged_with_its_numbering_found() {
    let dir = tempfile::tempdir().unwrap();
    let exe = c_kernel(dir.path());
    let base = [
        "--answerer",
        &exe,
        "--answerer-format",
        "binary",
        "--rows",
        "well,near-edge,near-vertex",
        "--cases",
        "3000",
    ];
    let with = |faces: &str| {
        let mut a = base.to_vec();
        a.extend(["--faces", faces]);
        stress(&a)
    };
    let (auto, err) = with("auto");
    assert!(err.contains("[3, 0, 1, 2]"), "{err}");
    let (given, _) = with("3,0,1,2");
    assert_eq!(tallies(&auto, 0), tallies(&given, 0));
    // Found on its well-shaped cases: right there, and wrong near edges (its epsilon).
    let wrong = |r: &Value, row: usize| {
        let t = &r["rows"][row]["tallies"][0];
        t["wrong_face"].as_u64().unwrap() + t["no_exit_face"].as_u64().unwrap()
    };
    assert_eq!(wrong(&auto, 0), 0);
    assert!(wrong(&auto, 1) > 100, "{auto}");
    let (identity, _) = with("0,1,2,3");
    assert!(wrong(&identity, 0) > 2000, "{identity}");
}

/// A Python kernel in numpy, reading binary records with one `frombuffer` a batch, answers as
/// tetwalk's own `ray-plane` does, case for case: the same table row for row. Needs numpy (`apt
/// install python3-numpy`; CI, with TETWALK_REQUIRE_NUMPY=1, fails without it).
#[test]
fn the_numpy_kernel_answers_as_tetwalks_ray_plane_does() {
    let has = std::process::Command::new("python3")
        .args(["-c", "import numpy"])
        .status()
        .is_ok_and(|s| s.success());
    if !has {
        assert!(
            std::env::var_os("TETWALK_REQUIRE_NUMPY").is_none(),
            "numpy is required here (TETWALK_REQUIRE_NUMPY) and is not installed"
        );
        eprintln!("SKIPPED the numpy kernel: python3 has no numpy here");
        return;
    }
    let py = concat!(
        "python3 ",
        env!("CARGO_MANIFEST_DIR"),
        "/examples/kernels/python/ray_plane.py"
    );
    let (r, _) = stress(&[
        "--answerer",
        py,
        "--answerer-format",
        "binary",
        "--answerer-batch",
        "777",
        "--methods",
        "ray-plane",
        "--cases",
        "3000",
    ]);
    assert_eq!(r["methods"], serde_json::json!(["answerer", "ray-plane"]));
    assert_eq!(tallies(&r, 0), tallies(&r, 1));
    let wrong: u64 = tallies(&r, 0)
        .iter()
        .map(|t| t["wrong_face"].as_u64().unwrap())
        .sum();
    assert!(wrong > 0);
}

/// An answerer that answers `face` to every case, in JSON Lines (Python, standard library only).
const FACE_ZERO: &str = r#"python3 -c '
import json, sys
for line in sys.stdin:
    if line.strip():
        print(json.dumps({"line": json.loads(line)["line"], "face": 0}))
    else:
        sys.stdout.flush()
'"#;

/// In JSON Lines, a stress row's verdicts are the ones `judge` gives the same answers to the same
/// cases (`gen-cases --row`); a program that runs past a batch's time limit, one that quits, and one
/// that answers a face that is none are errors naming why (one that reads nothing stopped at its time
/// limit, however large the batch); a campaign must be told where to file.
#[test]
fn an_answerer_in_json_lines_gets_the_verdicts_judge_gives() {
    let (r, _) = stress(&[
        "--answerer",
        FACE_ZERO,
        "--answerer-batch",
        "64",
        "--rows",
        "near-edge",
        "--cases",
        "500",
    ]);
    let t = &tallies(&r, 0)[0];
    let (_, cases, _) = tetwalk(&["gen-cases", "--row", "near-edge", "--count", "500"]);
    let dir = tempfile::tempdir().unwrap();
    let answers: String = (1..=500)
        .map(|n| format!("{{\"line\": {n}, \"face\": 0}}\n"))
        .collect();
    let judged = judged(dir.path(), &cases, &answers);
    assert_eq!(
        judged["methods"][0]["wrong"].as_u64(),
        Some(t["wrong_face"].as_u64().unwrap() + t["no_exit_face"].as_u64().unwrap())
    );
    for (cmd, cases, says) in [
        ("sleep 100", "10", "time limit"),
        // A program that never reads its input is stopped at the time limit, even when a batch is
        // more than a pipe holds (its writer, blocked, ends once the program is stopped).
        ("sleep 100000", "100000", "within its time limit of 2s"),
        // Its exit status is said, whether its exit or its output's end is seen first.
        (
            "exit 3",
            "10",
            "its output ended after 0 of a batch's 10 answers (lines 1 to 10); it exited with status 3",
        ),
        (
            r#"python3 -c 'import sys, json; [print(json.dumps({"line": json.loads(l)["line"], "face": 7}), flush=True) for l in sys.stdin if l.strip()]'"#,
            "10",
            "not 0..3",
        ),
    ] {
        let (code, _, err) = tetwalk(&[
            "stress",
            "--answerer",
            cmd,
            "--answerer-seconds",
            "2",
            "--rows",
            "well",
            "--cases",
            cases,
        ]);
        assert_eq!(code, 2, "{cmd}: {err}");
        assert!(err.contains(says), "{cmd}: {err}");
    }
    let (code, _, err) = tetwalk(&["stress", "--answerer", FACE_ZERO, "--seconds", "1"]);
    assert_eq!(code, 2);
    assert!(err.contains("--found"), "{err}");
    let (code, _, err) = tetwalk(&["stress", "--family", "walk", "--answerer", "cat"]);
    assert_eq!(code, 2);
    assert!(err.contains("count --answerer"), "{err}");
}

/// The side of face `f`'s plane `p` is on, as vertex `f` is (+1) or not (-1, 0): exactly.
fn side(t: &[glam::Vec3; 4], f: usize, p: glam::Vec3) -> i8 {
    let [a, b, c] = FACE_VERTICES[f].map(|i| t[i]);
    orientation(&[a, b, c, p]) * orientation(&[a, b, c, t[f]])
}

/// `gen-cases` under a contract writes only cases that hold it, checked here exactly and apart from
/// the code that made them: origin strictly inside, or strictly before every entry face; a unit
/// direction; the exact entry face given; both orientations when any is asked for.
#[test]
fn every_case_made_holds_its_contract() {
    for row in ["well", "needle", "near-edge", "through-vertex"] {
        for origin in ["inside", "before"] {
            let (code, out, err) = tetwalk(&[
                "gen-cases",
                "--row",
                row,
                "--count",
                "300",
                "--origin",
                origin,
                "--unit-direction",
                "--entry",
                "given",
                "--orientation",
                "any",
            ]);
            assert_eq!(code, 0, "{row} {origin}: {err}");
            let mut signs = [0; 2];
            for l in out.lines() {
                let c: Case = tetwalk::engine::found::Found::<tetwalk::family::ExitFace>::parse(l)
                    .unwrap()
                    .case;
                let x = classify(&c).unwrap();
                let e = c.entry.expect("an entry face given") as usize;
                assert!(x.entry.contains(e), "{l}");
                assert!((c.dir.as_dvec3().length() - 1.0).abs() < 1e-6, "{l}");
                match origin {
                    "inside" => assert!((0..4).all(|f| side(&c.tet, f, c.org) > 0), "{l}"),
                    _ => assert!(x.entry.iter().all(|f| side(&c.tet, f, c.org) < 0), "{l}"),
                }
                signs[(orientation(&c.tet) > 0) as usize] += 1;
            }
            assert_eq!(out.lines().count(), 300);
            assert!(signs[0] > 50 && signs[1] > 50, "{signs:?}");
            // The contract is recorded with what was generated.
            let dir = tempfile::tempdir().unwrap();
            let json = dir.path().join("g.json");
            let (code, _, _) = tetwalk(&[
                "gen-cases",
                "--row",
                row,
                "--count",
                "5",
                "--origin",
                origin,
                "--json",
                json.to_str().unwrap(),
            ]);
            assert_eq!(code, 0);
            let g: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
            assert_eq!(g["contract"]["origin"], origin);
        }
    }
}

/// A campaign files the answerer's failures under its name, found on `outside`; `shrink --answerer`
/// shrinks them inside the contract (the origin stays inside), and `replay` refuses them (status 2),
/// saying that they need the program.
#[test]
fn an_answerers_campaign_files_cases_that_shrink_inside_its_contract() {
    let dir = tempfile::tempdir().unwrap();
    let exe = c_kernel(dir.path());
    let found = dir.path().join("found");
    let mut kernel = c_args(&exe).to_vec();
    kernel.extend(["--answerer-name", "c-plucker", "--origin", "inside"]);
    let mut args = vec!["stress"];
    args.extend(&kernel);
    args.extend([
        "--rows",
        "near-vertex",
        "--cases",
        "2000",
        "--seconds",
        "0",
        "--keep",
        "2",
        "--found",
        found.to_str().unwrap(),
    ]);
    let (code, _, err) = tetwalk(&args);
    assert_eq!(code, 0, "{err}");
    let files: Vec<_> = std::fs::read_dir(found.join("c-plucker"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert!(!files.is_empty());
    for f in &files {
        let line = std::fs::read_to_string(f).unwrap();
        let v: Value = serde_json::from_str(&line).unwrap();
        assert_eq!(v["backend"], "outside");
        assert_eq!(v["method"], "c-plucker");
        let mut args = vec!["shrink"];
        args.extend(&kernel);
        args.push(f.to_str().unwrap());
        let (code, out, err) = tetwalk(&args);
        assert_eq!(code, 0, "{err}");
        let shrunk = out.lines().nth(1).unwrap().trim();
        let c = tetwalk::engine::found::Found::<tetwalk::family::ExitFace>::parse(shrunk)
            .unwrap()
            .case;
        assert!((0..4).all(|k| side(&c.tet, k, c.org) > 0), "{shrunk}");
    }
    let (code, out, err) = tetwalk(&["replay", "--found", files[0].to_str().unwrap()]);
    assert_eq!(code, 2, "{out} {err}");
    assert!(
        err.contains("found for c-plucker, a program outside tetwalk")
            && err.contains("--answerer"),
        "{err}"
    );
}

/// Nothing is claimed beyond what was judged: a contract that leaves no case is an error (not a
/// table of zeros, and not a claim that holds); an answerer's name is a plain name (its found cases
/// are filed under it); shards asked of different programs do not merge.
#[test]
fn nothing_is_claimed_beyond_what_was_judged() {
    let dir = tempfile::tempdir().unwrap();
    let exe = c_kernel(dir.path());
    let mut args = vec!["stress"];
    args.extend(c_args(&exe));
    args.extend([
        "--rows",
        "well",
        "--cases",
        "50",
        "--tolerance",
        "0.99",
        "--answerer-claims",
        "--fail-on",
        "claims",
    ]);
    let (code, out, err) = tetwalk(&args);
    assert_eq!(code, 2, "{out} {err}");
    assert!(err.contains("no case was judged"), "{err}");
    assert!(
        !out.contains("holds here") && !err.contains("holds here"),
        "{err}"
    );
    for name in ["../esc", "a/b", ".hidden", ""] {
        let (code, _, err) = tetwalk(&["stress", "--answerer", "cat", "--answerer-name", name]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains("not a plain name"), "{name}: {err}");
    }
    let shard = |i: &str, program: &str| {
        let json = dir.path().join(format!("shard{i}.json"));
        let (code, _, err) = tetwalk(&[
            "count",
            "--scene",
            "kuhn-far",
            "--views",
            "2",
            "--size",
            "8x8",
            "--shard",
            &format!("{i}/2"),
            "--answerer",
            program,
            "--answerer-format",
            "binary",
            "--faces",
            "3,0,1,2",
            "--json",
            json.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        json.to_str().unwrap().to_string()
    };
    // Another program line (the same kernel, started otherwise): shards asked of it do not merge.
    let other = format!("exec {exe}");
    let (a, b) = (shard("0", &exe), shard("1", &other));
    let (code, _, err) = tetwalk(&["count", "merge", &a, &b]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("answerer"), "{err}");
    let b = shard("1", &exe);
    let (code, _, err) = tetwalk(&["count", "merge", &a, &b]);
    assert_eq!(code, 0, "{err}");
}

/// `judge` tells the kinds of wrong answers to tetrahedra apart: no answer on every line of the
/// through-vertex row is wrong as no exit face, many of them at ties (the line leaves through a
/// vertex), each line saying which; a touch-only line is flagged; the summary of tetrahedron lines
/// carries no triangle fields, and a triangle line brings them.
#[test]
fn judge_names_the_kind_of_each_wrong_answer_to_a_tetrahedron() {
    let dir = tempfile::tempdir().unwrap();
    let (c, a, j) = (
        dir.path().join("c.jsonl"),
        dir.path().join("a.jsonl"),
        dir.path().join("j.json"),
    );
    let (_, cases, _) = tetwalk(&["gen-cases", "--row", "through-vertex", "--count", "200"]);
    // And a line that only touches an edge (faces 1 and 2 are right, exactly; face 0 is wrong).
    let touching =
        r#"{"tet":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],"org":[1,1,-1],"dir":[-1,-1,2],"entry":null}"#;
    std::fs::write(&c, format!("{cases}{touching}\n")).unwrap();
    let answers: String = (1..=200)
        .map(|n| format!("{{\"line\": {n}, \"face\": null}}\n"))
        .chain(["{\"line\": 201, \"face\": 0}\n".to_string()])
        .collect();
    std::fs::write(&a, answers).unwrap();
    let (_, out, err) = tetwalk(&[
        "judge",
        c.to_str().unwrap(),
        a.to_str().unwrap(),
        "--json",
        j.to_str().unwrap(),
    ]);
    let lines: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert!(lines[..200].iter().all(|l| l["verdict"] == "no_exit_face"));
    let ties = lines[..200].iter().filter(|l| l["tie"] == true).count();
    assert!(ties > 50, "{ties}");
    assert_eq!(lines[200]["touch_only"], true, "{}", lines[200]);
    let t = &serde_json::from_str::<Value>(&std::fs::read_to_string(&j).unwrap()).unwrap()["methods"]
        [0];
    assert_eq!(t["no_exit_face"], 200, "{t}");
    assert_eq!(lines[200]["verdict"], "wrong_face");
    assert_eq!(t["wrong_at_tie"].as_u64(), Some(ties as u64 + 1));
    assert_eq!(t["touch_only"], 1, "{t}");
    assert!(
        t.get("leaks").is_none() && t.get("t_alone").is_none(),
        "{t}"
    );
    assert!(err.contains("no face"), "{err}");
    let (_, tri, _) = tetwalk(&["gen-cases", "--shape", "octahedron", "--count", "1"]);
    let answers: String = (1..=200)
        .map(|n| format!("{{\"line\": {n}, \"face\": null}}\n"))
        .chain(["{\"line\": 201, \"tri\": null}\n".to_string()])
        .collect();
    let t = &judged(dir.path(), &format!("{cases}{tri}"), &answers)["methods"][0];
    assert!(
        t.get("leaks").is_some() && t.get("no_exit_face").is_some(),
        "{t}"
    );
}

/// `--offset` moves every case of every exit-face row, in `stress` and `gen-cases` alike: the cases
/// `gen-cases --row R --offset X` writes, answered by `exit`, are wrong as often as `stress --rows R
/// --offset X` counts; and the mm-offset row (meshes in millimetres, 10 to 1,000 from the origin)
/// already shows f32 Plücker failing.
#[test]
fn an_offset_moves_every_rows_cases() {
    for row in ["mm-offset", "near-edge"] {
        let (code, cases, err) = tetwalk(&[
            "gen-cases",
            "--row",
            row,
            "--offset",
            "300",
            "--count",
            "400",
        ]);
        assert_eq!(code, 0, "{err}");
        // Each one of the row's own cases, moved 300 along (1, 1, 1) (a case whose line the move's
        // rounding takes off the tetrahedron, or past it, is replaced by a later one: the row's
        // own taken twice as far).
        let (_, own, _) = tetwalk(&["gen-cases", "--row", row, "--count", "800"]);
        let parse = |l: &str| {
            tetwalk::engine::found::Found::<tetwalk::family::ExitFace>::parse(l)
                .unwrap()
                .case
        };
        let own: Vec<_> = own.lines().map(parse).collect();
        let moved = |c: &tetwalk::tet::Case, o: &tetwalk::tet::Case| {
            c.tet.iter().zip(&o.tet).all(|(v, w)| {
                let moved = (*v - *w).as_dvec3() - glam::DVec3::splat(300.0 / 3f64.sqrt());
                // Each coordinate rounded once, to within half an ulp of the moved one.
                let ulp = (v.abs().max_element() as f64 * f32::EPSILON as f64).max(1e-4);
                moved.abs().max_element() <= ulp
            })
        };
        let mut from = 0;
        for l in cases.lines() {
            let c = parse(l);
            let at = own[from..]
                .iter()
                .position(|o| moved(&c, o))
                .unwrap_or_else(|| panic!("{l}: no case of the row's own, moved"));
            from += at + 1;
        }
        let dir = tempfile::tempdir().unwrap();
        let json = dir.path().join("e.json");
        let (_, _, _) = run_tetwalk(
            &[
                "exit",
                "--method",
                "plucker",
                "--json",
                json.to_str().unwrap(),
            ],
            cases.as_bytes(),
        );
        let exit: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        let (r, _) = stress(&[
            "--rows",
            row,
            "--offset",
            "300",
            "--cases",
            "400",
            "--methods",
            "plucker",
        ]);
        let t = &tallies(&r, 0)[0];
        let wrong = t["wrong_face"].as_u64().unwrap() + t["no_exit_face"].as_u64().unwrap();
        assert_eq!(exit["methods"][0]["wrong"].as_u64(), Some(wrong), "{row}");
        assert!(wrong > 0, "{row}");
    }
}

/// `--tolerance` leaves out the lines a kernel's epsilon allows it: no line exactly through an edge
/// can be asked within a tolerance, so that row refuses to be written; well-shaped lines can; and the
/// needle row, refilled to its count with lines farther than 10^-3 from every edge, blames the C
/// kernel's epsilon far less often.
#[test]
fn a_tolerance_leaves_out_the_lines_it_allows() {
    let (code, _, err) = tetwalk(&[
        "gen-cases",
        "--row",
        "through-edge",
        "--count",
        "50",
        "--tolerance",
        "0.001",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("within the contract"), "{err}");
    let (code, out, err) = tetwalk(&[
        "gen-cases",
        "--row",
        "well",
        "--count",
        "50",
        "--tolerance",
        "0.001",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 50);
    let dir = tempfile::tempdir().unwrap();
    let exe = c_kernel(dir.path());
    let row = |tolerance: &str| {
        let mut args = c_args(&exe).to_vec();
        args.extend([
            "--rows",
            "cap,wedge,near-edge",
            "--cases",
            "4000",
            "--tolerance",
            tolerance,
        ]);
        let (r, _) = stress(&args);
        let t = tallies(&r, 0);
        let wrong =
            |t: &Value| t["wrong_face"].as_u64().unwrap() + t["no_exit_face"].as_u64().unwrap();
        assert_eq!(t[0]["judged"], 4000);
        assert_eq!(t[1]["judged"], 4000);
        (
            wrong(&t[0]) + wrong(&t[1]),
            t[2]["judged"].as_u64().unwrap(),
        )
    };
    let (all, near) = row("0");
    let (within, near_within) = row("0.00001");
    assert!(all >= 40 && within * 2 < all, "{all} {within}");
    assert_eq!((near, near_within), (4000, 0));
}

/// `count --answerer` walks the scene step by step through the program, a view's unfinished walks
/// asked as one batch: the numpy kernel walks as tetwalk's `ray-plane` does (the same tetrahedra
/// crossed, the same wrong rays); a program that always turns back is caught in cycles of period 2,
/// and one that never answers a face ends every walk with no exit face. Other families and
/// `--relabel` are refused.
#[test]
fn count_walks_the_scene_through_an_answerer() {
    let count = |extra: &[&str]| {
        let dir = tempfile::tempdir().unwrap();
        let json = dir.path().join("c.json");
        let mut args = vec!["count", "--views", "2", "--size", "40x40"];
        args.extend(extra);
        args.extend(["--json", json.to_str().unwrap()]);
        let (code, _, err) = tetwalk(&args);
        assert_eq!(code, 0, "{err}");
        let r: Value = serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
        r["methods"].as_array().unwrap().clone()
    };
    let binary = |cmd: &str| {
        format!(
            r#"python3 -c '
import sys, struct
inp, out = sys.stdin.buffer, sys.stdout.buffer
while True:
    head = inp.read(4)
    if len(head) < 4: break
    n = struct.unpack("<I", head)[0]
    for _ in range(n):
        line, entry = struct.unpack_from("<I72xi", inp.read(80))
        out.write(struct.pack("<Ii", line, {cmd}))
    out.flush()
'"#
        )
    };
    let has_numpy = std::process::Command::new("python3")
        .args(["-c", "import numpy"])
        .status()
        .is_ok_and(|s| s.success());
    if has_numpy {
        let py = concat!(
            "python3 ",
            env!("CARGO_MANIFEST_DIR"),
            "/examples/kernels/python/ray_plane.py"
        );
        let rows = count(&[
            "--answerer",
            py,
            "--answerer-format",
            "binary",
            "--methods",
            "ray-plane",
        ]);
        let (ours, theirs) = (&rows[1], &rows[2]);
        assert_eq!(ours["method"], "answerer");
        for k in ["wrong_total", "wrong", "steps"] {
            assert_eq!(ours[k], theirs[k], "{k}");
        }
        assert!(ours["steps"].as_u64().unwrap() > 3200);
    }
    let back = binary("entry if entry >= 0 else 0");
    let rows = count(&["--answerer", &back, "--answerer-format", "binary"]);
    assert!(
        rows[1]["wrong"]["cycle"].as_u64().unwrap() > 1000,
        "{}",
        rows[1]
    );
    let none = binary("-1");
    let rows = count(&["--answerer", &none, "--answerer-format", "binary"]);
    assert_eq!(rows[1]["wrong"]["no_exit_face"], 3200, "{}", rows[1]);
    assert_eq!(rows[1]["steps"], 3200);
    for extra in [["--family", "triangle"], ["--relabel", "all"]] {
        let mut args = vec!["count", "--answerer", "cat"];
        args.extend(extra);
        let (code, _, err) = tetwalk(&args);
        assert_eq!(code, 2, "{err}");
    }
}

/// A Python program answering every case with `json` (a JSON answer's fields) in JSON Lines, or with
/// the record `pack` (struct.pack's arguments) after the case's number, in binary records of `size`
/// bytes (the case's number among them).
fn constant(format: &str, json: &str, pack: &str, size: usize) -> String {
    match format {
        "json" => format!(
            r#"python3 -c '
import json, sys
for line in sys.stdin:
    if line.strip():
        a = {{"line": json.loads(line)["line"]}}
        a.update({json})
        print(json.dumps(a))
    else:
        sys.stdout.flush()
'"#
        ),
        _ => format!(
            r#"python3 -c '
import struct, sys
inp, out = sys.stdin.buffer, sys.stdout.buffer
while True:
    head = inp.read(4)
    if len(head) < 4: break
    n = struct.unpack("<I", head)[0]
    cases = inp.read(n * {size})
    for k in range(n):
        line = struct.unpack_from("<I", cases, k * {size})[0]
        out.write(struct.pack("<I", line) + struct.pack({pack}))
    out.flush()
'"#
        ),
    }
}

/// Triangle and octree cell cases travel in binary records too: the same answers given as records
/// and as JSON lines get the same tables, row for row; a record naming a triangle the case lacks is
/// an error naming it.
#[test]
fn triangles_and_octree_cells_travel_in_binary_records_too() {
    for (family, json, pack, size) in [
        ("triangle", r#"{"tri": None}"#, r#""<if", -1, 0.0"#, 756),
        (
            "octree",
            r#"{"face": "+x", "quarter": [1, 1]}"#,
            r#""<iii", 1, 1, 1"#,
            52,
        ),
    ] {
        let tables: Vec<Vec<Value>> = ["json", "binary"]
            .iter()
            .map(|format| {
                let (r, _) = stress(&[
                    "--family",
                    family,
                    "--cases",
                    "60",
                    "--answerer",
                    &constant(format, json, pack, size),
                    "--answerer-format",
                    format,
                ]);
                tallies(&r, 0)
            })
            .collect();
        assert_eq!(tables[0], tables[1], "{family}");
        // Some answers are wrong: a count other than the cases judged is above zero somewhere.
        let wrong: u64 = tables[0]
            .iter()
            .flat_map(|t| t.as_object().unwrap().iter())
            .filter(|(k, _)| *k != "judged")
            .filter_map(|(_, v)| v.as_u64())
            .sum();
        assert!(wrong > 0, "{family}: {:?}", tables[0]);
    }
    let (code, _, err) = tetwalk(&[
        "stress",
        "--family",
        "triangle",
        "--cases",
        "5",
        "--answerer",
        &constant("binary", "", r#""<if", 25, 1.0"#, 756),
        "--answerer-format",
        "binary",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("answered triangle 25"), "{err}");
}

/// `--answerer-claims`: the program claims what the family's methods claim, and `--fail-on claims`
/// fails the run that refutes it (status 1) and passes one that does not, in `stress` and in
/// `count`; an answerer may not take the name of one of tetwalk's methods.
#[test]
fn an_answerer_that_claims_is_held_to_its_claim() {
    let dir = tempfile::tempdir().unwrap();
    let exe = c_kernel(dir.path());
    let run = |rows: &str| {
        let mut args = vec!["stress"];
        args.extend(c_args(&exe));
        args.extend([
            "--answerer-claims",
            "--fail-on",
            "claims",
            "--rows",
            rows,
            "--cases",
            "500",
        ]);
        tetwalk(&args)
    };
    let (code, _, err) = run("near-edge");
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("claims robust: REFUTED"), "{err}");
    let (code, _, err) = run("well");
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("claims robust: holds here"), "{err}");
    // A count asks it every step of every walk: with its own face numbering it is right on the
    // small far grid; with the identity numbering every walk is wrong, and the claim refuted.
    for (faces, status, says) in [
        ("3,0,1,2", 0, "claims robust: holds here"),
        ("0,1,2,3", 1, "claims robust: REFUTED by 512"),
    ] {
        let (code, _, err) = tetwalk(&[
            "count",
            "--scene",
            "kuhn-far",
            "--views",
            "2",
            "--size",
            "16x16",
            "--answerer",
            &exe,
            "--answerer-format",
            "binary",
            "--faces",
            faces,
            "--answerer-claims",
            "--fail-on",
            "claims",
        ]);
        assert_eq!(code, status, "{err}");
        assert!(err.contains(says), "{err}");
    }
    let (code, _, err) = tetwalk(&[
        "stress",
        "--answerer",
        &exe,
        "--answerer-name",
        "certified",
        "--cases",
        "5",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("tetwalk's own"), "{err}");
}

/// `exit --answerer` and `hit --answerer` judge a file of cases through the program, line by line: on
/// a stress row's cases (`gen-cases --row`) the C kernel is wrong exactly as often as `stress` counts;
/// walk cases are refused, naming `count --answerer`.
#[test]
fn exit_and_hit_judge_a_file_through_an_answerer() {
    let dir = tempfile::tempdir().unwrap();
    let exe = c_kernel(dir.path());
    let kernel = c_args(&exe);
    let (_, cases, _) = tetwalk(&["gen-cases", "--row", "near-vertex", "--count", "400"]);
    let json = dir.path().join("e.json");
    let mut args = vec!["exit", "--json", json.to_str().unwrap()];
    args.extend(kernel);
    let (code, out, err) = run_tetwalk(&args, cases.as_bytes());
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 400);
    assert!(out.lines().all(|l| l.contains("\"backend\":\"outside\"")));
    let e: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    // Claiming robustness there fails the run.
    let mut args = vec!["exit", "--answerer-claims", "--fail-on", "claims"];
    args.extend(kernel);
    let (code, _, err) = run_tetwalk(&args, cases.as_bytes());
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("REFUTED"), "{err}");
    let mut args = vec!["--rows", "near-vertex", "--cases", "400"];
    args.extend(kernel);
    let (r, _) = stress(&args);
    let t = &tallies(&r, 0)[0];
    assert_eq!(
        e["methods"][0]["wrong"].as_u64(),
        Some(t["wrong_face"].as_u64().unwrap() + t["no_exit_face"].as_u64().unwrap())
    );
    let (_, tri, _) = tetwalk(&["gen-cases", "--shape", "octahedron", "--count", "30"]);
    let (code, out, err) = run_tetwalk(
        &[
            "hit",
            "--answerer",
            &constant("json", r#"{"tri": None}"#, "", 0),
        ],
        tri.as_bytes(),
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.lines().any(|l| l.contains("\"leak\":true")), "{out}");
    // A program that claims what the triangle methods claim, no leak, is refuted by its leaks.
    let (code, _, err) = run_tetwalk(
        &[
            "hit",
            "--answerer",
            &constant("json", r#"{"tri": None}"#, "", 0),
            "--answerer-claims",
            "--fail-on",
            "claims",
        ],
        tri.as_bytes(),
    );
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("claims no leak: REFUTED by"), "{err}");
    let walk = r#"{"mesh":"kuhn","org":[0.5,0.5,0.5],"dir":[1,0,0]}"#;
    let mut args = vec!["exit"];
    args.extend(kernel);
    let (_, out, _) = run_tetwalk(&args, format!("{walk}\n").as_bytes());
    assert!(
        out.contains("count --answerer") || out.contains("error"),
        "{out}"
    );
}

/// A Python exit-face answerer in binary records: `body` runs once per batch with `recs` (the cases'
/// numbers and entry faces, in order) and `out` (standard output) in scope, after which it flushes.
fn binary_program(body: &str) -> String {
    format!(
        r#"python3 -c '
import struct, sys, time
inp, out = sys.stdin.buffer, sys.stdout.buffer
batch = 0
while True:
    head = inp.read(4)
    if len(head) < 4: break
    n = struct.unpack("<I", head)[0]
    recs = [struct.unpack_from("<I72xi", inp.read(80)) for _ in range(n)]
    batch += 1
{body}
    out.flush()
'"#
    )
}

/// A Python exit-face answerer in JSON Lines: `body` runs once per batch with `lines` (the cases'
/// numbers, in order) and `say` (print one answer object) in scope.
fn json_program(body: &str) -> String {
    format!(
        r#"python3 -c '
import json, sys
def say(o): print(json.dumps(o))
batch = 0
lines = []
for l in sys.stdin:
    if l.strip():
        lines.append(json.loads(l)["line"])
        continue
    batch += 1
{body}
    sys.stdout.flush()
    lines = []
'"#
    )
}

/// `stress` of the `well` row through `cmd` in `format`, `cases` cases in batches of `batch`: its
/// status and standard error.
fn asked(cmd: &str, format: &str, cases: &str, batch: &str) -> (i32, String) {
    let (code, _, err) = tetwalk(&[
        "stress",
        "--rows",
        "well",
        "--cases",
        cases,
        "--answerer",
        cmd,
        "--answerer-format",
        format,
        "--answerer-batch",
        batch,
    ]);
    (code, err)
}

/// `stress` through `cmd` as [`asked`] runs it fails (status 2) saying `says`.
fn refused(cmd: &str, format: &str, cases: &str, batch: &str, says: &str) {
    let (code, err) = asked(cmd, format, cases, batch);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(says), "wanted '{says}': {err}");
}

/// Every answer is read against the case it names: a binary record carries its case's number, so one
/// record too many is refused wherever its bytes fall — in the same write as the batch's answers,
/// written apart before the next batch is asked, or after the run's last batch (read to its end);
/// the same for a JSON line answering a case again, within a batch of several cases or after the
/// last one. The honest programs pass.
#[test]
fn an_answer_stream_cannot_shift() {
    let each = "    for line, entry in recs: out.write(struct.pack(\"<Ii\", line, 0))";
    let (code, err) = asked(&binary_program(each), "binary", "40", "10");
    assert_eq!(code, 0, "{err}");
    let cases = [
        (
            format!("{each}\n    out.write(struct.pack(\"<Ii\", recs[-1][0], 0))"),
            "bytes more than the 10 answer records",
        ),
        (
            format!(
                "{each}\n    out.flush()\n    time.sleep(0.2)\n    out.write(struct.pack(\"<Ii\", recs[-1][0], 0))"
            ),
            "carries case number 10 where 11 was expected: the answer stream shifted",
        ),
    ];
    for (body, says) in &cases {
        let (code, err) = asked(&binary_program(body), "binary", "40", "10");
        assert_eq!(code, 2, "{body}: {err}");
        // Written at once, the extra record may still be read apart from the others on a busy
        // machine: then it is the next batch's first record that does not fit.
        let apart = "carries case number 10 where 11 was expected: the answer stream shifted";
        assert!(err.contains(says) || err.contains(apart), "{body}: {err}");
    }
    // One batch: the extra record arrives after it, when nothing more is asked.
    let late = format!(
        "{each}\n    out.flush()\n    time.sleep(0.2)\n    out.write(struct.pack(\"<Ii\", recs[-1][0], 0))"
    );
    refused(
        &binary_program(&late),
        "binary",
        "10",
        "10",
        "8 bytes after the run's last batch",
    );
    let answer = "    for k in lines: say({\"line\": k, \"face\": 0})";
    let (code, err) = asked(&json_program(answer), "json", "40", "10");
    assert_eq!(code, 0, "{err}");
    let twice_within = "    for k in lines: say({\"line\": k, \"face\": 0})\n    say({\"line\": lines[3], \"face\": 1})";
    refused(
        &json_program(twice_within),
        "json",
        "40",
        "10",
        "a second answer for line 4",
    );
    // Answered twice within the batch before its last answer: refused in the batch itself.
    let before_last = "    say({\"line\": lines[0], \"face\": 0})\n    for k in lines: say({\"line\": k, \"face\": 0})";
    refused(
        &json_program(before_last),
        "json",
        "40",
        "10",
        "a second answer for line 1 in its batch (lines 1 to 10)",
    );
    let last_twice = "    for k in lines: say({\"line\": k, \"face\": 0})\n    say({\"line\": lines[-1], \"face\": 0})";
    refused(
        &json_program(last_twice),
        "json",
        "10",
        "10",
        "a second answer for line 10 after the run's last batch",
    );
}

/// What went wrong is said: a binary program asked in JSON Lines, text printed in a binary stream, a
/// program answering no face to anything when its numbering is sought, a crash (named by its signal,
/// behind `sh -c` too), plain line ranges; `exit --answerer` asks in batches of `--answerer-batch`.
#[test]
fn an_answerers_failures_are_said_as_they_happened() {
    // Records written for each JSON line read: caught at its first bytes, not at a time limit.
    let records = "    for k in lines: sys.stdout.buffer.write(bytes([1, 0, 0, 0, 0, 0, 0, 0]))";
    let (code, err) = asked(&json_program(records), "json", "10", "10");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("its output is not JSON Lines: byte 0 of what it wrote is 0x01")
            && err.contains("does it answer in binary records (--answerer-format binary)?"),
        "{err}"
    );
    let text = "    for line, entry in recs: out.write(b\"face 0\\n\")";
    refused(
        &binary_program(text),
        "binary",
        "10",
        "10",
        "holds text ('face 0",
    );
    let none = "    for line, entry in recs: out.write(struct.pack(\"<Ii\", line, -1))";
    let (code, _, err) = tetwalk(&[
        "stress",
        "--answerer",
        &binary_program(none),
        "--answerer-format",
        "binary",
        "--faces",
        "auto",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("answered no exit face on every one of the 2000 cases"),
        "{err}"
    );
    let crash = "    if batch == 2: import os, signal; os.kill(os.getpid(), signal.SIGSEGV)\n    for k in lines: say({\"line\": k, \"face\": 0})";
    let (code, err) = asked(&json_program(crash), "json", "30", "10");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("after 0 of a batch's 10 answers (lines 11 to 20)")
            && err.contains("signal 11 (SIGSEGV)"),
        "{err}"
    );
    // A batch larger than --answerer-batch fails the program, so `exit` passing means none was.
    let at_most_7 =
        "    if len(lines) > 7: sys.exit(3)\n    for k in lines: say({\"line\": k, \"face\": 0})";
    let (_, cases, _) = tetwalk(&["gen-cases", "--row", "well", "--count", "50"]);
    let (code, out, err) = run_tetwalk(
        &[
            "exit",
            "--answerer",
            &json_program(at_most_7),
            "--answerer-batch",
            "7",
        ],
        cases.as_bytes(),
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 50);
}
