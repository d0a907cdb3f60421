//! `tetwalk bench`: walk speed per method and backend on a scene's primary rays.

use super::{JsonOut, Status};
use crate::backend::Backend;
use crate::engine::bench;
use crate::family::{self, Triangle, Walks};
use crate::scenes::camera::Views;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Which family: `exit-face` (walks) or `triangle` (seed 004 Figure 5's measure: every primary
    /// ray of one view against every triangle, one thread, packets of 1x1 to 8x8, speedups over
    /// mt-precomputed on single rays).
    #[arg(long, value_parser = ["exit-face", "triangle"], default_value = "exit-face")]
    family: String,
    /// A built-in scene, a TetGen stem, or a Gmsh, VTK or MEDIT file (as `count` takes).
    #[arg(long, default_value = "bunny-quality")]
    scene: String,
    /// Accept a scene without constrained faces (no TetGen `.face`, no triangles in another format).
    #[arg(long)]
    no_faces: bool,
    /// Viewpoints on a sphere around the model (`--family triangle` times the first inside the mesh).
    #[arg(long, allow_negative_numbers = true, default_value_t = 16)]
    views: usize,
    /// Image size, WxH [default: 1024x1024, or 256x256 (seed 004's) with --family triangle].
    #[arg(long)]
    size: Option<String>,
    /// Methods to time (comma-separated, or all); on a GPU, those with a GPU version.
    #[arg(long, default_value = "all")]
    methods: String,
    /// Backends, comma-separated (`cpu`, `cpu-fma`, `gpu`), timed on the same rays in one run.
    #[arg(long, default_value = "cpu")]
    backend: String,
    /// Rays handed to a backend at once (whole views; one 1024² view by default: larger batches were
    /// slower end to end on an H200, their host buffers being fresh memory each time).
    #[arg(long, default_value_t = 1 << 20)]
    batch: usize,
    /// Also time the walks over seed 003's layouts (Tet32, Tet20, Tet16) of the methods that have them.
    #[arg(long)]
    layouts: bool,
    /// Put the mesh in Hilbert order first (seed 003 §3).
    #[arg(long)]
    hilbert: bool,
    /// Seed of the viewpoints' rotation.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// Time each batch this many times: each timing is a sample, and rows give the median and range.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    repeat: usize,
    /// A report of an earlier run (its `--json`): each row's median is compared with the same row's
    /// there, as criterion compares (faster or slower where it leaves that row's range).
    #[arg(long)]
    baseline: Option<PathBuf>,
    /// Also write the report as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .scene("--scene", &self.scene)
            .input("--baseline", self.baseline.as_deref())
            .output("--json", self.json.as_deref())
    }
}

pub fn run(a: Args) -> Status {
    if a.family == "triangle" {
        return run_triangle(a);
    }
    let methods = family::parse_list::<Walks>(&a.methods)?;
    let kinds = super::backend_list(&a.backend)?;
    super::view_count(a.views, "bench")?;
    if a.batch == 0 {
        return Err("--batch 0: a batch holds at least one ray".into());
    }
    if a.repeat == 0 {
        return Err("--repeat 0: each batch is timed at least once".into());
    }
    let baseline = match &a.baseline {
        Some(p) => Some(
            super::read_reports::<bench::BenchReport>(std::slice::from_ref(p))?
                .remove(0)
                .1,
        ),
        None => None,
    };
    let (width, height) = super::size(a.size.as_deref().unwrap_or("1024x1024"), false, 65536)?;
    let per_view = width as u128 * height as u128;
    super::fits(
        &format!("--size {width}x{height} --batch {}", a.batch),
        per_view.max(a.batch as u128) * super::BYTES_PER_PIXEL,
    )?;
    let out = JsonOut::new(a.json.as_deref())?;
    let backends = kinds
        .into_iter()
        .map(Backend::open)
        .collect::<Result<Vec<_>, _>>()?;
    let mut mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
    if a.hilbert {
        mesh = crate::mesh::reorder::hilbert_sorted(&mesh);
    }
    let views = views(&a, width, height);
    let bar = super::progress("bench", a.views as u64, "views");
    let report = bench::run(
        &a.scene,
        &mesh,
        a.hilbert,
        &views,
        &methods,
        &backends.iter().collect::<Vec<_>>(),
        (a.batch, a.layouts, a.repeat),
        &|| bar.inc(1),
    )?;
    bar.finish_and_clear();
    let mut report = report;
    if let Some(b) = &baseline {
        let file = a.baseline.as_deref().unwrap_or(Path::new("")).display();
        if let Some(why) = report.differs_from(b) {
            return Err(format!(
                "--baseline {file}: a run of other settings ({why}): its batches are other rays; run the baseline with the same --scene, --views, --size, --seed, --batch and --hilbert"
            )
            .into());
        }
        if report.compare(b) == 0 {
            return Err(format!(
                "--baseline {file}: none of its rows (method, layout, backend) is one of this run's"
            )
            .into());
        }
    }
    print!("{}", report.markdown());
    out.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}

/// `bench --family triangle`.
fn run_triangle(a: Args) -> Status {
    if a.backend != "cpu" || a.layouts || a.hilbert || a.baseline.is_some() || a.repeat != 1 {
        return Err("--family triangle times the CPU, plain f32, best of 3; leave out --backend, --layouts, --hilbert, --repeat and --baseline".into());
    }
    super::view_count(a.views, "bench")?;
    let methods = family::parse_list::<Triangle>(&a.methods)?;
    let (width, height) = super::size(a.size.as_deref().unwrap_or("256x256"), false, 4096)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
    let views = views(&a, width, height);
    let report = crate::family::triangle::engine::speed(&mesh, &a.scene, &views, &methods, 3)?;
    print!("{}", report.markdown());
    out.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}

/// The views of a bench of `width × height`.
fn views(a: &Args, width: u32, height: u32) -> Views {
    Views {
        views: a.views,
        width,
        height,
        seed: a.seed,
        fov_deg: Views::FOV_DEG,
    }
}
