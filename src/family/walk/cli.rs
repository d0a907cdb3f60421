//! The walk family on the command line (a file of the command line's layer in the family's folder):
//! `tetwalk walk`, `render`'s views of a scene, the `stress` flags that choose its rows, what `count` asks of it (an answerer
//! asked step by step, `--rays-out`), and `judge` on that rays file: the walks given for its rays
//! judged as the count judges them.

use super::engine::{
    GivenWalksMap, RaysHeader, WalkSettings, Walker, asked_walks, frame, walk_run,
};
use super::{WalkRows, WalkScene, Walks, report};
use crate::backend::Backend;
use crate::cli::JsonOut;
use crate::cli::bench::Args as BenchArgs;
use crate::cli::choice;
use crate::cli::count::Dump;
use crate::cli::count::{Args as CountArgs, FamilyFlags, Flags, held, views};
use crate::cli::judge::Args as JudgeArgs;
use crate::cli::render::{Args as RenderArgs, Drawn, What, beside, drawn_methods, finish, write};
use crate::cli::stress::{Rows, Shape, or_all};
use crate::cli::{AnswererArg, BackendArg, Error, Files, Io, Status, WgslArg, fits};
use crate::engine::answerer::Answerer;
use crate::engine::answering::{AnswersError, each_answer};
use crate::engine::count::{GivenWalks, Shard};
use crate::engine::standing::Standings;
use crate::family::ExitFace;
use crate::family::contract::Contract;
use crate::family::wrong::WrongRay;
use crate::mesh::Mesh;
use crate::registry::Named;
use crate::render::{self, Image};
use crate::scenes::Generated;
use crate::walk::layouts::LayoutKind;
use serde_json::Value;
use std::io::BufRead;
use std::path::Path;
use std::path::PathBuf;
use std::process::ExitCode;

/// Walk rays through a generated mesh with each method, every step judged exactly.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The generated mesh.
    #[arg(long, value_parser = choice::<Generated>(), default_value = "fan")]
    mesh: Generated,
    /// Grid cells per side, or 16·size tetrahedra in the fan.
    #[arg(long, allow_negative_numbers = true, default_value_t = 8)]
    size: u32,
    /// Move the mesh and rays this far from the origin along (1, 1, 1); exact up to 2^20.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    offset: f32,
    /// Rays walked (half aimed exactly through vertices and edges).
    #[arg(long, allow_negative_numbers = true, default_value_t = 10000)]
    rays: usize,
    /// Methods (comma-separated, or all).
    #[arg(long, default_value = "all")]
    methods: String,
    /// Where the walks run: a CPU backend, `cpu`, `cpu-fma`, `cpu-ftz` or `cpu-gpu` (every step is judged by the oracle on the CPU, so the
    /// GPU has no place here; `count --backend gpu` walks on it).
    #[command(flatten)]
    backend: BackendArg,
    #[command(flatten)]
    wgsl: WgslArg,
    /// Seed of the rays (and of the jittered grid).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// Walk the methods that can (aman20, aman20-scaled) over this compact layout instead of the plain
    /// mesh (their "diverged" column is then not measured).
    #[arg(long, value_parser = choice::<LayoutKind>())]
    layout: Option<LayoutKind>,
    /// Reorder points and tetrahedra along a Hilbert curve, by region, first (seed 003 §5).
    #[arg(long)]
    hilbert: bool,
    /// `all`: also walk under each of the 12 orientation-preserving relabellings of the tetrahedra
    /// (the same for the whole mesh) and report, per method, wrong results and cycles with the mesh's
    /// own labelling beside their min / median / max over the 12.
    #[arg(long, value_parser = ["all"])]
    relabel: Option<String>,
    /// Also write the table as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl Io for Args {
    fn io(&self) -> Files {
        Files::default()
            .input("--wgsl", self.wgsl.wgsl.as_deref())
            .output("--json", self.json.as_deref())
    }
}

/// `tetwalk walk`: the mesh and rays made, the walks run and judged ([`super::engine`]), the tables
/// printed ([`super::report`]).
pub(crate) fn run(a: Args) -> Status {
    let (backend, methods) = a.wgsl.open::<Walks>(a.backend, &a.methods)?;
    // Every ray keeps one tally per method until the table is made.
    fits(
        &format!("--rays {}", a.rays),
        a.rays as u128 * super::engine::bytes_per_walked_ray(methods.len()) as u128,
    )?;
    let out = JsonOut::new(a.json.as_deref())?;
    let walker = match &backend {
        Backend::Cpu { model } => Walker::Checked(*model),
        Backend::Gpu(_) if a.wgsl.wgsl.is_some() => {
            if a.relabel.is_some() || a.layout.is_some() {
                return Err(
                    "--wgsl walks the plain mesh on the GPU; leave out --relabel and --layout"
                        .into(),
                );
            }
            Walker::Gpu(&backend)
        }
        Backend::Gpu(_) => {
            let cpus: Vec<&str> = crate::choice::Model::ALL
                .iter()
                .map(|m| crate::choice::Choice::name(m.backend()))
                .collect();
            return Err(format!("walk judges every step with the oracle on the CPU: use --backend {} (count --backend gpu walks on the GPU; a --wgsl function walks there too)", cpus.join(", ")).into());
        }
    };
    if a.relabel.is_some() && a.layout.is_some() {
        return Err("--relabel walks the plain mesh; leave out --layout".into());
    }
    let settings = WalkSettings {
        mesh: a.mesh,
        size: a.size,
        offset: a.offset,
        rays: a.rays,
        seed: a.seed,
        layout: a.layout,
        hilbert: a.hilbert,
        relabel: a.relabel.is_some(),
    };
    let report = walk_run(&settings, &methods, walker, a.backend.backend)?;
    let (walked_by, checked) = match walker {
        Walker::Checked(model) => (model.words().to_string(), true),
        Walker::Gpu(b) => (b.describe(), false),
    };
    println!("{}", report::walk_heading(&report, &walked_by));
    print!("{}", report::walk_table(&report, checked));
    if let Some(r) = &report.relabellings {
        print!("{}", report::relabelled_table(r));
    }
    out.finish(&report)?;
    Ok(ExitCode::SUCCESS)
}

/// Walk rows.
#[derive(clap::Args)]
#[group(skip)]
pub(crate) struct StressFlags {
    /// Walk rows: the scenes walked (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<WalkScene>(), value_delimiter = ',')]
    scenes: Vec<WalkScene>,
}

impl Rows for Walks {
    type Flags = StressFlags;
    fn own(all: &crate::cli::stress::RowFlags) -> &StressFlags {
        &all.walk
    }
    fn given(f: &StressFlags) -> Vec<&'static str> {
        if f.scenes.is_empty() {
            vec![]
        } else {
            vec!["--scenes"]
        }
    }
    fn chosen(f: &StressFlags, _: Shape) -> WalkRows {
        WalkRows {
            scenes: or_all(&f.scenes),
        }
    }
}

/// Walk counts have no flags of their own.
#[derive(clap::Args)]
#[group(skip)]
pub(crate) struct CountFlags {}

impl Flags for Walks {
    type Flags = CountFlags;
    fn own(all: &FamilyFlags) -> &CountFlags {
        &all.walk
    }
    fn settings(_: &CountFlags) {}
    const ASKS: bool = true;
    /// Started for exit-face cases: each step of a walk is one.
    fn start(
        a: &AnswererArg,
        k: &crate::cli::ContractArg,
    ) -> Result<Option<(Answerer, Contract)>, Error> {
        let k = k.contract::<ExitFace>()?;
        Ok(a.start::<ExitFace>(&k)?.map(|x| (x, k)))
    }
    /// Every step of every walk asked of the answerer, a view's unfinished walks in one batch, each
    /// step's case made under the contract.
    fn asking<'a>(x: &'a Answerer, mesh: &'a Mesh, k: Contract) -> Option<Box<GivenWalks<'a>>> {
        Some(Box::new(asked_walks(x, mesh, k)))
    }
    /// `count --rays-out FILE`: every ray of the views the shard holds whose camera is inside the mesh,
    /// with its view, pixel and starting tetrahedron.
    const RAYS_OUT: bool = true;
    fn judge_rays(a: &JudgeArgs, header: Value, input: Box<dyn BufRead + Send>) -> Status {
        let header = serde_json::from_value(header).map_err(|e| AnswersError::Answer {
            file: a.cases.display().to_string(),
            line: 1,
            why: format!("not a count --rays-out header: {e}"),
        })?;
        judge_scene(a, header, input)
    }
    fn rays_out(a: &CountArgs, shard: Shard, path: &std::path::Path) -> Status {
        let views = views::<Walks>(a, 0)?;
        held(shard, views.views)?;
        let scene = a.scene.load()?;
        let mut staged = crate::cli::Staged::new("--rays-out", path)?;
        let header = RaysHeader::of(&scene, views, shard, a.scene.no_faces);
        let (rays, counted_views) = header.write(&scene.mesh, &mut staged)?;
        staged.finish()?;
        println!(
            "{}: {} of {} of scene {} (walk them through `tetwalk scene export {}` and judge your answers with `tetwalk judge {} ANSWERS`)",
            path.display(),
            crate::report::counted(rays, "ray", "rays"),
            crate::report::counted(counted_views as u64, "view", "views"),
            scene.name,
            scene.name,
            path.display()
        );
        Ok(ExitCode::SUCCESS)
    }
}

/// A scene's walks computed elsewhere, judged as `count` judges its methods.
fn judge_scene(a: &JudgeArgs, header: RaysHeader, input: Box<dyn BufRead + Send>) -> Status {
    let out = JsonOut::new(a.json.as_deref())?;
    let mut dump = Dump::new(a.dump.as_deref())?;
    let scene = crate::scenes::load(&header.scene, crate::cli::faces(header.no_faces))?;
    let cases = a.cases.display().to_string();
    header.check_scene(&scene, &cases)?;
    header.check_rays(&cases, input, &scene.mesh)?;
    let mut given = GivenWalksMap::default();
    each_answer(&a.answers, |_, v| given.take(v, &scene.mesh))?;
    let mut write = |w: &WrongRay| dump.write(w);
    let file = a.answers.display().to_string();
    let report = given.judge(&scene, &header, &a.name, &file, &cases, Some(&mut write))?;
    dump.finish()?;
    print!("{}", report.table());
    out.finish(&report)?;
    Ok(a.fail.status("judge", &report.standings()))
}

/// `bench` (`--family exit-face`): walk speed per method and backend.
pub(crate) fn bench(a: BenchArgs) -> Status {
    let methods = crate::family::parse_list::<Walks>(&a.methods)?;
    crate::cli::view_count(a.views, "bench")?;
    if a.batch == 0 {
        return Err("--batch 0: a batch holds at least one ray".into());
    }
    if a.repeat == 0 {
        return Err("--repeat 0: each batch is timed at least once".into());
    }
    let baseline = match &a.baseline {
        Some(p) => Some(
            crate::cli::read_reports::<crate::engine::bench::BenchReport>(std::slice::from_ref(p))?
                .remove(0)
                .1,
        ),
        None => None,
    };
    let (width, height) = crate::cli::size(a.size.as_deref().unwrap_or("1024x1024"), false, 65536)?;
    let per_view = width as u128 * height as u128;
    crate::cli::fits(
        &format!("--size {width}x{height} --batch {}", a.batch),
        per_view.max(a.batch as u128) * crate::engine::count::bytes_per_ray(1) as u128,
    )?;
    let out = JsonOut::new(a.json.as_deref())?;
    let backends = crate::cli::open_each(&a.backend)?;
    let scene = a.scene.load()?;
    let views = crate::scenes::camera::Views::new(a.views, width, height, a.seed);
    let bar = crate::cli::progress("bench", a.views as u64, "views");
    let report = crate::engine::bench::run(
        &scene,
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
    out.done(&report.markdown(), &report)
}

/// `render shaded`, `failures` and `heat`: a view of the scene walked by the exact walk and by each
/// method ([`super::engine::frame`]).
pub(crate) fn render(a: RenderArgs) -> Status {
    let d = drawn_methods::<Walks>(&a)?;
    let mut drawn = Drawn::default();
    let backend = a.backend.open()?;
    let scene = a.scene.load()?;
    let views = crate::scenes::camera::Views::new(a.views, d.width, d.height, a.seed);
    let f = frame(&scene.mesh, &views, a.view, &d.methods, &backend)?;
    match a.what {
        What::Shaded => write(&a.out, &f.shaded(), &mut drawn)?,
        What::Heat => {
            write(&a.out, &f.heat(), &mut drawn)?;
            drawn.legend = render::HEAT_LEGEND.into();
        }
        _ => {
            let maps: Vec<Image> = (0..d.methods.len()).map(|i| f.failures(i)).collect();
            for ((name, wrong), im) in f.wrong.iter().zip(&maps) {
                let n = wrong.iter().flatten().count();
                write(&beside(&a.out, name), im, &mut drawn)?;
                println!(
                    "  {name}: {}",
                    crate::report::counted(n as u64, "wrong ray", "wrong rays")
                );
                drawn.wrong.push((name.clone(), n));
            }
            write(&a.out, &Image::tiled(&maps, 4), &mut drawn)?;
            let kinds: Vec<_> = f
                .wrong
                .iter()
                .flat_map(|(_, w)| w.iter().flatten())
                .copied()
                .collect();
            drawn.legend = render::failure_legend(&kinds);
            println!(
                "sheet order (left to right, then row by row): {}",
                d.methods
                    .iter()
                    .map(|m| m.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
    finish(drawn, d.json)
}
