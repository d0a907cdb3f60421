//! `tetwalk fuzz-import`: turn fuzzer artifacts into readable found cases under `corpora/found/`.

use crate::found::{Finding, check_exit, check_walk, required_methods};
use crate::scenes::from_bytes::{exit_case, walk_case};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The fuzz target that found them.
    #[arg(long, value_parser = ["exit_face", "walk"])]
    target: String,
    /// Where found cases go (one folder per method).
    #[arg(long, default_value = "corpora/found")]
    out: PathBuf,
    /// Artifacts (crash files) written by `cargo fuzz`, or found cases (`.json`) to file again.
    artifacts: Vec<PathBuf>,
}

pub fn run(a: Args) -> Result<ExitCode, String> {
    // The same methods the fuzz run held to exactness (TETWALK_FUZZ_METHOD).
    let methods = required_methods()?;
    for path in &a.artifacts {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut u = arbitrary::Unstructured::new(&bytes);
        let finding = if path.extension().is_some_and(|e| e == "json") {
            Some(Finding::from_json(&String::from_utf8_lossy(&bytes))?)
        } else if a.target == "exit_face" {
            exit_case(&mut u)
                .ok()
                .flatten()
                .and_then(|c| check_exit(&c, &methods).map(|f| Finding::exit(&c, f)))
        } else {
            walk_case(&mut u)
                .ok()
                .and_then(|c| check_walk(&c, &methods).map(|f| Finding::walk(&c, f)))
        };
        let Some(finding) = finding else {
            eprintln!(
                "{}: does not fail (any more) for {:?}",
                path.display(),
                methods.iter().map(|m| m.name).collect::<Vec<_>>()
            );
            continue;
        };
        let name = path.file_stem().and_then(|n| n.to_str()).unwrap_or("case");
        let stem = name.rsplit('-').next().unwrap_or(name);
        for finding in finding.with_robust_failures() {
            let f = finding.failure();
            let dir = a.out.join(&f.method);
            std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            let file = dir.join(format!(
                "{}-{}-{}.json",
                a.target,
                f.kind,
                &stem[..stem.len().min(12)]
            ));
            let text = serde_json::to_string(&finding).map_err(|e| e.to_string())?;
            std::fs::write(&file, text + "\n").map_err(|e| format!("{}: {e}", file.display()))?;
            let how = if f.fma { "fma" } else { "plain" };
            println!("{}: {} {} ({how})", file.display(), f.method, f.kind);
        }
    }
    Ok(ExitCode::SUCCESS)
}
