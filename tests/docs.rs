//! The documentation holds to the repository and the program: every path it names is in a fresh
//! clone, each command's page lists exactly the flags of its `--help`, every command line it shows
//! parses, its `console` examples run and print what they show, every page is in the book, the README
//! stays short, and the guide shows the routes script word for word.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");
const BIN: &str = env!("CARGO_BIN_EXE_tetwalk");

/// The documentation's markdown files, relative to the root: the README, the changelog and the guide.
fn pages() -> Vec<PathBuf> {
    let mut out = vec![PathBuf::from("README.md"), PathBuf::from("CHANGELOG.md")];
    let mut dirs = vec![PathBuf::from("docs")];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(Path::new(ROOT).join(&d)).unwrap() {
            let p = d.join(e.unwrap().file_name());
            if Path::new(ROOT).join(&p).is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "md") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(Path::new(ROOT).join(p)).unwrap()
}

/// Files a fresh clone has: tracked, or not yet tracked but not ignored (what the next commit adds).
/// An ignored file, which a clone would lack, is not among them.
fn in_a_clone() -> BTreeSet<String> {
    let out = Command::new("git")
        .args(["ls-files", "--cached", "--others", "--exclude-standard"])
        .current_dir(ROOT)
        .output()
        .expect("git runs (the documentation's paths are checked against the repository)");
    assert!(out.status.success(), "git ls-files failed in {ROOT}");
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect()
}

/// The first-level names a repository path in the docs starts with.
const ROOTS: [&str; 14] = [
    "src/",
    "tests/",
    "corpora/",
    "examples/",
    "scripts/",
    "fuzz/",
    "docs/",
    "golden/",
    "proofs/",
    "benches/",
    ".ci/",
    ".github/",
    ".clusterfuzzlite/",
    ".cargo/",
];
const ROOT_FILES: [&str; 5] = [
    "README.md",
    "CHANGELOG.md",
    "Cargo.toml",
    "Cargo.lock",
    "build.rs",
];

/// The part of a path written in the docs that names something fixed: cut at a glob, a brace list, a
/// `<placeholder>` or an upper-case `NAME` component (`NAME.wgsl` too; `README.md` is a name).
fn fixed_prefix(path: &str) -> &str {
    let mut end = path.find(['*', '{', '<', '…']).unwrap_or(path.len());
    let mut at = 0;
    for comp in path[..end].split('/') {
        let stem = comp.split('.').next().unwrap_or("");
        let placeholder = !stem.is_empty()
            && stem.chars().all(|c| c.is_ascii_uppercase() || c == '_')
            && !["README", "CHANGELOG", "LICENSE"].contains(&stem);
        if placeholder {
            end = at;
            break;
        }
        at += comp.len() + 1;
    }
    &path[..end.min(path.len())]
}

/// Spans between backticks, and link targets, of a markdown text.
fn quoted(text: &str) -> Vec<String> {
    let mut out: Vec<String> = text
        .split('`')
        .skip(1)
        .step_by(2)
        .flat_map(|s| s.split_whitespace().map(str::to_string).collect::<Vec<_>>())
        .collect();
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        if let Some(j) = rest.find(')') {
            out.push(format!("link:{}", &rest[..j]));
        }
    }
    out
}

#[test]
fn every_path_the_docs_name_is_in_a_fresh_clone() {
    let files = in_a_clone();
    let exists = |p: &str| {
        let p = p.trim_end_matches('/');
        files.contains(p) || files.iter().any(|f| f.starts_with(p))
    };
    let mut missing = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let dir = page.parent().unwrap_or(Path::new(""));
        for token in quoted(&read(&page)) {
            let (path, link) = match token.strip_prefix("link:") {
                Some(target) => {
                    if target.contains("://") || target.starts_with('#') {
                        continue;
                    }
                    let target = target.split('#').next().unwrap();
                    let joined = dir.join(target);
                    let mut parts: Vec<String> = Vec::new();
                    for c in joined.components() {
                        match c {
                            std::path::Component::ParentDir => {
                                parts.pop();
                            }
                            std::path::Component::Normal(n) => {
                                parts.push(n.to_string_lossy().into_owned())
                            }
                            _ => {}
                        }
                    }
                    (parts.join("/"), true)
                }
                None => (
                    token
                        .trim_matches(|c: char| ",.;:()\"'".contains(c))
                        .to_string(),
                    false,
                ),
            };
            let named = link
                || ROOTS.iter().any(|r| path.starts_with(r))
                || ROOT_FILES.contains(&path.as_str());
            if !named {
                continue;
            }
            let fixed = fixed_prefix(&path);
            if fixed.is_empty() {
                continue;
            }
            checked += 1;
            if !exists(fixed) {
                missing.push(format!("{}: {path}", page.display()));
            }
        }
    }
    assert!(checked > 200, "only {checked} paths found in the docs");
    assert!(
        missing.is_empty(),
        "paths the docs name that a fresh clone lacks:\n{}",
        missing.join("\n")
    );
}

/// The fixed-prefix rule: globs, brace lists, placeholders and NAME components end a path's fixed part.
#[test]
fn paths_are_cut_at_their_placeholders() {
    assert_eq!(
        fixed_prefix("corpora/scenes/bunny-paper.*"),
        "corpora/scenes/bunny-paper."
    );
    assert_eq!(fixed_prefix("src/methods/NAME.wgsl"), "src/methods/");
    assert_eq!(fixed_prefix("corpora/found/<method>/"), "corpora/found/");
    assert_eq!(fixed_prefix("src/gpu/tetwalk.wgsl"), "src/gpu/tetwalk.wgsl");
    assert_eq!(fixed_prefix("examples/README.md"), "examples/README.md");
}

/// Runs tetwalk with `args`: status, standard output, standard error.
fn tetwalk(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(BIN).args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The subcommands a help text lists (`help` aside).
fn subcommands(help: &str) -> Vec<String> {
    help.split("Commands:")
        .nth(1)
        .map(|s| {
            s.lines()
                .skip(1)
                .take_while(|l| !l.trim().is_empty())
                .filter_map(|l| l.split_whitespace().next())
                .filter(|&c| c != "help")
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default()
}

/// The long flags a help text defines (`--help` and `--version` aside).
fn flags(help: &str) -> BTreeSet<String> {
    help.lines()
        .filter_map(|l| {
            let l = l.trim_start();
            let l = l.strip_prefix("-h, ").unwrap_or(l);
            let l = match l.get(..4) {
                Some(s) if s.starts_with('-') && s.ends_with(", ") => &l[4..],
                _ => l,
            };
            let flag: String = l
                .strip_prefix("--")?
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            (!flag.is_empty() && flag != "help" && flag != "version").then(|| format!("--{flag}"))
        })
        .collect()
}

/// The flags written in a text.
fn flags_in(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let b = text.as_bytes();
    for (i, _) in text.match_indices("--") {
        if i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'-') {
            continue;
        }
        let name: String = text[i + 2..]
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
            .collect();
        if name.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
            out.insert(format!("--{name}"));
        }
    }
    out
}

/// The first fenced ```text block of a page: its synopsis.
fn synopsis(page: &str) -> &str {
    page.split("```text\n")
        .nth(1)
        .and_then(|s| s.split("```").next())
        .unwrap_or("")
}

#[test]
fn each_command_page_lists_the_flags_of_its_help() {
    let (_, top, _) = tetwalk(&["--help"]);
    let commands = subcommands(&top);
    assert!(commands.len() >= 18, "{top}");
    let mut wrong = Vec::new();
    for c in &commands {
        let page_path = PathBuf::from(format!("docs/commands/{c}.md"));
        let summary = read(Path::new("docs/SUMMARY.md"));
        assert!(
            summary.contains(&format!("(commands/{c}.md)")),
            "docs/SUMMARY.md lists no page for `{c}`"
        );
        assert!(
            Path::new(ROOT).join(&page_path).exists(),
            "no page for `tetwalk {c}`: {}",
            page_path.display()
        );
        let page = read(&page_path);
        let (_, help, _) = tetwalk(&[c, "--help"]);
        let mut defined = flags(&help);
        for sub in subcommands(&help) {
            let (_, h, _) = tetwalk(&[c, &sub, "--help"]);
            defined.extend(flags(&h));
            assert!(
                page.contains(&format!("{c} {sub}")),
                "{}: `tetwalk {c} {sub}` is not described",
                page_path.display()
            );
        }
        for f in &defined {
            if !page.contains(f.as_str()) {
                wrong.push(format!(
                    "{}: `{c} {f}` is not described",
                    page_path.display()
                ));
            }
        }
        for f in flags_in(synopsis(&page)) {
            if !defined.contains(&f) {
                wrong.push(format!(
                    "{}: the synopsis shows {f}, which `tetwalk {c} --help` lacks",
                    page_path.display()
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Shell-like words of a command line: quotes grouped, a `#` comment dropped.
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quote: Option<char> = None;
    let mut any = false;
    for ch in line.chars() {
        match (quote, ch) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => cur.push(c),
            (None, '\'' | '"') => {
                quote = Some(ch);
                any = true;
            }
            (None, '#') if cur.is_empty() && !any => break,
            (None, c) if c.is_whitespace() => {
                if any || !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                    any = false;
                }
            }
            (None, c) => {
                cur.push(c);
                any = true;
            }
        }
    }
    if any || !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// The code of a markdown text: indented blocks' lines and the `$ ` lines of `console` blocks.
fn code_lines(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fence: Option<String> = None;
    for line in text.lines() {
        if let Some(f) = line.trim_start().strip_prefix("```") {
            fence = match fence {
                None => Some(f.to_string()),
                Some(_) => None,
            };
            continue;
        }
        match &fence {
            Some(f) if f == "console" => {
                if let Some(c) = line.strip_prefix("$ ") {
                    out.push(c.to_string());
                }
            }
            Some(_) => {}
            None => {
                if let Some(c) = line.strip_prefix("    ") {
                    out.push(c.trim_start().to_string());
                }
            }
        }
    }
    out
}

/// The tetwalk invocations of a shell line: its pipeline's and list's parts that run tetwalk, as
/// arguments (`cargo run --release -- ARGS` counts; other programs do not).
fn invocations(line: &str) -> Vec<Vec<String>> {
    line.split(['|', ';'])
        .flat_map(|s| s.split("&&"))
        .filter_map(|part| {
            let part = part.split(['>', '<']).next().unwrap_or("");
            let w = words(part);
            let args = match w.first().map(String::as_str) {
                Some("tetwalk") => &w[1..],
                Some("cargo") if w.get(1).map(String::as_str) == Some("run") => {
                    let at = w.iter().position(|x| x == "--")?;
                    if w[..at].iter().any(|x| x == "-p" || x == "--example") {
                        return None;
                    }
                    &w[at + 1..]
                }
                _ => return None,
            };
            Some(args.to_vec())
        })
        .collect()
}

#[test]
fn every_command_line_in_the_docs_parses() {
    let mut checked = 0;
    let mut wrong = Vec::new();
    for page in pages() {
        for line in code_lines(&read(&page)) {
            for args in invocations(&line) {
                if args.is_empty() {
                    continue;
                }
                checked += 1;
                let mut a: Vec<&str> = args.iter().map(String::as_str).collect();
                a.push("--help");
                let (code, _, err) = tetwalk(&a);
                if code != 0 {
                    wrong.push(format!("{}: `{line}`: {err}", page.display()));
                }
            }
        }
    }
    assert!(checked > 40, "only {checked} command lines found");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Whether `got` is what an example shows: line by line, a `...` line standing for any lines and
/// `[..]` for any text within one.
fn matches(shown: &[&str], got: &[&str]) -> bool {
    match shown.split_first() {
        None => got.is_empty(),
        Some((&"...", rest)) => (0..=got.len()).any(|k| matches(rest, &got[k..])),
        Some((first, rest)) => got
            .split_first()
            .is_some_and(|(g, more)| line_matches(first, g) && matches(rest, more)),
    }
}

fn line_matches(shown: &str, got: &str) -> bool {
    let parts: Vec<&str> = shown.split("[..]").collect();
    if parts.len() == 1 {
        return shown == got;
    }
    let Some(mut rest) = got.strip_prefix(parts[0]) else {
        return false;
    };
    for (k, p) in parts.iter().enumerate().skip(1) {
        if k == parts.len() - 1 {
            return rest.ends_with(p);
        }
        match rest.find(p) {
            Some(i) => rest = &rest[i + p.len()..],
            None => return false,
        }
    }
    true
}

#[test]
fn example_output_wildcards_match_as_documented() {
    assert!(matches(&["a", "...", "z"], &["a", "b", "c", "z"]));
    assert!(matches(&["...", "z"], &["z"]));
    assert!(!matches(&["a", "z"], &["a", "b", "z"]));
    assert!(line_matches("x [..] y", "x 1 2 y"));
    assert!(!line_matches("x [..] y", "x 1 2 z"));
}

#[test]
fn the_docs_console_examples_run_as_shown() {
    let bin_dir = Path::new(BIN).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut ran = 0;
    let mut wrong = Vec::new();
    for page in pages() {
        let text = read(&page);
        for block in text.split("```console\n").skip(1) {
            let block = block.split("```").next().unwrap();
            let work = tempfile::tempdir().unwrap();
            let mut steps: Vec<(String, Vec<&str>)> = Vec::new();
            for line in block.lines() {
                match line.strip_prefix("$ ") {
                    Some(cmd) => steps.push((cmd.to_string(), Vec::new())),
                    None => steps
                        .last_mut()
                        .expect("a block starts with $")
                        .1
                        .push(line),
                }
            }
            for (cmd, shown) in steps {
                ran += 1;
                let out = Command::new("bash")
                    .args(["-c", &cmd])
                    .current_dir(work.path())
                    .env("PATH", &path)
                    .output()
                    .unwrap();
                let got = String::from_utf8_lossy(&out.stdout);
                let got: Vec<&str> = got.lines().collect();
                if !out.status.success() || !matches(&shown, &got) {
                    wrong.push(format!(
                        "{}: `{cmd}` ({}) printed:\n{}\n{}",
                        page.display(),
                        out.status,
                        got.join("\n"),
                        String::from_utf8_lossy(&out.stderr)
                    ));
                }
            }
        }
    }
    assert!(ran >= 5, "only {ran} examples found");
    assert!(wrong.is_empty(), "{}", wrong.join("\n\n"));
}

#[test]
fn every_page_of_the_guide_is_in_its_summary() {
    let summary = read(Path::new("docs/SUMMARY.md"));
    for page in pages() {
        let Ok(rel) = page.strip_prefix("docs") else {
            continue;
        };
        let rel = rel.display().to_string();
        if rel == "SUMMARY.md" {
            continue;
        }
        assert!(
            summary.contains(&format!("({rel})")),
            "docs/SUMMARY.md does not list {rel}"
        );
    }
}

/// The README: at most 150 lines, its two commands those of the guide and of CI word for word.
#[test]
fn the_readme_is_short_and_its_two_commands_are_the_real_ones() {
    let readme = read(Path::new("README.md"));
    let lines = readme.lines().count();
    assert!(lines <= 150, "README.md has {lines} lines");
    let main_job = "    bash .ci/setup && cargo run --release -- count";
    let tests = "    cargo test --release";
    for text in [&readme, &read(Path::new("docs/introduction.md"))] {
        assert!(text.lines().any(|l| l == main_job));
        assert!(text.lines().any(|l| l == tests));
    }
    let ci = read(Path::new(".ci/run"));
    assert!(ci.lines().any(|l| l.trim() == "bash .ci/setup"));
    assert!(ci.lines().any(|l| l.trim() == tests.trim()));
}

/// The guide's "Judging your own traversal" (`docs/your-own.md`) shows exactly the commands
/// `examples/conformance/routes.sh` runs (CI runs the script), in the same order.
#[test]
fn the_guide_shows_the_routes_script_word_for_word() {
    let section = read(Path::new("docs/your-own.md"));
    let script = read(Path::new("examples/conformance/routes.sh"));
    let shown: Vec<&str> = section
        .lines()
        .filter_map(|l| l.strip_prefix("    "))
        .collect();
    let run: Vec<&str> = script
        .lines()
        .filter(|l| l.starts_with("cargo ") || l.starts_with("out="))
        .collect();
    assert!(run.len() >= 10, "the script runs the three routes");
    assert_eq!(shown, run);
}
