//! The architecture, checked: the crate's top-level modules import only modules earlier in the data
//! flow (so there is no import circle), and command-line types (clap, indicatif) live only in
//! `src/cli/`.

use std::collections::BTreeSet;
use std::path::Path;

/// The data flow, upstream first, as src/lib.rs states it.
const ORDER: [&str; 19] = [
    "staged",
    "fpenv",
    "tet",
    "choice",
    "mesh",
    "octree",
    "exact",
    "scenes",
    "methods",
    "walk",
    "registry",
    "cases",
    "gpu",
    "backend",
    "found",
    "report",
    "conformance",
    "render",
    "cli",
];

fn sources(dir: &Path, out: &mut Vec<(String, String)>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push((
                p.display().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            ));
        }
    }
}

/// The top-level module a source file belongs to.
fn module_of(path: &str) -> String {
    let rel = path.split("/src/").nth(1).unwrap();
    rel.split(['/', '.']).next().unwrap().to_string()
}

/// Every `crate::NAME` a source names (code and doc links alike).
fn imports(text: &str) -> BTreeSet<String> {
    text.match_indices("crate::")
        .map(|(i, _)| {
            text[i + 7..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect()
        })
        .collect()
}

#[test]
fn modules_import_only_upstream_modules() {
    let mut files = Vec::new();
    sources(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    let rank = |m: &str| ORDER.iter().position(|x| *x == m);
    let mut wrong = Vec::new();
    for (path, text) in &files {
        let me = module_of(path);
        if me == "lib" || me == "main" {
            continue;
        }
        let mine = rank(&me).unwrap_or_else(|| panic!("{path}: module {me} is not in ORDER"));
        for dep in imports(text) {
            let Some(theirs) = rank(&dep) else { continue };
            if theirs > mine {
                wrong.push(format!("{path}: {me} imports {dep}, which is downstream"));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn command_line_types_live_only_in_src_cli() {
    let mut files = Vec::new();
    sources(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    for (path, text) in &files {
        if module_of(path) == "cli" || path.ends_with("/main.rs") {
            continue;
        }
        for t in ["clap::", "indicatif::"] {
            assert!(!text.contains(t), "{path} uses {t}");
        }
    }
}
