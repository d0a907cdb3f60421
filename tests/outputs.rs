//! Nothing a user gives is lost: an output that is one of the run's inputs or another of its outputs
//! (by identity: another spelling, a symbolic link, a hard link) is refused before any work, and
//! nothing is written; a dangling symbolic link given as an output is followed and stays a link.

use std::path::Path;

mod common;

use common::run_tetwalk as tetwalk;

/// The run must be refused naming both places, leave every file as it was and write nothing new.
fn refused(dir: &Path, args: &[&str], says: &[&str]) {
    let before = snapshot(dir);
    let (code, _, err) = tetwalk(args, b"");
    assert_eq!(code, 2, "tetwalk {args:?}: {err}");
    for s in says {
        assert!(err.contains(s), "tetwalk {args:?}: {err} lacks {s:?}");
    }
    assert!(err.contains("nothing was written"), "{err}");
    assert_eq!(snapshot(dir), before, "tetwalk {args:?} changed files");
}

/// Every file of a folder with its bytes.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            (name, std::fs::read(e.path()).unwrap_or_default())
        })
        .collect();
    out.sort();
    out
}

#[test]
fn an_output_that_is_an_input_or_another_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let at = |name: &str| dir.path().join(name).display().to_string();
    let (_, cases, _) = tetwalk(&["gen-cases", "--count", "3"], b"");
    std::fs::write(at("cases.jsonl"), &cases).unwrap();
    std::fs::write(
        at("answers.jsonl"),
        "{\"line\":1,\"face\":0}\n{\"line\":2,\"face\":0}\n{\"line\":3,\"face\":0}\n",
    )
    .unwrap();
    let (c, a) = (at("cases.jsonl"), at("answers.jsonl"));
    refused(
        dir.path(),
        &["judge", &c, &a, "--json", &c],
        &["--json", "CASES"],
    );
    refused(
        dir.path(),
        &["judge", &c, &a, "--json", &a],
        &["--json", "ANSWERS"],
    );
    // Another spelling, a symbolic link and a hard link are the same file.
    let spelled = format!("{}/./cases.jsonl", dir.path().display());
    refused(
        dir.path(),
        &["judge", &c, &a, "--json", &spelled],
        &["CASES"],
    );
    std::os::unix::fs::symlink(&c, at("link.jsonl")).unwrap();
    refused(
        dir.path(),
        &["judge", &c, &a, "--json", &at("link.jsonl")],
        &["CASES"],
    );
    std::fs::hard_link(&a, at("hard.jsonl")).unwrap();
    refused(
        dir.path(),
        &["judge", &c, &a, "--json", &at("hard.jsonl")],
        &["ANSWERS"],
    );
    refused(dir.path(), &["exit", &c, "--json", &c], &["--json", "FILE"]);
    // Two outputs in one place: one would be lost.
    let x = at("x.json");
    refused(
        dir.path(),
        &[
            "count", "--views", "1", "--size", "4x4", "--json", &x, "--dump", &x,
        ],
        &["--dump", "another output, --json"],
    );
    // Shards and found cases read by the run.
    let shard = at("shard.json");
    let (code, _, err) = tetwalk(
        &[
            "count", "--views", "2", "--size", "4x4", "--shard", "0/2", "--json", &shard,
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    refused(
        dir.path(),
        &["count", "merge", &shard, "--json", &shard],
        &["REPORTS"],
    );
    let found = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpora/found/maria17");
    let one = std::fs::read_dir(&found)
        .unwrap()
        .flatten()
        .next()
        .unwrap()
        .path();
    std::fs::copy(&one, at("found.json")).unwrap();
    refused(
        dir.path(),
        &["shrink", &at("found.json"), "--json", &at("found.json")],
        &["FILES"],
    );
}

#[test]
fn a_dangling_link_given_as_an_output_stays_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("report.json");
    std::os::unix::fs::symlink("target.json", &link).unwrap();
    let (code, _, err) = tetwalk(&["methods", "--json", &link.display().to_string()], b"");
    assert_eq!(code, 0, "{err}");
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    let written = std::fs::read_to_string(dir.path().join("target.json")).unwrap();
    assert!(written.contains("maria17"), "{written}");
}

/// `tetwalk ARGS` with standard input read from `stdin` and standard output written to `stdout`
/// (files): its status and standard error.
fn redirected(args: &[&str], stdin: &Path, stdout: &Path) -> (i32, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(args)
        .stdin(std::fs::File::open(stdin).unwrap())
        .stdout(std::fs::File::create(stdout).unwrap())
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// No output lands on what the run reads or prints: standard input given as a file is protected by
/// identity like a named input (`--json /dev/stdin`, `/proc/self/fd/0`); `/dev/stdout` is written
/// into, after the lines printed there, whether standard output is a file or a pipe; a named output
/// that is where standard output goes is refused (renamed over, it would lose the lines); `verify`'s
/// found corpus is among its inputs.
#[test]
fn no_output_lands_on_an_input_or_a_printed_stream() {
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("cases.jsonl");
    let (_, text, _) = tetwalk(&["gen-cases", "--row", "well", "--count", "3"], b"");
    std::fs::write(&cases, &text).unwrap();
    let printed = dir.path().join("printed.txt");
    for json in ["/dev/stdin", "/proc/self/fd/0"] {
        let (code, err) = redirected(&["exit", "--json", json], &cases, &printed);
        assert_eq!(code, 2, "{json}: {err}");
        assert!(
            err.contains("standard input") && err.contains("nothing was written"),
            "{err}"
        );
        assert_eq!(std::fs::read_to_string(&cases).unwrap(), text, "{json}");
    }
    let c = cases.to_str().unwrap();
    let (code, err) = redirected(&["exit", c, "--json", "/dev/stdout"], &cases, &printed);
    assert_eq!(code, 0, "{err}");
    let both = std::fs::read_to_string(&printed).unwrap();
    let lines = both.lines().filter(|l| l.starts_with("{\"line\"")).count();
    assert!(lines >= 3 && both.trim_end().ends_with('}'), "{both}");
    let report: serde_json::Value =
        serde_json::from_str(&both[both.find("{\n").expect("the JSON after the lines")..]).unwrap();
    assert!(report["methods"].is_array(), "{report}");
    let piped = std::process::Command::new(env!("CARGO_BIN_EXE_tetwalk"))
        .args(["exit", c, "--json", "/dev/stdout"])
        .output()
        .unwrap();
    assert!(
        piped.status.success(),
        "{}",
        String::from_utf8_lossy(&piped.stderr)
    );
    assert!(
        String::from_utf8_lossy(&piped.stdout)
            .trim_end()
            .ends_with('}')
    );
    let p = printed.to_str().unwrap();
    let (code, err) = redirected(&["exit", c, "--json", p], &cases, &printed);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("standard output") && err.contains("/dev/stdout"),
        "{err}"
    );
    // verify --json onto a counterexample of its own corpus.
    let found = dir.path().join("found");
    std::fs::create_dir(&found).unwrap();
    let case = found.join("case.json");
    std::fs::write(&case, "{}").unwrap();
    refused(
        dir.path(),
        &[
            "verify",
            "--found",
            found.to_str().unwrap(),
            "--json",
            case.to_str().unwrap(),
        ],
        &["--found", "case.json"],
    );
}
