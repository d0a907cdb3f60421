//! Found cases filed under `corpora/found/<method>/`, one naming scheme for a stress campaign's
//! findings and `fuzz-import`'s: `<origin>-<kind>-<hash>.json`, the hash that of the case's line as
//! found, so that the same failure files under the same name, once; each written shrunk, the case as
//! found kept beside it.

use crate::engine::found::Found;
use crate::engine::shrink;
use crate::engine::stress::{Who, Wrong};
use crate::family::Family;
use crate::family::contract::Contract;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Why a found case could not be filed.
#[derive(Debug, thiserror::Error)]
pub(crate) enum FilingError {
    /// Checking or shrinking it failed.
    #[error(transparent)]
    Found(#[from] crate::engine::found::FoundError),
    /// Writing it failed.
    #[error("{file}: {why}")]
    Write {
        /// The file.
        file: String,
        /// Why.
        why: std::io::Error,
    },
}

/// Where a found case is filed under `dir`: by method, `origin` (what found it: a stress row, a fuzz
/// target), kind and an FNV-1a hash of its line (the case as found, before any shrink).
pub(crate) fn path<F: Family>(dir: &Path, origin: &str, r: &Found<F>) -> PathBuf {
    let line = r.to_json();
    let hash = line.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    });
    let (method, kind) = r
        .failure
        .as_ref()
        .map_or(("", ""), |f| (f.method.as_str(), f.kind().wrong_key()));
    dir.join(method)
        .join(format!("{origin}-{kind}-{hash:016x}.json"))
}

/// `r` written to `file` (its folder made), whole or not at all.
pub(crate) fn write<F: Family>(file: &Path, r: &Found<F>) -> Result<(), FilingError> {
    file.parent()
        .map_or(Ok(()), std::fs::create_dir_all)
        .and_then(|_| crate::staged::write(file, (r.to_json() + "\n").as_bytes()))
        .map_err(|why| FilingError::Write {
            file: file.display().to_string(),
            why,
        })
}

/// A campaign's filing of failures as found cases: new ones only, at most `keep` per method, row and
/// kind (each with the same case for the methods that claim and fail it too); the first error stops
/// filing and is kept.
pub(crate) struct Filing {
    /// What an answerer's found cases are shrunk inside.
    contract: Contract,
    /// Where they are filed.
    pub(crate) dir: PathBuf,
    /// At most this many per method, row and kind.
    pub(crate) keep: usize,
    kept: HashMap<(String, String, &'static str), usize>,
    /// Wrong answers seen.
    pub(crate) seen: u64,
    /// The files written.
    pub(crate) filed: Vec<PathBuf>,
    /// The first error, which stopped the filing.
    pub(crate) error: Option<FilingError>,
}

impl Filing {
    /// Filing under `dir`, at most `keep` per method, row and kind; an answerer's cases shrunk inside
    /// `contract`.
    pub(crate) fn new(dir: PathBuf, keep: usize, contract: Contract) -> Filing {
        Filing {
            contract,
            dir,
            keep,
            kept: HashMap::new(),
            seen: 0,
            filed: Vec::new(),
            error: None,
        }
    }

    /// A wrong answer of a row.
    pub(crate) fn file<F: Family>(&mut self, w: Wrong<F>) {
        self.seen += 1;
        if self.error.is_none()
            && let Err(e) = self.try_file(w)
        {
            self.error = Some(e);
        }
    }

    fn try_file<F: Family>(&mut self, w: Wrong<F>) -> Result<(), FilingError> {
        let row = F::row_name(w.row);
        let origin = format!("stress-{row}");
        let found = Found::<F>::of(*w.case, w.who.failure(w.on, *w.answer));
        let kind = F::kind(w.answer).wrong_key();
        let key = (w.who.name().to_string(), row, kind);
        let n = self.kept.get(&key).copied().unwrap_or(0);
        if n >= self.keep || path(&self.dir, &origin, &found).exists() {
            return Ok(());
        }
        self.kept.insert(key, n + 1);
        // An answerer's cases are its own: the methods that claim and fail them too are not asked.
        let claims = !matches!(w.who, Who::Outside(_));
        let filed = file_with_claims(&self.dir, &origin, found, claims, Path::exists, |i, r| {
            Ok(if let Who::Outside(x) = &w.who {
                shrink::shrink_outside::<F>(x, &r.case, shrink::CHECKS, &self.contract)
                    .map(|s| shrink::shrunk(r, &s))?
            } else if let (0, Who::Method(m)) = (i, &w.who) {
                shrink::shrink_on(r, m, w.on, shrink::CHECKS)?.0
            } else {
                as_shrunk_as_can_be(r)?
            })
        })?;
        self.filed.extend(filed.into_iter().map(|(file, _)| file));
        Ok(())
    }
}

/// A fuzz run's finding filed as [`Filing`] files a campaign's (by `target`, its fuzz target), shrunk
/// where it can be; a name in `filed` (this run's) is not written twice. The files written, each with
/// what it holds.
pub(crate) fn file_finding<F: Family>(
    dir: &Path,
    target: &str,
    found: Found<F>,
    filed: &[PathBuf],
) -> Result<Vec<(PathBuf, Found<F>)>, FilingError> {
    let again = |file: &Path| filed.iter().any(|f| f == file);
    file_with_claims(dir, target, found, true, again, |_, r| {
        as_shrunk_as_can_be(r)
    })
}

/// `r` shrunk on the backend it was found on, or as found where that backend is not here.
fn as_shrunk_as_can_be<F: Family>(r: &Found<F>) -> Result<Found<F>, FilingError> {
    Ok(shrink::shrink_found(r, shrink::CHECKS)?.map_or(r.clone(), |(s, _)| s))
}

/// `found`, and with `claims` the same case for every method that claims and fails it too (on the
/// CPU: a failure of a claim is a finding of its own), filed under `dir` by `origin`: each named by
/// the case as found (so that it is filed once), written as `shrunk` makes it (given its place in
/// that list; the original kept beside it), a name `skip` says is there left alone.
fn file_with_claims<F: Family>(
    dir: &Path,
    origin: &str,
    found: Found<F>,
    claims: bool,
    skip: impl Fn(&Path) -> bool,
    shrunk: impl Fn(usize, &Found<F>) -> Result<Found<F>, FilingError>,
) -> Result<Vec<(PathBuf, Found<F>)>, FilingError> {
    let records = if claims {
        found.with_claim_failures()?
    } else {
        vec![found]
    };
    let mut written: Vec<(PathBuf, Found<F>)> = Vec::new();
    for (i, r) in records.iter().enumerate() {
        let file = path(dir, origin, r);
        if skip(&file) || written.iter().any(|(f, _)| *f == file) {
            continue;
        }
        let s = shrunk(i, r)?;
        write(&file, &s)?;
        written.push((file, s));
    }
    Ok(written)
}
