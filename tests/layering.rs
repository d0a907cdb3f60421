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
    ("process", &["child", "report", "staged"]),
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
            "octree", "registry", "scenes", "staged", "tet", "walk",
        ],
    ),
    (
        "kit",
        &[
            "backend", "cases", "choice", "engine", "family", "methods", "octree", "registry",
            "scenes", "tet",
        ],
    ),
    (
        "report",
        &[
            "cases", "choice", "engine", "exact", "family", "mesh", "octree", "tet", "walk",
        ],
    ),
    ("render", &["backend", "choice", "engine", "walk"]),
    (
        "cli",
        &[
            "backend", "choice", "engine", "exact", "family", "mesh", "octree", "process",
            "registry", "render", "report", "scenes", "staged", "walk",
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
        "render",
        "exact",
        "pictures judge nothing: the runs that return their data judged it",
    ),
    (
        "render",
        "registry",
        "pictures run no method: the families' engines walk the views",
    ),
    (
        "engine",
        "cli",
        "runs are a library; the command line drives them",
    ),
    (
        "cli",
        "methods",
        "the command line runs no method: the engine and the backends do",
    ),
    (
        "cli",
        "gpu",
        "the command line reaches the GPU through the backends",
    ),
    (
        "cli",
        "child",
        "the programs tetwalk runs are the engine's and the scenes' (and stopped by process)",
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

/// The files of a family's folder (`src/family/<name>/`) that belong to a later layer than the
/// family itself, by their name: how the family reads (`report.rs`), its command-line flags
/// (`cli.rs`), its conformance-kit entry point (`kit.rs`), what it runs beyond its `Family`
/// (`engine.rs`: a fuzz target's finding, a benchmark). The folder keeps a family together; each of its
/// files still imports only what its layer may.
const FOLDER_LAYERS: &[&str] = &["report", "cli", "kit", "engine"];

/// The layer (top-level module) a source file belongs to: its top-level module, or for a file of a
/// family's folder named in [`FOLDER_LAYERS`], that layer.
fn module_of(path: &str) -> String {
    let rel = path.split("/src/").nth(1).unwrap();
    let parts: Vec<&str> = rel.split('/').collect();
    if let ["family", _, file] = parts[..] {
        let stem = file.trim_end_matches(".rs");
        if FOLDER_LAYERS.contains(&stem) {
            return stem.to_string();
        }
    }
    rel.split(['/', '.']).next().unwrap().to_string()
}

/// A source's code: comments left out, string and character literals emptied (`""`, `' '`), so
/// that what messages and docs say is not read as code.
fn code(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < c.len() {
        let rest = |k: usize| c.get(i + k).copied();
        match c[i] {
            '/' if rest(1) == Some('/') => {
                while i < c.len() && c[i] != '\n' {
                    i += 1;
                }
            }
            '/' if rest(1) == Some('*') => {
                i += 2;
                while i + 1 < c.len() && !(c[i] == '*' && c[i + 1] == '/') {
                    i += 1;
                }
                i += 2;
            }
            // A raw string: r"…", r#"…"#, br"…".
            'r' if (rest(1) == Some('"') || rest(1) == Some('#'))
                && !ident_before(c[..i].strip_suffix(&['b']).unwrap_or(&c[..i])) =>
            {
                let mut j = i + 1;
                while c.get(j) == Some(&'#') {
                    j += 1;
                }
                if c.get(j) != Some(&'"') {
                    out.push(c[i]);
                    i += 1;
                    continue;
                }
                let hashes = j - i - 1;
                j += 1;
                while j < c.len()
                    && !(c[j] == '"' && (0..hashes).all(|h| c.get(j + 1 + h) == Some(&'#')))
                {
                    j += 1;
                }
                out += "\"\"";
                i = j + 1 + hashes;
            }
            '"' => {
                i += 1;
                while i < c.len() && c[i] != '"' {
                    i += if c[i] == '\\' { 2 } else { 1 };
                }
                out += "\"\"";
                i += 1;
            }
            // A character literal ('x', '\n', '\''), not a lifetime ('a).
            '\'' if rest(1) == Some('\\') => {
                i += 2;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                out += "' '";
                i += 1;
            }
            '\'' if rest(2) == Some('\'') => {
                out += "' '";
                i += 3;
            }
            ch => {
                out.push(ch);
                i += 1;
            }
        }
    }
    out
}

/// Whether `before` ends in a character of an identifier (so that an `r` after it is no raw string's).
fn ident_before(before: &[char]) -> bool {
    before
        .last()
        .is_some_and(|p| p.is_alphanumeric() || *p == '_')
}

/// The module path of a source file: `src/a/b.rs` and `src/a/b/mod.rs` are `[a, b]`.
fn module_path(path: &str) -> Vec<String> {
    let rel = path.split("/src/").nth(1).unwrap().trim_end_matches(".rs");
    let mut p: Vec<String> = rel.split('/').map(String::from).collect();
    if p.last().is_some_and(|l| l == "mod") {
        p.pop();
    }
    p
}

/// The layer a module path (from the crate root) belongs to, as [`module_of`] says of files.
fn layer_of(path: &[String]) -> String {
    match path {
        [f, _, file, ..] if f == "family" && FOLDER_LAYERS.contains(&file.as_str()) => file.clone(),
        [first, ..] => first.clone(),
        [] => String::new(),
    }
}

/// The identifier at the start of `s`.
fn ident(s: &str) -> String {
    s.chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect()
}

/// The layers a source's code imports: every `crate::NAME`, and every `super::NAME` (or
/// `super::super::…`, or `super::{NAME, …}`) resolved from the file's own module path.
fn imports(path: &str, text: &str) -> BTreeSet<String> {
    let code = code(text);
    let mut out: BTreeSet<String> = code
        .match_indices("crate::")
        .map(|(i, _)| ident(&code[i + 7..]))
        .collect();
    let me = module_path(path);
    let mut at = 0;
    while let Some(i) = code[at..].find("super::") {
        let start = at + i;
        let before = code[..start].chars().last();
        let mut rest = &code[start..];
        let mut ups = 0;
        while let Some(r) = rest.strip_prefix("super::") {
            ups += 1;
            rest = r;
        }
        at = code.len() - rest.len();
        // Only a path's first `super::` (not `a::super::`, which Rust does not allow anyway).
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let name = ident(rest.trim_start_matches(['{', ' ', '\n']));
        let mut target: Vec<String> = me[..me.len().saturating_sub(ups)].to_vec();
        target.push(name);
        out.insert(layer_of(&target));
    }
    out
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
        for dep in imports(path, text) {
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

/// The families' list (`families!` in `src/family/mod.rs`): each line's `Kind` variant and type.
fn families() -> Vec<(String, String)> {
    let list =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/family/mod.rs"))
            .unwrap();
    let out: Vec<(String, String)> = list
        .lines()
        .filter_map(|l| {
            let (variant, rest) = l.trim().split_once(" => \"")?;
            let ty = rest.split_once("$crate::family::")?.1.split(',').next()?;
            Some((variant.to_string(), ty.to_string()))
        })
        .collect();
    assert!(out.len() >= 4, "families! read as {out:?}");
    out
}

/// The family folders, `src/family/<name>/`.
fn family_folders() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/family");
    let mut out: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    out.sort();
    out
}

/// The families' method registries and their method types (`src/registry.rs`): a family's methods are
/// reached through [`Family::methods`] everywhere else.
const REGISTRIES: &[&str] = &[
    "METHODS",
    "USER_WGSL",
    "TRIANGLE_METHODS",
    "TriangleMethod",
    "OCTREE_METHODS",
    "OctreeMethod",
];

/// Files outside the family folders that may name families, and why: data, not code paths.
const DATA_TABLES: &[(&str, &str)] = &[
    (
        "src/engine/verify.rs",
        "the claims register: each check names its family, method and backend",
    ),
    (
        "src/engine/paper.rs",
        "the seeds' tables: each reproduces one paper's measurement of the family that paper studies (seed 000's Table 4 and Table 5 of walks, seed 001's octree counts, seed 004's Figure 5 of ray-triangle tests), beside the paper's own numbers",
    ),
];

/// What in a source's code names a concrete family: its type, its `Kind`/`CountKind`/`of` variant,
/// its folder's module (`family::NAME`, or `super::NAME` from within `src/family/`), its registry.
fn names_a_family(path: &str, text: &str) -> Vec<String> {
    let code = code(text);
    let families = families();
    let folders = family_folders();
    let in_family = path.contains("/src/family/");
    let mut seen = BTreeSet::new();
    let mut i = 0;
    while let Some(c) = code[i..].chars().next() {
        if !(c.is_alphanumeric() || c == '_') {
            i += c.len_utf8();
            continue;
        }
        let word = ident(&code[i..]);
        let before = &code[..i];
        let owner = before
            .strip_suffix("::")
            .map(|b| {
                let s = b.trim_end_matches(|c: char| c.is_alphanumeric() || c == '_');
                &b[s.len()..]
            })
            .unwrap_or("");
        if families.iter().any(|(_, ty)| *ty == word) {
            seen.insert(word.clone());
        }
        if ["Kind", "CountKind", "of"].contains(&owner) && families.iter().any(|(v, _)| *v == word)
        {
            seen.insert(format!("{owner}::{word}"));
        }
        if (owner == "family" || (owner == "super" && in_family)) && folders.contains(&word) {
            seen.insert(format!("{owner}::{word}"));
        }
        if REGISTRIES.contains(&word.as_str()) {
            seen.insert(word.clone());
        }
        i += word.len();
    }
    seen.into_iter().collect()
}

#[test]
fn no_file_outside_a_family_folder_names_a_family() {
    let mut files = Vec::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    sources(&root.join("src"), &mut files);
    let folders = family_folders();
    let mut naming = BTreeSet::new();
    let mut said = Vec::new();
    for (path, text) in &files {
        let rel = path
            .split_once("/src/")
            .map(|(_, r)| format!("src/{r}"))
            .unwrap();
        let layer = module_of(path);
        let in_folder = folders
            .iter()
            .any(|f| rel.starts_with(&format!("src/family/{f}/")));
        // The layers above the families, and the family layer's own generic files; the list itself
        // (`src/family/mod.rs`) names every family once.
        let checked = ["engine", "kit", "report", "render", "cli"].contains(&layer.as_str())
            || (layer == "family" && rel != "src/family/mod.rs");
        if !checked || in_folder || DATA_TABLES.iter().any(|(f, _)| *f == rel) {
            continue;
        }
        let names = names_a_family(path, text);
        if !names.is_empty() {
            said.push(format!("{rel}: {}", names.join(", ")));
            naming.insert(rel);
        }
    }
    assert!(
        naming.is_empty(),
        "files outside a family's folder name a family: {naming:?}\n{}",
        said.join("\n")
    );
}

#[test]
fn the_family_rule_sees_what_it_should() {
    let f = "/x/src/cli/foo.rs";
    let names = |text| names_a_family(f, text);
    assert_eq!(
        names("use crate::family::{Family, Triangle};"),
        ["Triangle"]
    );
    assert_eq!(names("let k = Kind::Octree;"), ["Kind::Octree"]);
    assert_eq!(
        names("use crate::family::triangle::bins;"),
        ["family::triangle"]
    );
    assert_eq!(
        names("for m in crate::registry::OCTREE_METHODS {}"),
        ["OCTREE_METHODS"]
    );
    assert!(names("// Triangle in a comment\nlet x = \"Triangle\";").is_empty());
    assert!(
        names("let m = \"the bins (family::triangle::bins)\"; let c = '\"'; /* Walks */")
            .is_empty()
    );
    assert!(names("let s = r#\"a \"quoted\" OctreeCells\"#;").is_empty());
    assert_eq!(names("let s = br\"\\\"; let t = Triangle;"), ["Triangle"]);
    assert_eq!(names("let c = '\\''; let w: Walks = x;"), ["Walks"]);
    assert_eq!(names("fn f<'a>(x: &'a Triangle) {}"), ["Triangle"]);
    assert!(names("fn run<F: Family>(k: Kind) { with_family!(k, F => go::<F>()) }").is_empty());
    assert_eq!(
        names_a_family("/x/src/family/count.rs", "use super::walk::WalkTruth;"),
        ["super::walk"]
    );
    assert_eq!(
        imports(
            "/x/src/family/triangle/report.rs",
            "use super::{Hits, Triangle};\nuse super::super::count::Counts;"
        ),
        ["family".to_string()].into_iter().collect()
    );
    assert_eq!(
        imports(
            "/x/src/report/stress.rs",
            "use super::lines::Said;\nuse crate::engine::count::CountReport;"
        ),
        ["engine".to_string(), "report".to_string()]
            .into_iter()
            .collect()
    );
}
