//! Reading TetGen files: bad input gets an error naming the file, line and tetrahedron; never a panic.

use std::path::{Path, PathBuf};
use tetwalk::mesh::load_tetgen;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");

/// A copy of the test mesh in a fresh directory with `edit` applied to one of its files.
fn corrupted(ext: &str, edit: impl Fn(String) -> String) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    for e in ["node", "ele", "neigh", "face"] {
        let text = std::fs::read_to_string(Path::new(DATA).join(format!("twobox.1.{e}"))).unwrap();
        let text = if e == ext { edit(text) } else { text };
        std::fs::write(dir.path().join(format!("twobox.1.{e}")), text).unwrap();
    }
    let stem = dir.path().join("twobox.1");
    (dir, stem)
}

/// Replace line `n` (1-based) of a file.
fn set_line(text: String, n: usize, line: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines[n - 1] = line.to_string();
    lines.join("\n") + "\n"
}

fn error(ext: &str, edit: impl Fn(String) -> String) -> String {
    let (_dir, stem) = corrupted(ext, edit);
    load_tetgen(&stem)
        .expect_err("corrupted mesh must not load")
        .to_string()
}

#[test]
fn the_unchanged_copy_loads() {
    let (_dir, stem) = corrupted("node", |t| t);
    assert_eq!(load_tetgen(&stem).unwrap().tets.len(), 42);
    // Any of the four file names works as well as the stem.
    assert!(load_tetgen(&stem.with_extension("1.ele")).is_ok());
}

#[test]
fn every_kind_of_bad_input_names_its_place() {
    type Edit = Box<dyn Fn(String) -> String>;
    let cases: Vec<(&str, Edit, &[&str])> = vec![
        (
            "node",
            Box::new(|t| set_line(t, 3, "   1    4  zero  0")),
            &["twobox.1.node line 3", "not a number"],
        ),
        (
            "node",
            Box::new(|t| set_line(t, 3, "   1    1e39  0  0")),
            &["twobox.1.node line 3", "not finite"],
        ),
        (
            "node",
            Box::new(|t| set_line(t, 3, "   1    nan  0  0")),
            &["twobox.1.node line 3", "not finite"],
        ),
        (
            "node",
            Box::new(|t| set_line(t, 1, "99 3 0 0")),
            &["twobox.1.node line 1", "announces 99"],
        ),
        (
            "node",
            Box::new(|_| String::new()),
            &["twobox.1.node", "empty"],
        ),
        (
            "ele",
            Box::new(|t| set_line(t, 2, "    0      15    11     1")),
            &["twobox.1.ele line 2", "at least 5"],
        ),
        (
            "ele",
            Box::new(|_| "0 4 1\n".to_string()),
            &["twobox.1.ele", "no tetrahedra"],
        ),
        (
            "ele",
            Box::new(|t| set_line(t, 2, "    0      15    11     1     99    1")),
            &["twobox.1.ele line 2", "out of range"],
        ),
        (
            "ele",
            Box::new(|t| set_line(t, 2, "    0      15    11     1     -3    1")),
            &["twobox.1.ele line 2", "out of range"],
        ),
        (
            "ele",
            Box::new(|t| set_line(t, 2, "    0      11    15     1     9    1")),
            &["twobox.1.ele line 2", "inverted"],
        ),
        (
            "ele",
            Box::new(|t| set_line(t, 2, "    0      15    15     1     9    1")),
            &["twobox.1.ele line 2", "repeated vertex"],
        ),
        (
            "neigh",
            Box::new(|t| set_line(t, 2, "   0      23     4    35    40")),
            &["twobox.1.neigh line 2", "tetrahedron 0"],
        ),
        (
            "neigh",
            Box::new(|t| set_line(t, 2, "   0      23     4    35    420")),
            &["twobox.1.neigh line 2", "out of range"],
        ),
        (
            "face",
            Box::new(|t| set_line(t, 2, "    0      2     0     15    1")),
            &["twobox.1.face line 2", "not a face"],
        ),
    ];
    for (ext, edit, expect) in cases {
        let e = error(ext, edit);
        for part in expect {
            assert!(e.contains(part), "error '{e}' should mention '{part}'");
        }
    }
}

#[test]
fn flat_tetrahedra_are_named() {
    // Give point 9 the coordinates of point 15: tetrahedron 0 (15 11 1 9) becomes flat.
    let e = error("node", |t| set_line(t, 11, "9 2.5 2.5 2.5"));
    assert!(e.contains("flat"), "{e}");
    assert!(e.contains("twobox.1.ele line"), "{e}");
}

#[test]
fn a_missing_file_is_named() {
    let e = load_tetgen(Path::new("/nonexistent/mesh.1"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("/nonexistent/mesh.1.node") && e.contains("cannot read"),
        "{e}"
    );
}
