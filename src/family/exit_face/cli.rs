//! The family's command line (a file of the command line's layer in the family's folder): `tetwalk
//! exit`, which answers its cases, `render predicate`, and the flags of `stress` that choose its rows;
//! the commands flatten every family's.

use super::ExitRow;
use super::engine::{free_cases, predicate_case, predicate_grid};
use super::{ExitFace, ExitRows, TetRow};
use crate::backend::Backend;
use crate::choice::Model;
use crate::cli::answer::{Answering, methods_part};
use crate::cli::gen_cases::{Args as GenArgs, Start, generated, row, start, write_lines};
use crate::cli::render::{Args as RenderArgs, Maps, drawn_methods, square};
use crate::cli::stress::{Rows, Shape, or_all};
use crate::cli::{Status, WgslArg, choice};
use crate::family::contract::Contract;
use crate::family::{Family, Scale};
use crate::family::{Kind, Walks};
use crate::registry::{Method, Named, reference};
use crate::render;
use crate::scenes::rng;
use crate::scenes::tets::TetShape;
use crate::scenes::tets::{self, Target};

/// Exit-face rows.
#[derive(clap::Args)]
#[group(skip)]
pub(crate) struct StressFlags {
    /// Exit-face rows (comma-separated) [default: all].
    #[arg(long, alias = "families", value_parser = choice::<TetRow>(), value_delimiter = ',')]
    rows: Vec<TetRow>,
    /// Exit-face rows: every case moved this far from the origin along (1, 1, 1) (rounded to f32;
    /// each case judged as it then is).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0, value_parser = finite)]
    offset: f32,
}

/// A finite f32.
fn finite(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(x) => Err(format!("{x} is not finite")),
        Err(e) => Err(e.to_string()),
    }
}

impl Rows for ExitFace {
    type Flags = StressFlags;
    fn own(all: &crate::cli::stress::RowFlags) -> &StressFlags {
        &all.exit_face
    }
    fn given(f: &StressFlags) -> Vec<&'static str> {
        [
            ("--rows", !f.rows.is_empty()),
            ("--offset", f.offset != 0.0),
        ]
        .into_iter()
        .filter_map(|(flag, given)| given.then_some(flag))
        .collect()
    }
    fn chosen(f: &StressFlags, s: Shape) -> ExitRows {
        ExitRows {
            rows: or_all(&f.rows),
            flatness: s.flatness,
            ulps: s.ulps,
            offset: f.offset,
            ..ExitRows::default()
        }
    }
}

/// Answer cases (or found cases) from JSON Lines with each method, judged exactly.
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(flatten)]
    common: crate::cli::answer::Common,
    #[command(flatten)]
    wgsl: WgslArg,
}

impl crate::cli::Io for Args {
    fn io(&self) -> crate::cli::Files {
        self.common.io().input("--wgsl", self.wgsl.wgsl.as_deref())
    }
}

/// `tetwalk exit`: the cases read, answered by each method (or `--answerer`) and judged.
pub(crate) fn run(Args { common: a, wgsl }: Args) -> Status {
    let (backend, methods) = wgsl.open::<ExitFace>(a.backend, &a.method)?;
    let outside = a.answerer.start::<ExitFace>(&Default::default())?;
    if let Some(x) = &outside {
        return crate::cli::answer::outside::<ExitFace>("exit", x, &a, refuse_walks, 0.0);
    }
    Answering::own::<ExitFace>("exit", &methods, &backend, a.input())
        .missing()
        .by_parts(
            || {
                vec![
                    Box::new(methods_part::<ExitFace>(&methods, &backend, 0.0)),
                    Box::new(methods_part::<Walks>(&methods, &backend, 0.0)),
                ]
            },
            refuse,
        )
}

/// Why `exit --answerer` answers no case of family `k`.
fn refuse_walks(k: Kind) -> String {
    match k {
        Kind::Walk => "a walk case: an answerer answers one tetrahedron's cases (count --answerer walks a scene through it)".into(),
        k => refuse(k),
    }
}

/// Why `exit` answers no case of family `k`.
fn refuse(k: Kind) -> String {
    match k {
        Kind::Triangle => "a ray-triangle case: tetwalk hit answers it",
        _ => "an octree cell case: tetwalk box-exit answers it",
    }
    .into()
}

/// `render predicate`: a sheet per method, the exit faces over a grid of ulp steps of a case's origin
/// ([`super::engine::predicate_grid`]), exact | cpu | cpu-fma (| gpu).
pub(crate) fn render(a: RenderArgs) -> Status {
    let d = drawn_methods::<ExitFace>(&a)?;
    let (w, h) = (d.width, d.height);
    square(&a.size, w, h)?;
    let case = predicate_case(a.tet_shape, a.through == "edge", a.seed)
        .ok_or("no case could be generated")?;
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let exact = render::face_image(&predicate_grid(&case, w, reference(), &cpu)?, w);
    let heading = |m: &Method| {
        format!(
            "{}: exit face, origin moved {} ulps in x and y",
            m.name(),
            w / 2
        )
    };
    let panel =
        |m: &Method, b: &Backend| Ok(render::face_image(&predicate_grid(&case, w, m, b)?, w));
    Maps {
        exact,
        key: &render::predicate_key(),
        legend: render::predicate_legend(),
        shows: format!("origin moved ±{} ulps in x (right) and y (up)", w / 2),
    }
    .draw(&a.out, d.json, &d.methods, heading, panel)
}

/// How the ray meets the tetrahedron.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum Rays {
    /// Through two random face points.
    Stab,
    /// Exactly through an edge.
    Edge,
    /// Exactly through a vertex.
    Vertex,
    /// Within k ulps (of the case's largest coordinate) of an edge.
    NearEdge,
    /// Within k ulps (of the case's largest coordinate) of a vertex.
    NearVertex,
}

/// `gen-cases`' exit-face flags.
#[derive(clap::Args)]
#[group(id = "exit-face")]
pub(crate) struct GenFlags {
    /// The tetrahedron's shape (`--family` is an older name for it).
    #[arg(long, alias = "family", value_parser = choice::<TetShape>(), default_value = "well")]
    tet_shape: TetShape,
    /// How the ray meets the tetrahedron.
    #[arg(long, value_enum, default_value = "stab")]
    rays: Rays,
    /// Move each case this far from the origin along (1, 1, 1) (rounded to f32).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    offset: f32,
    /// Give each case its exact entry face (the lowest one) when it has one.
    #[arg(long)]
    with_entry: bool,
    /// Write an exit-face stress row's cases instead (`tet` lines for `tetwalk exit`): with the same
    /// `--flatness` (0.001 by default, as there), `--ulps` and `--seed`, the cases `stress --rows ROW`
    /// judges, in its order.
    #[arg(long, value_parser = choice::<TetRow>(), conflicts_with_all = ["tet_shape", "rays", "with_entry"])]
    row: Option<TetRow>,
}

/// What `gen-cases` generated, as `--json` writes it.
#[derive(serde::Serialize)]
struct Generated {
    tet_shape: TetShape,
    rays: Rays,
    flatness: f32,
    ulps: i32,
    offset: f32,
    seed: u64,
    with_entry: bool,
    #[serde(skip_serializing_if = "Scale::is_one")]
    scale: Scale,
    /// What every case holds (`--origin`, `--unit-direction`, …).
    contract: Contract,
    written: usize,
}

/// `gen-cases`' exit-face cases (the family that writes when no other's flags ask): with `--row`, a
/// stress row's; else (tetrahedron, ray) cases of `--tet-shape` and `--rays`, for `tetwalk exit`.
pub(crate) fn gen_cases(a: &GenArgs, f: &GenFlags) -> Option<Status> {
    Some(match f.row {
        Some(at) => stress_row(a, f, at),
        None => free(a, f),
    })
}

/// `gen-cases --row`: an exit-face stress row's cases.
fn stress_row(a: &GenArgs, f: &GenFlags, at: TetRow) -> Status {
    let Start {
        flatness,
        out,
        contract,
    } = start::<ExitFace>(a, 1e-3, || finite_offset(f.offset))?;
    let rows = ExitRows {
        rows: vec![at],
        flatness,
        ulps: a.ulps,
        offset: f.offset,
        ..ExitRows::default()
    };
    let written = row::<ExitFace>(&rows, ExitRow { row: at }, a, &contract, |c, _| {
        Some(ExitFace::case_json(c))
    })?;
    generated(
        out,
        &serde_json::json!({
            "row": at, "flatness": flatness, "ulps": a.ulps, "offset": f.offset, "seed": a.seed, "scale": a.scale,
            "contract": contract, "written": written,
        }),
    )
}

/// `--offset` finite.
fn finite_offset(offset: f32) -> Result<(), crate::cli::Error> {
    if !offset.is_finite() {
        return Err(format!("--offset {offset} is not finite").into());
    }
    Ok(())
}

/// `gen-cases`' (tetrahedron, ray) cases of `--tet-shape` and `--rays`.
fn free(a: &GenArgs, f: &GenFlags) -> Status {
    let Start {
        flatness,
        out,
        contract,
    } = start::<ExitFace>(a, 1.0, || finite_offset(f.offset))?;
    let mut r = rng(a.seed);
    let make = || match f.rays {
        Rays::Stab => {
            let t = tets::tet(f.tet_shape, flatness, &mut r);
            Some((t, tets::stabbing_ray(&t, &mut r)))
        }
        Rays::Edge => tets::through(f.tet_shape, flatness, Target::Edge, &mut r),
        Rays::Vertex => tets::through(f.tet_shape, flatness, Target::Vertex, &mut r),
        Rays::NearEdge => tets::near(f.tet_shape, flatness, Target::Edge, a.ulps, &mut r),
        Rays::NearVertex => tets::near(f.tet_shape, flatness, Target::Vertex, a.ulps, &mut r),
    };
    let cases = free_cases(
        a.count.saturating_mul(100),
        make,
        f.offset,
        f.with_entry,
        a.scale,
        &contract,
    );
    let written = write_lines(cases.take(a.count).map(|c| ExitFace::case_json(&c)))?;
    if written < a.count {
        return Err(format!(
            "only {written} of {} cases could be generated with these settings (in {} tries: the others' tetrahedra were flat in f32, their rays missed the edge or vertex, or left f32's range)",
            a.count,
            a.count.saturating_mul(100)
        )
        .into());
    }
    generated(
        out,
        &Generated {
            tet_shape: f.tet_shape,
            rays: f.rays,
            flatness,
            ulps: a.ulps,
            offset: f.offset,
            seed: a.seed,
            with_entry: f.with_entry,
            scale: a.scale,
            contract,
            written,
        },
    )
}
