//! `tetwalk replay`: answer the wrong rays of a `count --dump` again, every family's, and say whether
//! each still fails the same way (the same method on the same backend stopping at the same place, and
//! still wrong);
//! with `--found`, the same for found cases (on their backend, and for a GPU finding on its adapter).

use super::{JsonOut, Status};
use crate::cases::object;
use crate::engine::count::{Dumped, Redone};
use crate::engine::found::{Replay, ReplayTally, replay_object};
use crate::family::wrong::WrongRay;
use crate::report::replay::{dumped_line, found_line, summary};
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

/// Replay found cases: each must fail again on its backend with its recorded answer.
fn found(a: &Args) -> Status {
    let out = JsonOut::new(a.json.as_deref())?;
    let mut tally = ReplayTally::default();
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
            let (now, method) = replay_object(obj).map_err(|e| place(&e))?;
            tally.add(now.same());
            if let Replay::Skipped(why) = &now {
                eprintln!("tetwalk replay: {} skipped: {why}", place(&"case"));
            }
            let file = path.display().to_string();
            writeln!(w, "{}", found_line(&file, n + 1, method.as_deref(), &now))?;
        }
    }
    w.flush()?;
    finish(
        tally,
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
    let mut dumped = Dumped::new(super::faces(a.no_faces));
    let mut tally = ReplayTally::default();
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    for (n, line) in std::io::BufReader::new(file).lines().enumerate() {
        let n = n + 1;
        let place = |e: &dyn std::fmt::Display| format!("{file_name} line {n}: {e}");
        let line = line.map_err(|e| place(&e))?;
        if line.trim().is_empty() {
            continue;
        }
        let d: WrongRay = serde_json::from_str(&line).map_err(|e| place(&e))?;
        match dumped.line(&d).map_err(|e| place(&e))? {
            Redone::Skipped(why) => {
                tally.add(None);
                eprintln!("tetwalk replay: line {n} skipped: {why}");
            }
            Redone::Rerun(r, backend) => {
                tally.add(Some(r.same));
                writeln!(w, "{}", dumped_line(n, &r, &backend, &d.stopped.outcome))?;
            }
        }
    }
    w.flush()?;
    finish(
        tally,
        out,
        &format!("{file_name}: no wrong ray to replay"),
        "wrong rays fail again the same way",
    )
}

/// Write the tally, say it, and end: an error when nothing was replayed, status 1 when a line
/// changed.
fn finish(t: ReplayTally, out: JsonOut, nothing: &str, what: &str) -> Status {
    if t.lines == 0 {
        return Err(nothing.into());
    }
    out.finish(&t)?;
    eprintln!("tetwalk replay: {}", summary(&t, what));
    Ok(if t.changed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
