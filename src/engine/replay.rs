//! `tetwalk replay`'s runs: every line of the files, in order, answered again — found cases
//! ([`found`]) or a count's dumped wrong rays ([`dumped`]) — and tallied.

use crate::cases::object;
use crate::engine::count::{Dumped, Redone};
use crate::engine::found::{Replay, ReplayTally, replay_object};
use crate::family::wrong::WrongRay;
use crate::mesh::Faces;
use std::io::BufRead;
use std::path::PathBuf;

/// Why a replay stopped: a file or a line (named) that could not be read, or what `each` returned.
#[derive(Debug, thiserror::Error)]
pub(crate) enum ReplayError {
    /// A file or line that could not be read or answered again, named.
    #[error("{0}")]
    Place(String),
    /// What `each` returned (its source, so that a closed standard output is told apart).
    #[error("{0}")]
    Write(#[from] std::io::Error),
}

/// Found cases replayed ([`replay_object`]), each given to `each` with its file, line number and
/// method.
pub(crate) fn found(
    files: &[PathBuf],
    mut each: impl FnMut(&str, usize, &Replay, Option<&str>) -> std::io::Result<()>,
) -> Result<ReplayTally, ReplayError> {
    let mut tally = ReplayTally::default();
    each_line(files, |file, n, line| {
        let place = |e: &dyn std::fmt::Display| ReplayError::Place(format!("{file} line {n}: {e}"));
        let obj = object(line).map_err(|e| place(&e))?;
        let (now, method) = replay_object(obj).map_err(|e| place(&e))?;
        tally.add(now.same());
        Ok(each(file, n, &now, method.as_deref())?)
    })?;
    Ok(tally)
}

/// A count's dumped wrong rays answered again ([`Dumped::line`], scenes loaded with `faces`), each
/// given to `each` with its file, line number and the line read.
pub(crate) fn dumped(
    files: &[PathBuf],
    faces: Faces,
    mut each: impl FnMut(&str, usize, &WrongRay, &Redone) -> std::io::Result<()>,
) -> Result<ReplayTally, ReplayError> {
    // One for every file: the scenes loaded and the views made once.
    let mut dumped = Dumped::new(faces);
    let mut tally = ReplayTally::default();
    each_line(files, |file, n, line| {
        let place = |e: &dyn std::fmt::Display| ReplayError::Place(format!("{file} line {n}: {e}"));
        let d: WrongRay = serde_json::from_str(line).map_err(|e| place(&e))?;
        let again = dumped.line(&d).map_err(|e| place(&e))?;
        tally.add(match &again {
            Redone::Skipped(_) => None,
            Redone::Rerun(r, _) => Some(r.same),
        });
        Ok(each(file, n, &d, &again)?)
    })?;
    Ok(tally)
}

/// `f` on every line of `files` but blank ones, with its file's name and line number.
fn each_line(
    files: &[PathBuf],
    mut f: impl FnMut(&str, usize, &str) -> Result<(), ReplayError>,
) -> Result<(), ReplayError> {
    for path in files {
        let name = path.display().to_string();
        let file =
            std::fs::File::open(path).map_err(|e| ReplayError::Place(format!("{name}: {e}")))?;
        for (n, line) in std::io::BufReader::new(file).lines().enumerate() {
            let line =
                line.map_err(|e| ReplayError::Place(format!("{name} line {}: {e}", n + 1)))?;
            if !line.trim().is_empty() {
                f(&name, n + 1, &line)?;
            }
        }
    }
    Ok(())
}
