//! `tetwalk shrink`: found cases, and the wrong rays of a `count --dump` (the one-tetrahedron case of
//! each walk's diverging step), shrunk to the simplest case the same method still fails the same way
//! on the same backend (`crate::engine::shrink`); each printed with the line that reproduces it, and
//! with `--in-place` written back over its file, the original kept in the line.

use super::{JsonOut, Status};
use crate::cases::object;
use crate::choice::Choice;
use crate::engine::found::{Found, FoundError};
use crate::engine::shrink::{
    Backends, CHECKS, Place, ShrinkReport, shrink_case, shrink_case_outside, shrink_dump_line,
};
use crate::family::{Family, Kind, owner};
use crate::report::shrink::{case_lines, summary};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

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
        a.answerer.start::<F>(&contract)?
    });
    let mut backends = Backends::default();
    let mut report = ShrinkReport::default();
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    // Files to rewrite, each whole and only once every file's every line is shrunk.
    let mut rewrites: Vec<(PathBuf, String)> = Vec::new();
    for path in &a.files {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut rewritten = String::new();
        for (n, line) in text.lines().enumerate() {
            let at = Place {
                file: path.display().to_string(),
                line: n + 1,
            };
            let place = |e: &dyn std::fmt::Display| format!("{} line {}: {e}", at.file, at.line);
            if line.trim().is_empty() {
                rewritten += line;
                rewritten += "\n";
                continue;
            }
            let obj = object(line).map_err(|e| place(&e))?;
            let dump = obj.contains_key("pixel") && obj.contains_key("scene");
            if dump && a.in_place {
                return Err(place(
                    &"a count's dump is not rewritten: leave out --in-place (its shrunk cases are printed)",
                )
                .into());
            }
            let result = if let Some(x) = &answerer {
                if dump {
                    return Err(place(
                        &"--answerer shrinks cases (one per line), not a count's dump",
                    )
                    .into());
                }
                crate::with_family!(owner(&obj), F => Found::<F>::from_object(obj)
                .and_then(|found| {
                    let contract = a.contract.contract::<F>().map_err(|e| FoundError::Field {
                        field: "contract",
                        why: e.to_string(),
                    })?;
                    shrink_case_outside::<F>(&found, x, &contract, &at, a.checks)
                }))
            } else if dump {
                shrink_dump_line(obj, &at, &mut backends, a.checks)
            } else {
                crate::with_family!(owner(&obj), F => Found::<F>::from_object(obj)
                    .and_then(|found| shrink_case::<F>(&found, &at, &mut backends, a.checks)))
            }
            .map_err(|e| place(&e))?;
            match result {
                Ok(done) => {
                    w.write_all(case_lines(&place(&"case"), &done).as_bytes())?;
                    rewritten += &done.shrunk.to_string();
                    report.cases.push(done);
                }
                Err(why) => {
                    eprintln!("tetwalk shrink: {} left as it is: {why}", place(&"case"));
                    rewritten += line;
                    report.left.push((at.clone(), why));
                }
            }
            rewritten += "\n";
        }
        if a.in_place {
            rewrites.push((path.clone(), rewritten));
        }
    }
    w.flush()?;
    if report.cases.is_empty() && report.left.is_empty() {
        return Err("no case to shrink in the files given".into());
    }
    for (path, text) in &rewrites {
        crate::staged::write(path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    eprintln!("{}", summary(&report, a.in_place));
    out.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}
