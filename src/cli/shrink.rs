//! `tetwalk shrink`: found cases, and the wrong rays of a `count --dump` (the one-tetrahedron case of
//! each walk's diverging step), shrunk to the simplest case the same method still fails the same way
//! on the same backend (`crate::engine::shrink`); each printed with the line that reproduces it, and
//! with `--in-place` written back over its file, the original kept in the line.

use super::{JsonOut, Status};
use crate::choice::Choice;
use crate::engine::Backends;
use crate::engine::shrink::{CHECKS, ShrinkLines, ShrinkReport, shrink_lines};
use crate::family::{Family, Kind};
use crate::report::shrink::{case_lines, summary};
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Files of found cases (`corpora/found/`, one JSON line each or more), or a `count --dump`.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Write each file of found cases back with its cases shrunk, the case as found kept in each
    /// line's `original` (a dump is never rewritten: its shrunk cases are printed).
    #[arg(long)]
    in_place: bool,
    /// Shrink for a program outside tetwalk instead (--answerer CMD, docs/answerers.md): each line
    /// of FILE is a case (a found case too), asked of the program as `stress --answerer` asks; the
    /// simplest case it still answers wrongly the same way, inside its contract, is printed (a leak
    /// stays a leak, a failure that is no tie does not become one), with the line that reproduces it.
    #[command(flatten)]
    answerer: super::AnswererArg,
    #[command(flatten)]
    contract: super::ContractArg,
    /// Checks (exact judgements of a candidate case) one shrink may make at most.
    #[arg(long, default_value_t = CHECKS)]
    checks: usize,
    /// Also write what was done to each case (significant bits before and after, checks, the shrunk
    /// line, the line that reproduces it) and the totals as JSON here.
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

pub(crate) fn run(a: Args) -> Status {
    let out = JsonOut::new(a.json.as_deref())?;
    if a.checks == 0 {
        return Err("--checks 0 would shrink nothing".into());
    }
    if a.answerer.answerer.is_some() && a.in_place {
        return Err("--answerer prints the shrunk cases; a user's file is not rewritten (leave out --in-place)".into());
    }
    // Started once, before the first line, as the family whose faces it may number starts it (its
    // numbering found then); each case's family checks the contract again as it is shrunk.
    let faces = Kind::ALL
        .iter()
        .copied()
        .find(|&k| crate::with_family!(k, F => F::FACES))
        .ok_or("no family numbers faces")?;
    let answerer = crate::with_family!(faces, F => {
        let contract = a.contract.contract::<F>()?;
        if a.answerer.answerer.is_none() && contract != Default::default() {
            return Err("--origin, --unit-direction, --entry, --orientation and --tolerance state an --answerer's contract; tetwalk's own methods are shrunk as they fail".into());
        }
        a.answerer.start::<F>(&contract)?.map(|x| (x, contract))
    });
    let how = ShrinkLines {
        checks: a.checks,
        outside: answerer.as_ref().map(|(x, k)| (x, *k)),
        in_place: a.in_place,
    };
    let mut backends = Backends::default();
    let mut report = ShrinkReport::default();
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    // Files to rewrite, each whole and only once every file's every line is shrunk.
    let mut rewrites: Vec<(PathBuf, String)> = Vec::new();
    for path in &a.files {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let file = path.display().to_string();
        let rewritten = shrink_lines(
            &file,
            &text,
            &how,
            &mut backends,
            &mut report,
            |at, done| match done {
                Ok(done) => w.write_all(case_lines(at, done).as_bytes()),
                Err(why) => {
                    eprintln!("tetwalk shrink: {at} left as it is: {why}");
                    Ok(())
                }
            },
        )?;
        if a.in_place {
            rewrites.push((path.clone(), rewritten));
        }
    }
    w.flush()?;
    if let Some((x, _)) = &answerer {
        x.finish()?;
    }
    if report.cases.is_empty() && report.left.is_empty() {
        return Err("no case to shrink in the files given".into());
    }
    for (path, text) in &rewrites {
        crate::staged::write(path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    eprintln!("{}", summary(&report, a.in_place));
    out.done("", &report)
}
