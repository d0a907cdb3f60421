//! Bad input, as a user can type it: each gets a clear error naming what is wrong (or a right answer),
//! never a panic, an abort, a hang or a silent default, and leaves no file behind.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use tetwalk::family::{ExitFace, Family, OctreeCells, Triangle, Walks};
use tetwalk::registry::Named;

mod common;

use common::run_tetwalk as tetwalk;

/// `args` must fail (status 1 or 2) with a message holding every one of `says`, and no panic.
fn refused(args: &[&str], says: &[&str]) {
    let (code, _, err) = tetwalk(args, b"");
    assert!(
        code == 1 || code == 2,
        "tetwalk {args:?}: status {code}, {err}"
    );
    assert!(
        !err.contains("panicked"),
        "tetwalk {args:?} panicked: {err}"
    );
    for s in says {
        assert!(err.contains(s), "tetwalk {args:?}: {err:?} lacks {s:?}");
    }
}

#[test]
fn impossible_sizes_and_counts_are_refused_with_the_figure_they_need() {
    refused(
        &["walk", "--mesh", "kuhn", "--size", "100000"],
        &["tetrahedra", "GiB"],
    );
    refused(&["walk", "--size", "0"], &["size must be 1 or more"]);
    refused(
        &["count", "--size", "16384x16384"],
        &["GiB", "--size 16384x16384"],
    );
    refused(
        &["count", "--size", "100000x100000"],
        &["--size 100000x100000"],
    );
    refused(&["stress", "--cases", "1000000000000"], &["GiB", "--cases"]);
    refused(&["stress", "--cases", "0"], &["--cases 0"]);
    refused(&["walk", "--rays", "100000000000"], &["GiB", "--rays"]);
    refused(&["render", "shaded", "--size", "20000x20000"], &["GiB"]);
    refused(
        &["bench", "--size", "65536x65536"],
        &["GiB", "--size 65536x65536"],
    );
    refused(&["bench", "--batch", "0"], &["--batch 0"]);
}

#[test]
fn silent_defaults_and_empty_runs_are_errors() {
    refused(&["stress", "--ulps", "0"], &["--ulps 0"]);
    refused(&["gen-cases", "--ulps", "0"], &["--ulps 0"]);
    refused(&["count", "--views", "0"], &["--views 0"]);
    refused(&["bench", "--views", "0"], &["--views 0"]);
    refused(&["bench", "--backend", "cpu,tpu"], &["'tpu'", "cpu-fma"]);
    refused(
        &["render", "shaded", "--view", "200", "--size", "8x8"],
        &["view 200", "numbered 0 to 159"],
    );
    refused(
        &[
            "render",
            "failures",
            "--methods",
            "exact",
            "--size",
            "16x16",
        ],
        &["nothing to draw"],
    );
    refused(&["count", "--views", "-1"], &["-1"]);
    refused(
        &["exit", "--fma", "--backend", "cpu"],
        &["--backend cpu-fma"],
    );
    refused(
        &["count", "--methods", "maria18"],
        &["unknown method 'maria18'"],
    );
}

/// `count --rays-out` of a scene none of whose cameras lies inside it writes nothing: the run is an
/// error, and no rays file (nor a staging file) is left.
#[test]
fn rays_out_of_no_view_is_an_error_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("one.msh");
    std::fs::write(
        &mesh,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 2 0 1 1 2 3 4\n$EndElements\n",
    )
    .unwrap();
    let rays = dir.path().join("rays.jsonl");
    refused(
        &[
            "count",
            "--scene",
            mesh.to_str().unwrap(),
            "--no-faces",
            "--views",
            "2",
            "--size",
            "8x8",
            "--rays-out",
            rays.to_str().unwrap(),
        ],
        &["none of the 2 camera positions lies inside the mesh"],
    );
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        left,
        vec![std::ffi::OsString::from("one.msh")],
        "left: {left:?}"
    );
}

#[test]
fn a_scene_without_its_constrained_faces_is_refused_unless_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    for e in ["node", "ele", "neigh", "face"] {
        std::fs::copy(
            Path::new(data).join(format!("twobox.1.{e}")),
            dir.path().join(format!("m.{e}")),
        )
        .unwrap();
    }
    let stem = dir.path().join("m");
    let count = [
        "count",
        "--scene",
        stem.to_str().unwrap(),
        "--views",
        "3",
        "--size",
        "4x4",
    ];
    let (code, out, err) = tetwalk(&count, b"");
    // With its faces the scene is counted; without the .face file, or with an empty one, refused.
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("3 views"), "{out}");
    std::fs::remove_file(stem.with_extension("face")).unwrap();
    refused(&count, &["m.face", "missing", "--no-faces"]);
    std::fs::write(stem.with_extension("face"), "0 1\n").unwrap();
    refused(&count, &["m.face", "holds no faces"]);
    let (code, _, err) = tetwalk(
        &["scene", "info", stem.to_str().unwrap(), "--no-faces"],
        b"",
    );
    assert_eq!(
        code, 0,
        "asked for explicitly, a mesh without faces loads: {err}"
    );
}

#[test]
fn exit_answers_a_stream_line_by_line_and_names_bad_lines() {
    let good = br#"{"tet":[[0,0,0],[0,1,0],[1,0,0],[0,0,1]],"org":[0.1,0.1,-1],"dir":[0,0,1]}"#;
    let mut input = b"\xff\xfe not utf-8\n".to_vec();
    input.extend_from_slice(good);
    input.push(b'\n');
    input.extend(std::iter::repeat_n(b'x', 2 << 20));
    input.push(b'\n');
    input.extend_from_slice(good);
    input.push(b'\n');
    let (code, out, err) = tetwalk(&["exit", "--method", "maria17"], &input);
    assert_eq!(code, 1, "{err}");
    let lines: Vec<serde_json::Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 4, "{out}");
    assert_eq!(lines[0]["line"], 1);
    assert!(lines[0]["error"].as_str().unwrap().contains("UTF-8"));
    assert_eq!(lines[1]["correct"], true);
    assert!(lines[2]["error"].as_str().unwrap().contains("longer than"));
    assert_eq!(lines[3]["line"], 4);
    assert_eq!(lines[3]["correct"], true);
}

#[test]
fn an_exit_stream_gets_answers_before_it_ends() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(["exit", "--method", "maria17"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    stdin
        .write_all(
            b"{\"tet\":[[0,0,0],[0,1,0],[1,0,0],[0,0,1]],\"org\":[0.1,0.1,-1],\"dir\":[0,0,1]}\n",
        )
        .unwrap();
    stdin.flush().unwrap();
    // The input stays open; the answer must come anyway.
    let mut stdout = std::io::BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    std::io::BufRead::read_line(&mut stdout, &mut line).unwrap();
    assert!(line.contains("\"correct\":true"), "{line}");
    drop(stdin);
    assert!(child.wait().unwrap().success());
}

#[test]
fn scene_build_refuses_what_cannot_be_represented_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let cube = dir.path().join("cube.off");
    let mut text = String::from("OFF\n8 12 0\n");
    for k in 0..8 {
        text += &format!("{} {} {}\n", k & 1, (k >> 1) & 1, (k >> 2) & 1);
    }
    for [a, b, c] in [
        [0, 3, 1],
        [0, 2, 3],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ] {
        text += &format!("3 {a} {b} {c}\n");
    }
    std::fs::write(&cube, text).unwrap();
    let c = cube.to_str().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    for (offset, says) in [
        ("inf", "not finite"),
        ("nan", "not finite"),
        ("1e35", "1e30"),
    ] {
        refused(
            &["scene", "build", c, "--offset", offset, "--out", o],
            &[says],
        );
    }
    let files = || std::fs::read_dir(dir.path()).unwrap().count();
    assert_eq!(files(), 1, "nothing but the model is left");
    // The unit cube moved by 3: every point of the built scene is an f32, and it loads.
    let (code, _, err) = tetwalk(&["scene", "build", c, "--offset", "3", "--out", o], b"");
    if code == 0 {
        let mesh = tetwalk::mesh::load_tetgen(&out).unwrap();
        assert!(mesh.tets.len() > 12);
    } else {
        assert!(
            !err.contains("panicked") && err.contains("nothing was written"),
            "{err}"
        );
        assert_eq!(files(), 1, "a failed build leaves nothing");
    }
}

#[test]
fn generators_refuse_what_would_underflow_or_leave_f32() {
    for family in ["well", "needle", "wedge"] {
        refused(
            &["gen-cases", "--tet-shape", family, "--flatness", "1e-45"],
            &["--flatness 1e-45", "2^-126"],
        );
    }
    refused(
        &["gen-cases", "--shape", "needle", "--flatness", "1e-45"],
        &["--flatness 1e-45"],
    );
    refused(
        &["gen-cases", "--rays", "near-edge", "--ulps", "2147483647"],
        &["--ulps 2147483647", "1048576"],
    );
    for family in ["exit-face", "triangle", "octree"] {
        refused(
            &[
                "stress",
                "--family",
                family,
                "--flatness",
                "1e-45",
                "--cases",
                "5",
            ],
            &["--flatness 1e-45"],
        );
        refused(
            &[
                "stress",
                "--family",
                family,
                "--ulps",
                "2147483647",
                "--cases",
                "5",
            ],
            &["--ulps 2147483647"],
        );
    }
    // At the smallest normal flatness every family still gives cases exit judges (no null, no panic).
    let (code, out, err) = tetwalk(
        &[
            "gen-cases",
            "--tet-shape",
            "wedge",
            "--flatness",
            "1.2e-38",
            "--count",
            "20",
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        !out.contains("[null") && !out.contains(",null"),
        "every coordinate finite: {out}"
    );
    let (code, _, err) = tetwalk(&["exit", "--method", "stp"], out.as_bytes());
    assert_eq!(code, 0, "{err}");
}

#[test]
fn odd_sizes_views_depths_and_shards_are_refused_before_any_work() {
    refused(
        &["render", "predicate", "--size", "64x4000"],
        &["--size 64x4000", "square"],
    );
    refused(&["render", "leak", "--size", "64x32"], &["square"]);
    refused(
        &["count", "--views", "100000000", "--size", "1x1"],
        &["--views 100000000"],
    );
    refused(
        &["count", "--family", "octree", "--depth", "0"],
        &["--depth 0"],
    );
    refused(
        &[
            "count", "--scene", "kuhn", "--views", "3", "--shard", "5/10",
        ],
        &["--shard 5/10 holds no view"],
    );
    refused(
        &["count", "--rays-out", "x.jsonl", "--fail-on", "wrong"],
        &["--fail-on"],
    );
    refused(&["exit", "--t-ulps", "3"], &["--t-ulps"]);
    refused(&["hit", "--wgsl", "user.wgsl"], &["--wgsl"]);
}

/// A folder given where a file goes is refused before the run, for every output flag.
#[test]
fn an_output_that_is_a_folder_is_refused_up_front() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let count = ["count", "--scene", "kuhn", "--views", "2", "--size", "8x8"];
    for flag in ["--json", "--dump", "--rays-out"] {
        let mut args = count.to_vec();
        args.extend([flag, d]);
        refused(&args, &[flag, "is a folder"]);
    }
    refused(
        &[
            "render", "shaded", "--scene", "kuhn", "--size", "8x8", "--out", d,
        ],
        &["--out", "is a folder"],
    );
    refused(
        &["paper", "--scene", "kuhn", "--out", d],
        &["--out", "is a folder"],
    );
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "nothing left behind: {left:?}");
}

/// `child` sent `signal` (`-TERM`, `-INT`): it must end with status 130; its standard error.
fn interrupted(child: &mut std::process::Child, signal: &str) -> String {
    let killed = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    let mut err = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    err
}

/// A run stopped by SIGTERM removes the staging file of the output it was writing.
#[test]
fn an_interrupted_run_leaves_no_staging_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rays.jsonl");
    let mut child = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args([
            "count",
            "--views",
            "1000",
            "--size",
            "1024x1024",
            "--rays-out",
        ])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let staging = || {
        std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with(".tetwalk-"))
            .count()
    };
    // Wait (by progress, not by the clock) until it is writing: its staging file has grown.
    let mut grown = false;
    for _ in 0..6000 {
        let size: u64 = std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(|e| e.ok()?.metadata().ok())
            .map(|m| m.len())
            .sum();
        if size > 1 << 20 {
            grown = true;
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    assert!(grown, "the run began writing");
    assert_eq!(staging(), 1);
    let err = interrupted(&mut child, "-TERM");
    assert!(
        err.contains("interrupted; 1 unfinished output file removed, nothing written"),
        "{err}"
    );
    assert_eq!(staging(), 0, "the staging file is removed");
    assert!(!out.exists(), "and nothing half-written appears");
}

/// An interrupted campaign says what it kept: the found cases it filed, each written whole.
#[test]
fn an_interrupted_campaign_says_what_it_kept() {
    let dir = tempfile::tempdir().unwrap();
    let found = dir.path().join("found");
    let mut child = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args([
            "stress",
            "--methods",
            "plucker",
            "--seconds",
            "600",
            "--found",
        ])
        .arg(&found)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let filed = || {
        std::fs::read_dir(found.join("plucker"))
            .map(|d| d.filter_map(|e| e.ok()).count())
            .unwrap_or(0)
    };
    // Wait (by progress) until it has filed a case.
    for _ in 0..6000 {
        if filed() > 0 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    assert!(filed() > 0, "the campaign filed a case");
    let err = interrupted(&mut child, "-INT");
    let kept = filed();
    assert!(
        err.contains("written whole before it kept") && !err.contains("nothing written"),
        "{kept} filed: {err}"
    );
}

/// A count of 512 rays on a scene where f32 Plücker is wrong on every one.
const SMALL_COUNT: [&str; 7] = [
    "count", "--scene", "kuhn-far", "--views", "2", "--size", "16x16",
];

#[test]
fn replay_refuses_a_ray_no_walk_was_made_of() {
    let dir = tempfile::tempdir().unwrap();
    let dump = dir.path().join("dump.jsonl");
    let mut args = SMALL_COUNT.to_vec();
    args.extend(["--methods", "plucker", "--dump", dump.to_str().unwrap()]);
    let (code, _, err) = tetwalk(&args, b"");
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&dump).unwrap();
    let first = text.lines().next().expect("plucker is wrong somewhere");
    let mut v: serde_json::Value = serde_json::from_str(first).unwrap();
    v["dir"] = serde_json::json!([0.0, 0.0, 0.0]);
    std::fs::write(&dump, format!("{v}\n")).unwrap();
    refused(
        &["replay", dump.to_str().unwrap()],
        &["line 1", "nonzero direction"],
    );
}

/// `--fail-on`: status 0 without it whatever is wrong; 1 with it when a method is wrong (or a claim
/// refuted), after the report; one line per method on standard error.
#[test]
fn fail_on_gives_ci_a_status() {
    let mut count = SMALL_COUNT.to_vec();
    count.extend(["--methods", "plucker,stp"]);
    let (code, _, err) = tetwalk(&count, b"");
    assert_eq!(code, 0, "{err}");
    let with = |rule: &str| {
        let mut a = count.to_vec();
        a.extend(["--fail-on", rule]);
        tetwalk(&a, b"")
    };
    let (code, out, err) = with("wrong");
    assert_eq!(code, 1, "{err}");
    assert!(out.contains("totals over"), "the report first: {out}");
    assert!(err.contains("plucker: 512 wrong of 512 judged"), "{err}");
    assert!(err.contains("stp: 0 wrong"), "{err}");
    assert!(err.contains("--fail-on wrong: plucker"), "{err}");
    // Neither plucker nor stp claims robustness: no claim refuted.
    let (code, _, err) = with("claims");
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("no method judged here makes a claim"), "{err}");
    // A claim held: certified on the stress rows.
    let (code, _, err) = tetwalk(
        &[
            "stress",
            "--cases",
            "200",
            "--methods",
            "certified,plucker",
            "--fail-on",
            "claims",
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("certified: 0 wrong") && err.contains("claims robust: holds here"),
        "{err}"
    );
    let case = br#"{"tet":[[0,0,0],[0,1,0],[1,0,0],[0,0,1]],"org":[0.1,0.1,-1],"dir":[0,0,1]}"#;
    let (code, _, err) = tetwalk(&["exit", "--method", "stp", "--fail-on", "wrong"], case);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("stp: 0 wrong of 1 judged"), "{err}");
}

/// An output given as a symbolic link writes its target and the link stays; one that is not a
/// regular file (a FIFO here, `/dev/stdout` in use) is written straight into, never replaced.
#[test]
fn outputs_through_links_and_fifos_are_written_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let (real, link, fifo) = (
        dir.path().join("real.json"),
        dir.path().join("link.json"),
        dir.path().join("fifo"),
    );
    std::fs::write(&real, "old").unwrap();
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let mut args = SMALL_COUNT.to_vec();
    args.extend(["--methods", "stp", "--json", link.to_str().unwrap()]);
    args.extend(["--dump", fifo.to_str().unwrap()]);
    let (code, _, err) = tetwalk(&args, b"");
    assert_eq!(code, 0, "{err}");
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    let report = std::fs::read_to_string(&real).unwrap();
    assert!(report.contains("\"settings\""), "{report}");
    let dumped = reader.join().unwrap();
    assert_eq!(dumped, "", "stp is wrong nowhere: an empty dump");
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(
        std::os::unix::fs::FileTypeExt::is_fifo(&kind),
        "still a FIFO"
    );
}

/// A closed standard output (`tetwalk … | head -1`) ends a command quietly with status 141, as SIGPIPE
/// would, and a full one (`> /dev/full`) with status 2 and one line saying so: never a panic.
#[test]
fn a_closed_or_full_standard_output_ends_the_command_quietly() {
    // Found cases enough for more than a buffer's worth of lines (8 KiB), so that a write inside the
    // engine's loop meets the closed pipe, not only the last flush.
    let found = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpora/found/maria17");
    let mut cases: Vec<String> = std::fs::read_dir(found)
        .unwrap()
        .flatten()
        .map(|e| e.path().display().to_string())
        .filter(|p| p.contains("/stress-"))
        .collect();
    cases.sort();
    let replay = [
        &["replay", "--found"][..],
        &cases.iter().map(String::as_str).collect::<Vec<_>>(),
    ]
    .concat();
    let shrink = [
        &["shrink", "--checks", "50"][..],
        &cases[..20].iter().map(String::as_str).collect::<Vec<_>>(),
    ]
    .concat();
    for args in [
        &["gen-cases", "--count", "200000"][..],
        &["stress", "--cases", "2000", "--rows", "well"],
        &["methods"],
        &replay,
        &shrink,
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        // A run whose output fitted the pipe before it closed may have ended well.
        assert!(
            matches!(out.status.code(), Some(0 | 141)),
            "{args:?}: {:?} {err}",
            out.status
        );
        // These write more than a pipe's buffer before they end: the closed pipe stops them, quietly
        // (replay may say on standard error that it skipped a case found on another GPU).
        if ["gen-cases", "replay", "shrink"].contains(&args[0]) {
            assert_eq!(out.status.code(), Some(141), "{:?}: {err}", &args[..3]);
            assert!(!err.contains("Broken pipe"), "{:?}: {err}", &args[..3]);
        }
        if args[0] == "gen-cases" {
            assert!(err.is_empty(), "{err}");
        }
        if Path::new("/dev/full").exists() {
            let full = std::fs::OpenOptions::new()
                .write(true)
                .open("/dev/full")
                .unwrap();
            let out = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
                .args(args)
                .stdout(full)
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
            assert!(
                !err.contains("panicked") && err.contains("No space left"),
                "{err}"
            );
        }
    }
}

/// A `scene build` interrupted while TetGen runs stops TetGen, removes its working folder and writes
/// nothing.
#[test]
fn an_interrupted_scene_build_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let model = dir.path().join("bunny2.off");
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpora/scenes/bunny.off");
    let (code, _, err) = tetwalk(
        &[
            "scene",
            "subdivide",
            bunny.to_str().unwrap(),
            "--levels",
            "2",
            "--out",
            model.to_str().unwrap(),
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    let out = dir.path().join("built");
    let mut child = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args([
            "scene",
            "build",
            model.to_str().unwrap(),
            "--quality",
            "--out",
            out.to_str().unwrap(),
        ])
        .env("TMPDIR", &tmp)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until TetGen works in its folder.
    let started = std::time::Instant::now();
    let working = || -> Vec<std::path::PathBuf> {
        std::fs::read_dir(&tmp)
            .unwrap()
            .flatten()
            .map(|e| e.path())
            // Mesa's private runtime folder (made by every run, kept) aside.
            .filter(|p| p.file_name().unwrap() != "tetwalk-xdg-runtime")
            .collect()
    };
    while working().is_empty() && started.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(!working().is_empty(), "no working folder was seen");
    std::thread::sleep(std::time::Duration::from_millis(300));
    // SAFETY: kill sends SIGTERM to the child tetwalk.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    assert!(working().is_empty(), "left behind: {:?}", working());
    assert!(!out.with_extension("ele").exists(), "a mesh was written");
}

/// Generated stress-row cases are written as many as `--count` asks, or none with an error (at a
/// scale where they round); a render of no view is refused with the figure, not a wrapped index.
#[test]
fn gen_cases_writes_its_count_or_fails_and_renders_need_a_view() {
    for args in [
        &[
            "gen-cases",
            "--shape",
            "octahedron",
            "--count",
            "5",
            "--scale",
            "200",
        ][..],
        &[
            "gen-cases",
            "--row",
            "near-edge",
            "--count",
            "5",
            "--scale",
            "150",
        ],
        &[
            "gen-cases",
            "--cell-aim",
            "edge",
            "--count",
            "5",
            "--scale",
            "150",
        ],
    ] {
        let (code, out, err) = tetwalk(args, b"");
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?} wrote {out}");
        assert!(
            err.contains("of the row's first 5") && err.contains("nothing was written"),
            "{err}"
        );
    }
    let (code, out, err) = tetwalk(&["gen-cases", "--shape", "octahedron", "--count", "5"], b"");
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 5);
    refused(&["render", "shaded", "--views", "0"], &["--views 0"]);
}

// The memory figures by which runs that would hold more than tetwalk plans to (`MEMORY_BUDGET`) are
// refused are at least what the runs hold: each family's `BYTES_PER_CASE` (stress, campaigns,
// gen-cases, verify) per case of a stress row, and `engine::count::bytes_per_ray` per ray of a
// counted view with one method and with every one. Measured as the growth of the peak resident
// memory of `tetwalk` (each child's own, `wait4`) between two sizes of one run. A figure set too low
// would let a run the budget admits abort on memory.

/// Peak resident bytes of `tetwalk ARGS`, which must succeed.
fn peak(args: &[&str]) -> u64 {
    // Reaped by `wait4` below, which gives the child's own peak.
    #[allow(clippy::zombie_processes)]
    let child = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid value for wait4 to fill.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: the child is ours and not yet waited for; both pointers are to live locals.
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as libc::pid_t, "wait4 failed");
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "tetwalk {args:?} failed ({status})"
    );
    // Linux reports ru_maxrss in KiB.
    usage.ru_maxrss as u64 * 1024
}

/// Bytes held per unit (case, ray): the growth of the peak from `tetwalk SMALL` (`small` units) to
/// `tetwalk LARGE` (`large` units), said on standard error.
fn per_unit(what: &str, small: (&[&str], u64), large: (&[&str], u64)) -> f64 {
    let bytes = peak(large.0).saturating_sub(peak(small.0)) as f64 / (large.1 - small.1) as f64;
    eprintln!("{what}: {bytes:.0} bytes held per unit");
    bytes
}

/// Bytes per ray of a count of one view, `tetwalk count ARGS`: the growth of the peak from 256² to
/// 512² rays.
fn per_ray(args: &[&str]) -> f64 {
    let run = |size: &'static str| [&["count", "--views", "1", "--size", size], args].concat();
    per_unit(
        &format!("count {args:?}, per ray"),
        (&run("256x256"), 256 * 256),
        (&run("512x512"), 512 * 512),
    )
}

#[test]
fn a_counts_bytes_per_ray_is_at_least_what_a_view_holds() {
    use tetwalk::engine::count::bytes_per_ray;
    // The methods a count runs by default: every one but the reference.
    fn counted<F: Family>() -> usize {
        F::methods().iter().filter(|m| !m.is_reference()).count()
    }
    for (family, methods) in [
        ("walk", 1),
        ("walk", counted::<Walks>()),
        ("triangle", counted::<Triangle>()),
        ("octree", counted::<OctreeCells>()),
    ] {
        let args: Vec<&str> = if methods == 1 {
            vec!["--family", family, "--methods", "maria17"]
        } else {
            vec!["--family", family]
        };
        let bytes = per_ray(&args);
        assert!(
            bytes <= bytes_per_ray(methods) as f64,
            "count {args:?}: a view holds {bytes:.0} bytes per ray, more than bytes_per_ray({methods}) = {}",
            bytes_per_ray(methods)
        );
    }
}

#[test]
fn walks_bytes_per_ray_is_at_least_what_tetwalk_walk_holds() {
    let run = |n: &'static str| ["walk", "--rays", n, "--methods", "maria17"];
    let bytes = per_unit(
        "walk, per ray",
        (&run("50000"), 50_000),
        (&run("200000"), 200_000),
    );
    let planned = tetwalk::family::walk::engine::bytes_per_walked_ray(1);
    assert!(
        bytes <= planned as f64,
        "tetwalk walk holds {bytes:.0} bytes per ray, more than bytes_per_walked_ray(1) = {planned}"
    );
}

/// Bytes per case a row of family `F` holds: the growth of the peak from `small` to `large` cases.
fn per_case<F: Family>(row: &[&str], small: u64, large: u64) -> f64 {
    fn run<'a>(family: &'a str, n: &'a str, row: &[&'a str]) -> Vec<&'a str> {
        [&["stress", "--family", family, "--cases", n], row].concat()
    }
    let (s, l) = (small.to_string(), large.to_string());
    per_unit(
        &format!("stress {}, per case", F::NAME),
        (&run(F::NAME, &s, row), small),
        (&run(F::NAME, &l, row), large),
    )
}

#[test]
fn each_familys_bytes_per_case_is_at_least_what_a_stress_row_holds() {
    let measured = [
        (
            ExitFace::NAME,
            per_case::<ExitFace>(
                &["--rows", "sliver", "--methods", "maria17"],
                250_000,
                1_000_000,
            ),
            ExitFace::BYTES_PER_CASE,
        ),
        (
            Walks::NAME,
            per_case::<Walks>(&["--scenes", "kuhn", "--methods", "maria17"], 5_000, 20_000),
            Walks::BYTES_PER_CASE,
        ),
        (
            Triangle::NAME,
            per_case::<Triangle>(
                &[
                    "--shapes",
                    "tetrahedron",
                    "--aims",
                    "edge",
                    "--places",
                    "origin",
                    "--methods",
                    "mt",
                ],
                20_000,
                80_000,
            ),
            Triangle::BYTES_PER_CASE,
        ),
        (
            OctreeCells::NAME,
            per_case::<OctreeCells>(
                &[
                    "--cell-aims",
                    "edge",
                    "--cell-places",
                    "origin",
                    "--methods",
                    "exact",
                ],
                20_000,
                80_000,
            ),
            OctreeCells::BYTES_PER_CASE,
        ),
    ];
    for (family, bytes, declared) in measured {
        assert!(
            bytes <= declared as f64,
            "{family}: a stress row holds {bytes:.0} bytes per case, more than BYTES_PER_CASE = {declared}"
        );
    }
}

/// A run that would judge nothing, or drop what a flag asks, is an error naming why: a tolerance that
/// leaves no case; a direction scaled and then made a unit one; an answerer's setting without an
/// answerer; a value that is not UTF-8, named with its flag; and an echoed input is cut short.
#[test]
fn a_flag_whose_meaning_would_be_dropped_is_refused() {
    refused(
        &[
            "stress",
            "--rows",
            "well",
            "--cases",
            "20",
            "--tolerance",
            "0.99",
        ],
        &["no case was judged", "tolerance 0.99"],
    );
    refused(
        &[
            "stress",
            "--unit-direction",
            "--scale",
            "0/5",
            "--cases",
            "5",
        ],
        &["--scale 0/5", "--unit-direction undoes", "--scale 0/0"],
    );
    refused(
        &[
            "gen-cases",
            "--unit-direction",
            "--scale",
            "3",
            "--count",
            "5",
        ],
        &["--scale 3/3", "--scale 3/0"],
    );
    refused(
        &["stress", "--answerer-seconds", "0", "--cases", "5"],
        &["--answerer"],
    );
    let odd = <std::ffi::OsStr as std::os::unix::ffi::OsStrExt>::from_bytes(b"\xff.msh");
    let out = Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .arg("count")
        .arg("--scene")
        .arg(odd)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("argument 3") && err.contains("--scene") && err.contains("not UTF-8"),
        "{err}"
    );
    let dir = tempfile::tempdir().unwrap();
    let (_, case, _) = tetwalk(&["gen-cases", "--row", "well", "--count", "1"], b"");
    let (cases, answers) = (dir.path().join("c.jsonl"), dir.path().join("a.jsonl"));
    std::fs::write(&cases, case).unwrap();
    std::fs::write(
        &answers,
        format!("{{\"line\": 1, \"face\": {}}}\n", "9".repeat(1_000_000)),
    )
    .unwrap();
    let (_, out, _) = tetwalk(
        &["judge", cases.to_str().unwrap(), answers.to_str().unwrap()],
        b"",
    );
    assert!(
        out.len() < 1000 && out.contains("characters in all"),
        "{} bytes",
        out.len()
    );
}
