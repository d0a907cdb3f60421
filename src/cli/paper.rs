//! `tetwalk paper`: the seeds' tables that tetwalk reproduces, ours beside theirs.

use super::{JsonOut, Outcome, Staged};
use crate::backend::Backend;
use crate::report::paper::{self, Size};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (seed 000's tables are of the bunny).
    #[arg(long, default_value = "bunny-quality")]
    scene: String,
    /// The papers' sizes: 1,282 views of 1024² (hours on two cores), Table 5 over 10,000 tetrahedra.
    #[arg(long)]
    full: bool,
    /// Backends of the counts, comma-separated (`cpu`, `cpu-fma`, `gpu`): one Table 4 column each.
    #[arg(long, default_value = "cpu,cpu-fma")]
    backend: String,
    /// Where the tables go (written whole, or not at all).
    #[arg(long, default_value = "corpora/results/paper.md")]
    out: PathBuf,
    /// Also write the numbers as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

pub fn run(a: Args) -> Outcome {
    let kinds = super::backend_list(&a.backend)?;
    let json = JsonOut::new(a.json.as_deref())?;
    let mut out = Staged::new("--out", &a.out)?;
    let backends = kinds
        .into_iter()
        .map(Backend::open)
        .collect::<Result<Vec<_>, _>>()?;
    let mesh = crate::scenes::load(&a.scene, crate::mesh::Faces::Required)?;
    let size = if a.full { Size::FULL } else { Size::REDUCED };
    // The counts on each backend, then the octree count.
    let bar = super::progress((size.views * (backends.len() + 1)) as u64, "views");
    let report = paper::run(&a.scene, &mesh, size, &backends, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let text = report.markdown();
    print!("{text}");
    out.writer().write_all(text.as_bytes())?;
    out.finish()?;
    json.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}
