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
