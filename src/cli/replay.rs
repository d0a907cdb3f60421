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
    /// Dumps written by `tetwalk count --dump` (a sharded count's, or several counts'), or with
    /// `--found` found cases (files of JSON lines).
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
    each_line(&a.files, |file, n, line| {
        let place = |e: &dyn std::fmt::Display| format!("{file} line {n}: {e}");
        let obj = object(line).map_err(|e| place(&e))?;
        let (now, method) = replay_object(obj).map_err(|e| place(&e))?;
        tally.add(now.same());
        if let Replay::Skipped(why) = &now {
            eprintln!("tetwalk replay: {} skipped: {why}", place(&"case"));
        }
        writeln!(w, "{}", found_line(file, n, method.as_deref(), &now))?;
        Ok(())
    })?;
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
    let out = JsonOut::new(a.json.as_deref())?;
    // One for every file: the scenes loaded and the views made once.
    let mut dumped = Dumped::new(super::faces(a.no_faces));
    let mut tally = ReplayTally::default();
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    each_line(&a.files, |file, n, line| {
        let place = |e: &dyn std::fmt::Display| format!("{file} line {n}: {e}");
        let d: WrongRay = serde_json::from_str(line).map_err(|e| place(&e))?;
        match dumped.line(&d).map_err(|e| place(&e))? {
            Redone::Skipped(why) => {
                tally.add(None);
                eprintln!("tetwalk replay: {file} line {n} skipped: {why}");
            }
            Redone::Rerun(r, backend) => {
                tally.add(Some(r.same));
                let line = dumped_line(file, n, &r, &backend, &d.stopped.outcome);
                writeln!(w, "{line}")?;
            }
        }
        Ok(())
    })?;
    w.flush()?;
    let files: Vec<String> = a.files.iter().map(|f| f.display().to_string()).collect();
    finish(
        tally,
        out,
        &format!("{}: no wrong ray to replay", files.join(", ")),
        "wrong rays fail again the same way",
    )
}

/// `f` on each line of each file that is not blank: the file's name, the line's number (from 1) and
/// the line, read one at a time.
fn each_line(
    files: &[PathBuf],
    mut f: impl FnMut(&str, usize, &str) -> Result<(), super::Error>,
) -> Result<(), super::Error> {
    for path in files {
        let name = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|e| format!("{name}: {e}"))?;
        for (n, line) in std::io::BufReader::new(file).lines().enumerate() {
            let line = line.map_err(|e| format!("{name} line {}: {e}", n + 1))?;
            if !line.trim().is_empty() {
                f(&name, n + 1, &line)?;
            }
        }
    }
    Ok(())
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
