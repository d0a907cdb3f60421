//! `tetwalk fuzz-import`: turn fuzzer artifacts into readable found cases under `corpora/found/`.

use super::{JsonOut, Outcome};
use crate::cases::{HitCase, Subject};
use crate::found::{
    Record, fuzz_find, octree_walk_find, required_methods, required_octree_methods,
    required_triangle_methods,
};
use crate::scenes::from_bytes::{cell_case, exit_case, hit_case, walk_case};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The fuzz target that found them.
    #[arg(long, value_parser = ["exit_face", "walk", "triangle_hit", "octree_cell", "octree_walk"])]
    target: String,
    /// Where found cases go (one folder per method).
    #[arg(long, default_value = "corpora/found")]
    out: PathBuf,
    /// Also write the files filed as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Artifacts (crash files) written by `cargo fuzz`, or found cases (`.json`) to file again.
    artifacts: Vec<PathBuf>,
}

pub fn run(a: Args) -> Outcome {
    // The same methods the fuzz run held to exactness (TETWALK_FUZZ_METHOD), on the same backend
    // (TETWALK_FUZZ_BACKEND: the CPU plain and fused, or a GPU with each case's neighbourhood), as the
    // fuzz targets do.
    let held: Vec<&str> = match a.target.as_str() {
        "triangle_hit" => required_triangle_methods()?
            .0
            .iter()
            .map(|m| m.name)
            .collect(),
        "octree_cell" | "octree_walk" => {
            required_octree_methods()?.iter().map(|m| m.name).collect()
        }
        _ => required_methods()?.iter().map(|m| m.name).collect(),
    };
    let json = JsonOut::new(a.json.as_deref())?;
    let mut filed = Vec::new();
    for path in &a.artifacts {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut u = arbitrary::Unstructured::new(&bytes);
        let subject = if path.extension().is_some_and(|e| e == "json") {
            let text = String::from_utf8_lossy(&bytes);
            Some(
                Record::parse(text.trim())
                    .map_err(|e| format!("{}: {e}", path.display()))?
                    .subject,
            )
        } else if a.target == "exit_face" {
            exit_case(&mut u).ok().flatten().map(Subject::Exit)
        } else if a.target == "octree_cell" {
            cell_case(&mut u).ok().map(|(lo, hi, r)| {
                Subject::Box(crate::cases::BoxCase {
                    lo,
                    hi,
                    org: r.org,
                    dir: r.dir,
                })
            })
        } else if a.target == "octree_walk" {
            None
        } else if a.target == "triangle_hit" {
            hit_case(&mut u)
                .ok()
                .and_then(|(mesh, ray)| HitCase::closed(&mesh, ray).ok())
                .map(Subject::Hit)
        } else {
            walk_case(&mut u).ok().map(Subject::Walk)
        };
        let found = if a.target == "octree_walk" && subject.is_none() {
            // A walk's finding is the box case of its first wrong cell.
            match hit_case(&mut arbitrary::Unstructured::new(&bytes)) {
                Ok((mesh, ray)) => {
                    octree_walk_find(&mesh, &ray).map_err(|e| format!("{}: {e}", path.display()))?
                }
                Err(_) => None,
            }
        } else {
            match subject {
                Some(s) => fuzz_find(&s).map_err(|e| format!("{}: {e}", path.display()))?,
                None => None,
            }
        };
        let Some(found) = found else {
            eprintln!(
                "{}: does not fail (any more) for {:?}",
                path.display(),
                held
            );
            continue;
        };
        let name = path.file_stem().and_then(|n| n.to_str()).unwrap_or("case");
        let stem = name.rsplit('-').next().unwrap_or(name);
        for record in found.with_robust_failures()? {
            let f = record
                .failure
                .as_ref()
                .expect("a found case records its failure");
            let dir = a.out.join(&f.method);
            std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            let file = dir.join(format!(
                "{}-{}-{}.json",
                a.target,
                f.kind().wrong_key(),
                &stem[..stem.len().min(12)]
            ));
            crate::staged::write(&file, (record.to_json() + "\n").as_bytes())
                .map_err(|e| format!("{}: {e}", file.display()))?;
            println!(
                "{}: {} {} ({})",
                file.display(),
                f.method,
                f.kind().wrong(),
                crate::choice::Choice::name(f.backend)
            );
            filed.push(file.display().to_string());
        }
    }
    json.finish(&serde_json::json!({ "filed": filed }))?;
    Ok(ExitCode::SUCCESS)
}
