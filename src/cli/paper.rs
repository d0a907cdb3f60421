//! `tetwalk paper`: the seeds' tables that tetwalk reproduces, ours beside theirs.

use super::{JsonOut, Staged, Status};
use crate::choice::BackendKind;
use crate::engine::count::Shard;
use crate::engine::paper::{self, PaperReport, Size};
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
pub(crate) struct Args {
    #[command(subcommand)]
    merge: Option<Merge>,
    /// The scene (seed 000's tables are of the bunny).
    #[arg(long, default_value = "bunny-quality")]
    scene: String,
    /// The papers' sizes: 1,282 views of 1024² (hours on two cores), Table 5 over 10,000 tetrahedra.
    #[arg(long)]
    full: bool,
    /// Views of the counts and the walk speeds, instead of the size's (32, or 1,282 with `--full`):
    /// a smaller run for a quick look, its size written in the report.
    #[arg(long, allow_negative_numbers = true)]
    views: Option<usize>,
    /// Image side of the counts and the walk speeds, instead of the size's (256, or 1024 with
    /// `--full`).
    #[arg(long, allow_negative_numbers = true)]
    side: Option<u32>,
    /// Backends of the counts, comma-separated (`cpu`, `cpu-fma`, `gpu`): one Table 4 column each.
    #[arg(long, value_parser = super::choice::<BackendKind>(), value_delimiter = ',', default_value = "cpu,cpu-fma")]
    backend: Vec<BackendKind>,
    /// Count only views `v` with `v % N == I` (`I/N`, 0-based), the timings whole; the shard's report
    /// goes to `--json` only, and `tetwalk paper merge` adds the N shards up into the tables.
    #[arg(long, default_value = "0/1")]
    shard: String,
    /// Also write the tables here (written whole, or not at all); they are always printed.
    /// `corpora/results/paper.md` is the repository's record of a run: name it to update it.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write the numbers as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        match &self.merge {
            Some(Merge::Merge { reports, out, json }) => super::Files::default()
                .inputs("REPORTS", reports)
                .output("--out", out.as_deref())
                .output("--json", json.as_deref()),
            None => super::Files::default()
                .scene("--scene", &self.scene)
                .output("--out", self.out.as_deref())
                .output("--json", self.json.as_deref()),
        }
    }
}

#[derive(clap::Subcommand)]
enum Merge {
    /// Add up the JSON reports of a sharded run (`paper --shard I/N --json FILE`, every I once) and
    /// write the tables.
    Merge {
        /// The shards' reports.
        #[arg(required = true)]
        reports: Vec<PathBuf>,
        /// Also write the tables here (written whole, or not at all); they are always printed.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also write the merged report as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
}

pub(crate) fn run(a: Args) -> Status {
    if let Some(Merge::Merge { reports, out, json }) = &a.merge {
        return merge(reports, out.as_deref(), json.as_deref());
    }
    let shard = super::count::shard(&a.shard)?;
    if shard != Shard::ALL && a.json.is_none() {
        return Err(format!(
            "--shard {}: a shard's report goes to --json FILE, for `tetwalk paper merge`",
            a.shard
        )
        .into());
    }
    let mut size = if a.full { Size::FULL } else { Size::REDUCED };
    if let Some(v) = a.views {
        size.views = super::view_count(v, "paper run")?;
        size.bench_views = size.views;
    }
    if let Some(side) = a.side {
        if !(1..=4096).contains(&side) {
            return Err(format!("--side {side} is not 1..=4096 pixels").into());
        }
        size.side = side;
    }
    super::count::held(shard, size.views)?;
    let json = JsonOut::new(a.json.as_deref())?;
    let whole = shard == Shard::ALL;
    let out = a
        .out
        .as_deref()
        .filter(|_| whole)
        .map(|p| Staged::new("--out", p))
        .transpose()?;
    let backends = super::open_each(&a.backend)?;
    let scene = crate::scenes::load(&a.scene, crate::mesh::Faces::Required)?;
    // The count and the octree count on each backend.
    let bar = super::progress(
        "paper",
        (shard.held(size.views) * backends.len() * 2) as u64,
        "views",
    );
    let report = paper::run(&scene, size, shard, &backends, &|| bar.inc(1))?;
    bar.finish_and_clear();
    if whole {
        write(&report, out)?;
    } else {
        println!(
            "shard {} of the run written to {}; `tetwalk paper merge` adds the shards up",
            a.shard,
            a.json.as_deref().unwrap_or(Path::new("-")).display()
        );
    }
    json.done("", &report)
}

/// The tables, printed and, with `--out`, written there.
fn write(report: &PaperReport, out: Option<Staged>) -> Result<(), super::Error> {
    let text = report.markdown();
    print!("{text}");
    match out {
        Some(mut out) => {
            out.write_all(text.as_bytes())?;
            out.finish()
        }
        None => Ok(()),
    }
}

fn merge(reports: &[PathBuf], out: Option<&Path>, json: Option<&Path>) -> Status {
    let json = JsonOut::new(json)?;
    let out = out.map(|p| Staged::new("--out", p)).transpose()?;
    let merged = crate::engine::count::merge::<PaperReport>(&super::read_reports(reports)?)?;
    write(&merged, out)?;
    json.done("", &merged)
}
