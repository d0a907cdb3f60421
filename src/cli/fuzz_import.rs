//! `tetwalk fuzz-import`: turn fuzzer artifacts into readable found cases under `corpora/found/`,
//! each shrunk (`crate::engine::shrink`) with the case as found kept beside it.

use super::{JsonOut, Status};
use crate::choice::Choice;
use crate::engine::filing;
use crate::engine::found::Found;
use crate::engine::fuzz::{finding, held};
use crate::family::{Family, Kind};
use crate::registry::Named;
use std::path::{Path, PathBuf};

crate::families!(__more_fuzz_targets);

/// The fuzz targets beyond each family's own, from the families' list: `MORE_TARGETS`, their names,
/// and `import_more`, which files one's artifacts with its finding function.
#[doc(hidden)]
#[macro_export]
macro_rules! __more_fuzz_targets {
    ([] { $($line:tt)* } counted { $($c:tt)* } kit { $($k:tt)* } commands { $($cm:tt)* } fuzz { $($m:ident: $t:ident),* } $($rest:tt)*) => {
        /// The fuzz targets beyond each family's own ([`Family::FUZZ_TARGET`]).
        const MORE_TARGETS: &[&str] = &[$(stringify!($t)),*];

        /// `target`'s artifacts filed, if it is one of [`MORE_TARGETS`].
        fn import_more(
            target: &str,
            a: &Args,
            filed: &mut Vec<PathBuf>,
        ) -> Option<Result<(), super::Error>> {
            $(
                if target == stringify!($t) {
                    return Some(import(a, filed, |_, bytes| Ok($crate::family::$m::engine::$t(bytes)?)));
                }
            )*
            None
        }
    };
}

/// The fuzz targets: each family's, and those beyond them.
fn targets() -> clap::builder::PossibleValuesParser {
    let families = Kind::ALL
        .iter()
        .map(|&k| crate::with_family!(k, F => F::FUZZ_TARGET));
    families
        .chain(MORE_TARGETS.iter().copied())
        .collect::<Vec<_>>()
        .into()
}

#[derive(clap::Args)]
pub(crate) struct Args {
    /// The fuzz target that found them.
    #[arg(long, value_parser = targets())]
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

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .inputs("ARTIFACTS", &self.artifacts)
            .output("--json", self.json.as_deref())
    }
}

pub(crate) fn run(a: Args) -> Status {
    let json = JsonOut::new(a.json.as_deref())?;
    let mut filed = Vec::new();
    if let Some(filing) = import_more(&a.target, &a, &mut filed) {
        filing?;
    } else {
        let kind = Kind::ALL
            .iter()
            .copied()
            .find(|&k| crate::with_family!(k, F => F::FUZZ_TARGET) == a.target)
            .ok_or_else(|| format!("--target {}: no family's fuzz target", a.target))?;
        crate::with_family!(kind, F => import::<F>(&a, &mut filed, |path, bytes| {
            Ok(finding::<F>(bytes, path.extension().is_some_and(|e| e == "json"))?)
        }))?;
    }
    json.done("", &serde_json::json!({ "filed": filed }))
}

/// What a held method fails on one artifact, if anything (`engine::fuzz::finding`, or a target's
/// beyond the families' own).
type Finding<F> = fn(&Path, &[u8]) -> Result<Option<Found<F>>, super::Error>;

/// File each artifact's finding, and the same case for the methods that claim and fail it too, under
/// `corpora/found/<method>/`. The methods the fuzz run held (`TETWALK_FUZZ_METHOD`) on the backend it
/// held them on (`TETWALK_FUZZ_BACKEND`), as the fuzz targets do.
fn import<F: Family>(
    a: &Args,
    filed: &mut Vec<PathBuf>,
    finding: Finding<F>,
) -> Result<(), super::Error> {
    let held: Vec<&str> = held::<F>()?.iter().map(|(m, _)| m.name()).collect();
    for path in &a.artifacts {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let Some(found) = finding(path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?
        else {
            eprintln!(
                "{}: does not fail (any more) for {:?}",
                path.display(),
                held
            );
            continue;
        };
        for (file, record) in filing::file_finding(&a.out, &a.target, found, filed)? {
            let f = record
                .failure
                .as_ref()
                .expect("a found case records its failure");
            println!(
                "{}: {} {} ({})",
                file.display(),
                f.method,
                f.kind().wrong(),
                crate::choice::Choice::name(f.backend)
            );
            filed.push(file);
        }
    }
    Ok(())
}
