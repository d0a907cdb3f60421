//! `tetwalk replay`: answer the wrong rays of a `count --dump` again, every family's, and say whether
//! each still fails the same way (the same method on the same backend stopping at the same place, and
//! still wrong);
//! with `--found`, the same for found cases (on their backend, and for a GPU finding on its adapter).

use super::{JsonOut, Status};
use crate::engine::count::Redone;
use crate::engine::found::{Replay, ReplayTally};
use crate::engine::replay;
use crate::report::replay::{dumped_line, found_line, summary};
use std::io::Write;
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
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    let tally = replay::found(&a.files, |file, n, now, method| {
        if let Replay::Skipped(why) = now {
            eprintln!("tetwalk replay: {file} line {n}: case skipped: {why}");
        }
        writeln!(w, "{}", found_line(file, n, method, now))
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
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    let tally = replay::dumped(
        &a.files,
        super::faces(a.no_faces),
        |file, n, d, again| match again {
            Redone::Skipped(why) => {
                eprintln!("tetwalk replay: {file} line {n} skipped: {why}");
                Ok(())
            }
            Redone::Rerun(r, backend) => writeln!(
                w,
                "{}",
                dumped_line(file, n, r, backend, &d.stopped.outcome)
            ),
        },
    )?;
    w.flush()?;
    let files: Vec<String> = a.files.iter().map(|f| f.display().to_string()).collect();
    finish(
        tally,
        out,
        &format!("{}: no wrong ray to replay", files.join(", ")),
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
