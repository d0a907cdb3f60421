//! The architecture, checked: each top-level module imports only the modules its row of [`ALLOWED`]
//! names (code, not comments), the allowed edges form no circle, the rules of [`NEVER`] hold in the
//! table itself, and command-line types (clap, indicatif) live only in `src/cli/`.

use std::collections::BTreeSet;
use std::path::Path;

/// Each module and the modules it may import. Data flows one way: geometry and the oracle, then the
/// methods, walks and registry, the backends, the families, the engine's runs, and last what shows
/// them (reports, renders) and the command line.
const ALLOWED: &[(&str, &[&str])] = &[
    ("staged", &[]),
    ("child", &[]),
    ("fpenv", &[]),
    ("tet", &[]),
    ("choice", &[]),
    ("mesh", &["tet"]),
    ("octree", &["tet"]),
    ("exact", &["fpenv", "mesh", "octree", "tet"]),
    (
        "scenes",
        &[
            "child", "choice", "exact", "mesh", "octree", "staged", "tet",
        ],
    ),
    ("methods", &["choice", "exact", "fpenv", "octree", "tet"]),
    (
        "walk",
        &[
            "choice", "exact", "fpenv", "mesh", "methods", "octree", "tet",
        ],
    ),
    ("registry", &["exact", "methods", "octree", "tet", "walk"]),
    ("cases", &["exact", "methods", "scenes", "tet"]),
    (
        "gpu",
        &[
            "choice", "mesh", "methods", "octree", "registry", "tet", "walk",
        ],
    ),
    (
        "backend",
        &[
            "cases", "choice", "fpenv", "gpu", "mesh", "methods", "octree", "registry", "tet",
            "walk",
        ],
    ),
    (
        "family",
        &[
            "backend", "cases", "choice", "exact", "mesh", "methods", "octree", "registry",
            "scenes", "tet", "walk",
        ],
    ),
    (
        "engine",
        &[
            "backend", "cases", "child", "choice", "exact", "family", "fpenv", "mesh", "methods",
            "octree", "registry", "scenes", "tet", "walk",
        ],
    ),
    (
        "kit",
        &[
            "backend", "choice", "engine", "family", "methods", "octree", "registry", "scenes",
            "tet",
        ],
    ),
    (
        "report",
        &[
            "cases", "choice", "engine", "exact", "family", "mesh", "octree", "tet", "walk",
        ],
    ),
    (
        "render",
        &[
            "backend", "cases", "choice", "exact", "mesh", "methods", "octree", "registry",
            "scenes", "tet", "walk",
        ],
    ),
    (
        "cli",
        &[
            "backend", "cases", "child", "choice", "engine", "exact", "family", "gpu", "mesh",
            "methods", "octree", "registry", "render", "report", "scenes", "staged", "tet", "walk",
        ],
    ),
];

/// Edges that must never be allowed, and why.
const NEVER: &[(&str, &str, &str)] = &[
    (
        "report",
        "backend",
        "reports format what runs returned; they open and run nothing",
    ),
    (
        "report",
        "gpu",
        "reports format; only backends talk to the GPU",
    ),
    (
        "report",
        "registry",
        "reports name methods as runs recorded them",
    ),
    (
        "methods",
        "scenes",
        "methods are plain functions over plain data; generators feed them",
    ),
    ("methods", "backend", "a method never knows where it runs"),
    ("exact", "methods", "the oracle never calls a method"),
    (
        "family",
        "engine",
        "a family says what is asked; the engine runs it",
    ),
    ("engine", "report", "runs compute; reports only format"),
    (
        "engine",
        "cli",
        "runs are a library; the command line drives them",
    ),
    (
        "kit",
        "report",
        "the kit is a library a user's cargo test links",
    ),
    (
        "kit",
        "gpu",
        "the kit runs on the CPU, without the GPU feature",
    ),
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

/// Every `crate::NAME` a source's code names (comments left out).
fn imports(text: &str) -> BTreeSet<String> {
    let code: String = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n");
    code.match_indices("crate::")
        .map(|(i, _)| {
            code[i + 7..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect()
        })
        .collect()
}

fn allowed(module: &str) -> Option<&'static [&'static str]> {
    ALLOWED.iter().find(|(m, _)| *m == module).map(|(_, a)| *a)
}

#[test]
fn modules_import_only_what_their_row_allows() {
    let mut files = Vec::new();
    sources(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    let modules: BTreeSet<String> = ALLOWED.iter().map(|(m, _)| m.to_string()).collect();
    let mut wrong = Vec::new();
    for (path, text) in &files {
        let me = module_of(path);
        // The crate root and the binaries (src/main.rs, src/bin/) use the library from outside.
        if me == "lib" || me == "main" || me == "bin" {
            continue;
        }
        let mine =
            allowed(&me).unwrap_or_else(|| panic!("{path}: module {me} has no row in ALLOWED"));
        for dep in imports(text) {
            if dep == me || !modules.contains(&dep) {
                continue;
            }
            if !mine.contains(&dep.as_str()) {
                wrong.push(format!(
                    "{path}: {me} imports {dep}, which its row does not allow"
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn the_allowed_edges_form_no_circle() {
    // Repeatedly take out a module whose allowed imports are all taken out already.
    let mut left: Vec<&str> = ALLOWED.iter().map(|(m, _)| *m).collect();
    let mut done: Vec<&str> = Vec::new();
    while !left.is_empty() {
        let next = left
            .iter()
            .position(|m| allowed(m).unwrap().iter().all(|d| done.contains(d)));
        let Some(i) = next else {
            panic!("an import circle among {left:?}");
        };
        done.push(left.remove(i));
    }
    for (m, deps) in ALLOWED {
        for d in *deps {
            assert!(allowed(d).is_some(), "{m} allows {d}, which has no row");
        }
    }
}

#[test]
fn no_allowed_edge_breaks_a_rule() {
    for (from, to, why) in NEVER {
        assert!(
            !allowed(from).unwrap().contains(to),
            "{from} may import {to}, but {why}"
        );
    }
}

#[test]
fn command_line_types_live_only_in_src_cli() {
    let mut files = Vec::new();
    sources(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    for (path, text) in &files {
        if module_of(path) == "cli" || path.ends_with("/main.rs") || path.contains("/bin/") {
            continue;
        }
        for t in ["clap::", "indicatif::"] {
            assert!(!text.contains(t), "{path} uses {t}");
        }
    }
}
