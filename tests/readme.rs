//! README's "Judging your own traversal" shows exactly the commands `examples/conformance/routes.sh`
//! runs (CI runs the script), in the same order.

#[test]
fn the_readme_shows_the_routes_script_word_for_word() {
    let root = env!("CARGO_MANIFEST_DIR");
    let readme = std::fs::read_to_string(format!("{root}/README.md")).unwrap();
    let script = std::fs::read_to_string(format!("{root}/examples/conformance/routes.sh")).unwrap();
    let section = readme
        .split("## Judging your own traversal")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("the README has the section");
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
