//! The family's command line (a file of the command line's layer in the family's folder): `tetwalk
//! hit`, which answers its cases, `render leak`, the flags of `stress` that choose its rows and those
//! of `count`; the commands flatten every family's.

use super::TriRow;
use super::engine::{EdgeHit, LeakGrid, first_crossed, leak_case};
use super::{TriCountSettings, TriRows, Triangle};
use crate::backend::Backend;
use crate::choice::{BackendKind, Choice};
use crate::cli::answer::{Answering, methods_part};
use crate::cli::bench::Args as BenchArgs;
use crate::cli::count::{FamilyFlags, Flags};
use crate::cli::gen_cases::{Args as GenArgs, Start, generated, row, start};
use crate::cli::render::{Args as RenderArgs, Maps, square};
use crate::cli::size;
use crate::cli::stress::{Rows, Shape, or_all};
use crate::cli::{JsonOut, Status, choice};
use crate::family::Family;
use crate::family::{self, Kind};
use crate::registry::TriangleMethod;
use crate::registry::{Named, TRIANGLE_METHODS};
use crate::render::{self, Image};
use crate::scenes::closed::{MeshShape, TriAim, TriPlace};

/// Triangle rows.
#[derive(clap::Args)]
#[group(skip)]
pub(crate) struct StressFlags {
    /// Triangle rows: closed mesh shapes (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<MeshShape>(), value_delimiter = ',')]
    shapes: Vec<MeshShape>,
    /// Triangle rows: where rays are aimed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<TriAim>(), value_delimiter = ',')]
    aims: Vec<TriAim>,
    /// Triangle rows: where meshes are placed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<TriPlace>(), value_delimiter = ',')]
    places: Vec<TriPlace>,
}

impl Rows for Triangle {
    type Flags = StressFlags;
    fn own(all: &crate::cli::stress::RowFlags) -> &StressFlags {
        &all.triangle
    }
    fn given(f: &StressFlags) -> Vec<&'static str> {
        [
            ("--shapes", !f.shapes.is_empty()),
            ("--aims", !f.aims.is_empty()),
            ("--places", !f.places.is_empty()),
        ]
        .into_iter()
        .filter_map(|(flag, given)| given.then_some(flag))
        .collect()
    }
    fn chosen(f: &StressFlags, s: Shape) -> TriRows {
        TriRows {
            shapes: or_all(&f.shapes),
            aims: or_all(&f.aims),
            places: or_all(&f.places),
            flatness: s.flatness,
            ulps: s.ulps,
        }
    }
}

/// `count --family triangle`'s flags.
#[derive(clap::Args)]
#[group(skip)]
pub(crate) struct CountFlags {
    /// `--family triangle`: primary rays per packet side (1, 2, 4 or 8: packets of 1, 4, 16 or 64
    /// rays sharing the camera's origin).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=8), default_value_t = 2)]
    packet: u32,
    /// `--family triangle`: test every triangle per ray (brute force), not each tile's candidates (the
    /// counts are the same; the candidates are derived in `src/family/triangle/bins.rs` and audited).
    #[arg(long)]
    brute_force: bool,
}

impl Flags for Triangle {
    type Flags = CountFlags;
    fn own(all: &FamilyFlags) -> &CountFlags {
        &all.triangle
    }
    fn settings(f: &CountFlags) -> TriCountSettings {
        TriCountSettings {
            packet: f.packet,
            brute_force: f.brute_force,
        }
    }
}

/// Answer ray-triangle cases from JSON Lines with each ray-triangle method, judged exactly.
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(flatten)]
    common: crate::cli::answer::Common,
    /// A hit's `t` is right within this many ulps of the exact `t` (of the f32 nearest it), and
    /// always needs `0 < t < ∞` [default: 4096].
    #[arg(long, value_name = "ULPS", allow_negative_numbers = true)]
    t_ulps: Option<f64>,
    /// Also answer every case with each method's 4-wide version (seed 004's SIMD packets, where a
    /// method has one), the ray in every lane, and compare: each line of such a method says
    /// `"wide_same"`, and any case answered otherwise than by the scalar version, bit for bit, gives
    /// exit status 1. Plain f32 only (`--backend cpu`).
    #[arg(long)]
    wide: bool,
}

impl crate::cli::Io for Args {
    fn io(&self) -> crate::cli::Files {
        self.common.io()
    }
}

/// `tetwalk hit`: the cases read, answered by each method (or `--answerer`) and judged.
pub(crate) fn run(
    Args {
        common: a,
        t_ulps,
        wide,
    }: Args,
) -> Status {
    let methods = crate::family::parse_list::<Triangle>(&a.method)?;
    let t_ulps = crate::cli::t_ulps(t_ulps)?;
    if wide {
        if a.backend.backend != BackendKind::Cpu {
            return Err(format!(
                "--wide compares the 4-wide versions with the scalar ones in plain f32, where they answer alike: give --backend cpu, not {}",
                a.backend.backend.name()
            )
            .into());
        }
        if methods.iter().all(|m| m.wide.is_none()) {
            let have: Vec<&str> = TRIANGLE_METHODS
                .iter()
                .filter(|m| m.wide.is_some())
                .map(|m| m.name())
                .collect();
            return Err(format!(
                "--wide: none of the methods asked for has a 4-wide version ({} have)",
                have.join(", ")
            )
            .into());
        }
    }
    let outside = a.answerer.start::<Triangle>(&Default::default())?;
    if let Some(x) = &outside {
        if wide {
            return Err("--wide compares tetwalk's 4-wide versions; an --answerer has none".into());
        }
        return crate::cli::answer::outside::<Triangle>("hit", x, &a, refuse, t_ulps);
    }
    let backend = a.backend.open()?;
    Answering::own::<Triangle>("hit", &methods, &backend, a.input())
        .leaking()
        .by_parts(
            || {
                let mut part = methods_part::<Triangle>(&methods, &backend, t_ulps);
                part.wide = wide;
                vec![Box::new(part)]
            },
            refuse,
        )
}

/// `hit` answers ray–triangle cases only.
fn refuse(_: Kind) -> String {
    "not a ray-triangle case (tri or tris); tetwalk exit answers it".into()
}

/// `bench --family triangle`: seed 004 Figure 5's measure.
pub(crate) fn bench(a: BenchArgs) -> Status {
    if a.backend != [BackendKind::Cpu]
        || a.layouts
        || a.hilbert
        || a.baseline.is_some()
        || a.repeat != 1
    {
        return Err("--family triangle times the CPU, plain f32, best of 3; leave out --backend, --layouts, --hilbert, --repeat and --baseline".into());
    }
    crate::cli::view_count(a.views, "bench")?;
    let methods = crate::family::parse_list::<Triangle>(&a.methods)?;
    let (width, height) = crate::cli::size(a.size.as_deref().unwrap_or("256x256"), false, 4096)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let scene = a.scene.load()?;
    let views = crate::scenes::camera::Views::new(a.views, width, height, a.seed);
    let report = super::engine::speed(&scene, &views, &methods, 3)?;
    out.done(&report.markdown(), &report)
}

/// `render leak`: a sheet per ray–triangle method, exact | cpu | cpu-fma (| gpu), of the hits through
/// and beside an edge ([`super::engine::LeakGrid`]).
pub(crate) fn render(a: RenderArgs) -> Status {
    let methods = family::parse_list::<Triangle>(&a.methods)?;
    let json = JsonOut::new(a.json.as_deref())?;
    let (w, h) = size(&a.size, true, 4096)?;
    square(&a.size, w, h)?;
    let (case, pair) = leak_case(a.shape, a.place, a.seed, &methods)
        .ok_or("no ray of the edge row crosses the surface between an edge's two triangles")?;
    let grid = LeakGrid::new(&case, pair, w);
    let exact = leak_image(grid.exact(), w);
    let heading = |m: &TriangleMethod| format!("{}: hits through and beside an edge", m.name());
    let panel = |m: &TriangleMethod, b: &Backend| Ok(leak_image(&grid.of(m, b)?, w));
    let key = EdgeHit::key();
    Maps {
        exact,
        key: &key,
        legend: render::key_line("leak maps: hits on the two triangles sharing the edge, each leak ringed", &key),
        shows: format!(
            "the {} {} edge row's first case a listed method leaks through (else its first): along x, rays exactly through the edge at points of its middle half; along y, the direction moved ±{} ulp steps off it",
            a.shape.name(),
            a.place.name(),
            w / 2
        ),
    }
    .draw(&a.out, json, &methods, heading, panel)
}

/// A leak map as an image ([`EdgeHit::colour`]), each leak ringed (rays through an edge lie on one
/// row of pixels: a leak alone would vanish once the sheet is scaled down).
fn leak_image(cells: &[EdgeHit], size: u32) -> Image {
    let mut im = render::grid_image(size, cells.iter().map(|c| c.colour()));
    for (i, c) in cells.iter().enumerate() {
        if *c == EdgeHit::Neither {
            im.ring(i as u32 % size, i as u32 / size, c.colour());
        }
    }
    im
}

/// `gen-cases`' ray–triangle flags.
#[derive(clap::Args)]
#[group(id = "triangle")]
pub(crate) struct GenFlags {
    /// Write ray–triangle cases for `tetwalk hit` instead: the stress row of closed meshes of this
    /// shape, `--aim` and `--place` (`tris` lines; with the same `--flatness`, `--ulps` and `--seed`,
    /// the cases `stress --family triangle` judges).
    #[arg(long, value_parser = choice::<MeshShape>())]
    shape: Option<MeshShape>,
    /// With `--shape`: each case's triangle where the ray first crosses the mesh, alone (`tri`
    /// lines, one-triangle cases).
    #[arg(long, requires = "shape")]
    single: bool,
    /// With `--shape`: where the rays are aimed.
    #[arg(long, value_parser = choice::<TriAim>(), default_value = "edge", requires = "shape")]
    aim: TriAim,
    /// With `--shape`: where the mesh is placed.
    #[arg(long, value_parser = choice::<TriPlace>(), default_value = "origin", requires = "shape")]
    place: TriPlace,
}

/// `gen-cases --shape`: a ray–triangle stress row's cases (closed meshes, or with `--single` the
/// triangle each ray first crosses); none without `--shape`.
pub(crate) fn gen_cases(a: &GenArgs, f: &GenFlags) -> Option<Status> {
    Some(stress_row(a, f, f.shape?))
}

/// `gen-cases --shape SHAPE`: the row of closed meshes of `shape`, `--aim` and `--place`.
fn stress_row(a: &GenArgs, f: &GenFlags, shape: MeshShape) -> Status {
    let Start {
        flatness,
        out,
        contract,
    } = start::<Triangle>(a, 1e-3, || Ok(()))?;
    let rows = TriRows {
        shapes: vec![shape],
        aims: vec![f.aim],
        places: vec![f.place],
        flatness,
        ulps: a.ulps,
    };
    let at = TriRow {
        shape,
        aim: f.aim,
        place: f.place,
    };
    let written = row::<Triangle>(&rows, at, a, &contract, |c, x| {
        if !f.single {
            return Some(Triangle::case_json(c));
        }
        Some(Triangle::case_json(&first_crossed(c, x)?))
    })?;
    generated(
        out,
        &serde_json::json!({
            "shape": shape, "aim": f.aim, "place": f.place, "flatness": flatness,
            "ulps": a.ulps, "seed": a.seed, "single": f.single, "scale": a.scale,
            "contract": contract, "written": written,
        }),
    )
}
