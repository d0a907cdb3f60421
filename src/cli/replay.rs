//! `tetwalk replay`: answer the wrong rays of a `count --dump` again, every family's, and say whether
//! each still fails the same way (the same method on the same backend stopping at the same place, and
//! still wrong);
//! with `--found`, the same for found cases (on their backend, and for a GPU finding on its adapter).

use super::{JsonOut, Status};
use crate::backend::{Backend, BackendKind};
use crate::cases::object;
use crate::engine::count::{Reanswered, Rerun, RerunError, rerun};
use crate::engine::found::{Found, FoundError, Replay, replay};
use crate::family::wrong::WrongRay;
use crate::family::{Family, owner};
use crate::mesh::Mesh;
use std::collections::HashMap;
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// A dump written by `tetwalk count --dump`, or with `--found` found cases (files of JSON lines).
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// The files hold found cases (`corpora/found/`), not a count's dump.
    #[arg(long)]
    found: bool,
    /// The dump's scene has no constrained faces (it was counted with --no-faces).
    #[arg(long)]
    no_faces: bool,
    /// Also write the summary (lines, still failing the same way, changed, skipped) as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .inputs("FILES", &self.files)
            .output("--json", self.json.as_deref())
    }
}

#[derive(Default, serde::Serialize)]
struct Summary {
    lines: u64,
    same: u64,
    changed: u64,
    skipped: u64,
}

/// Replay one found case of family `F`: how it replays now, and the method that failed on it.
fn replayed<F: Family>(
    obj: serde_json::Map<String, serde_json::Value>,
) -> Result<(Replay, Option<String>), FoundError> {
    let r = Found::<F>::from_object(obj)?;
    Ok((replay(&r)?, r.failure.map(|f| f.method)))
}

/// Replay found cases: each must fail again on its backend with its recorded answer.
fn found(a: &Args) -> Status {
    let out = JsonOut::new(a.json.as_deref())?;
    let mut summary = Summary::default();
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    for path in &a.files {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        for (n, line) in text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty())
        {
            let place =
                |e: &dyn std::fmt::Display| format!("{} line {}: {e}", path.display(), n + 1);
            let obj = object(line).map_err(|e| place(&e))?;
            let (now, method) =
                crate::with_family!(owner(&obj), F => replayed::<F>(obj)).map_err(|e| place(&e))?;
            summary.lines += 1;
            let what = match &now {
                Replay::Holds => {
                    summary.same += 1;
                    "holds".to_string()
                }
                Replay::Skipped(why) => {
                    summary.skipped += 1;
                    eprintln!("tetwalk replay: {} skipped: {why}", place(&"case"));
                    "skipped".to_string()
                }
                Replay::Right => {
                    summary.changed += 1;
                    "right now".to_string()
                }
                Replay::OtherAnswer(x) => {
                    summary.changed += 1;
                    format!("other answer {x}")
                }
            };
            let v = serde_json::json!({
                "file": path.display().to_string(), "line": n + 1,
                "method": method, "replay": what,
            });
            writeln!(w, "{v}")?;
        }
    }
    w.flush()?;
    summary.finish(
        out,
        "no found case to replay",
        "found cases fail again with their recorded answer",
    )
}

pub(crate) fn run(a: Args) -> Status {
    if a.found {
        return found(&a);
    }
    let [file] = a.files.as_slice() else {
        return Err("a count's dump is replayed one file at a time".into());
    };
    let out = JsonOut::new(a.json.as_deref())?;
    let file_name = file.display();
    let file = std::fs::File::open(file).map_err(|e| format!("{file_name}: {e}"))?;
    let mut scenes: HashMap<String, Mesh> = HashMap::new();
    let mut backends: HashMap<BackendKind, Result<Backend, String>> = HashMap::new();
    let mut made = Reanswered::default();
    let mut summary = Summary::default();
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    for (n, line) in std::io::BufReader::new(file).lines().enumerate() {
        let n = n + 1;
        let place = |e: &dyn std::fmt::Display| format!("{file_name} line {n}: {e}");
        let line = line.map_err(|e| place(&e))?;
        if line.trim().is_empty() {
            continue;
        }
        summary.lines += 1;
        let d: WrongRay = serde_json::from_str(&line).map_err(|e| place(&e))?;
        let Some(kind) = d.backend else {
            return Err(place(&RerunError::NotWalked(d.method.clone())).into());
        };
        if !scenes.contains_key(&d.scene) {
            let mesh =
                crate::scenes::load(&d.scene, super::faces(a.no_faces)).map_err(|e| place(&e))?;
            scenes.insert(d.scene.clone(), mesh);
        }
        let mesh = &scenes[&d.scene];
        let backend = backends
            .entry(kind)
            .or_insert_with(|| Backend::open(kind).map_err(|e| e.to_string()));
        let backend = match backend {
            Ok(b) => b,
            Err(why) => {
                summary.skipped += 1;
                eprintln!("tetwalk replay: line {n} skipped: recorded on {kind:?}: {why}");
                continue;
            }
        };
        let Rerun {
            method,
            now,
            still_wrong,
            same,
        } = rerun(&d, mesh, backend, &mut made).map_err(|e| place(&e))?;
        if same {
            summary.same += 1;
        } else {
            summary.changed += 1;
        }
        let v = serde_json::json!({
            "line": n, "method": method, "backend": backend.describe(), "still_wrong": still_wrong,
            "same": same, "now": now.outcome, "recorded": d.stopped.outcome,
        });
        writeln!(w, "{v}")?;
    }
    w.flush()?;
    summary.finish(
        out,
        &format!("{file_name}: no wrong ray to replay"),
        "wrong rays fail again the same way",
    )
}

impl Summary {
    /// Write the summary, say it, and end: an error when nothing was replayed, status 1 when a case
    /// changed.
    fn finish(self, out: JsonOut, nothing: &str, what: &str) -> Status {
        if self.lines == 0 {
            return Err(nothing.into());
        }
        out.finish(&self)?;
        eprintln!(
            "tetwalk replay: {} of {} {what} ({} changed, {} skipped)",
            self.same, self.lines, self.changed, self.skipped
        );
        Ok(if self.changed > 0 {
            ExitCode::FAILURE
        } else {
            ExitCode::SUCCESS
        })
    }
}
