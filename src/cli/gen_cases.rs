//! `tetwalk gen-cases`: generated (tetrahedron, ray) cases as JSON Lines, for `tetwalk exit`; with
//! `--shape`, a ray–triangle stress row's cases for `tetwalk hit` (closed meshes, or with `--single`
//! the triangle each ray first crosses); with `--cell-aim`, an octree stress row's cells for
//! `tetwalk box-exit`. A stress row's cases are exactly those `tetwalk stress` judges for the same
//! arguments and seed.

use super::{JsonOut, Status, choice};
use crate::cases::{Case, HitCase};
use crate::exact::classify;
use crate::family::contract::{Contract, cases_within};
use crate::family::exit_face::{ExitRow, ExitRows, TetRow};
use crate::family::octree::{CellRow, CellRows};
use crate::family::triangle::{TriRow, TriRows};
use crate::family::{ExitFace, Family, OctreeCells, Scale, Triangle};
use crate::scenes::cells::{CellAim, CellPlace};
use crate::scenes::closed::{MeshShape, TriAim, TriPlace};
use crate::scenes::rng;
use crate::scenes::tets::{self, Target, TetShape};
use glam::Vec3;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// How the ray meets the tetrahedron.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Rays {
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

#[derive(clap::Args)]
pub struct Args {
    /// The tetrahedron's shape (`--family` is an older name for it).
    #[arg(long, alias = "family", value_parser = choice::<TetShape>(), default_value = "well")]
    tet_shape: TetShape,
    /// How the ray meets the tetrahedron.
    #[arg(long, value_enum, default_value = "stab")]
    rays: Rays,
    /// In (0, 1]; smaller is flatter [default: 1 for tetrahedra, the stress rows' 0.001 with
    /// --shape].
    #[arg(long, allow_negative_numbers = true)]
    flatness: Option<f32>,
    /// Largest offset of the near-* rays, in ulps of the case's largest coordinate (so a zero
    /// coordinate moves as far as the others).
    #[arg(long, allow_negative_numbers = true, default_value_t = 4)]
    ulps: i32,
    /// Move each case this far from the origin along (1, 1, 1) (rounded to f32).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    offset: f32,
    /// Cases to write (at most 100,000,000).
    #[arg(long, allow_negative_numbers = true, default_value_t = 100)]
    count: usize,
    /// Seed of the generator.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// Give each case its exact entry face (the lowest one) when it has one.
    #[arg(long)]
    with_entry: bool,
    /// Write an exit-face stress row's cases instead (`tet` lines for `tetwalk exit`): with the same
    /// `--flatness` (0.001 by default, as there), `--ulps` and `--seed`, the cases `stress --rows ROW`
    /// judges, in its order.
    #[arg(long, value_parser = choice::<TetRow>(), conflicts_with_all = ["tet_shape", "rays", "with_entry"])]
    row: Option<TetRow>,
    /// Write ray–triangle cases for `tetwalk hit` instead: the stress row of closed meshes of this
    /// shape, `--aim` and `--place` (`tris` lines; with the same `--flatness`, `--ulps` and `--seed`,
    /// the cases `stress --family triangle` judges).
    #[arg(long, value_parser = choice::<MeshShape>(), conflicts_with_all = ["tet_shape", "rays", "offset", "with_entry", "row"])]
    shape: Option<MeshShape>,
    /// With `--shape`: each case's triangle where the ray first crosses the mesh, alone (`tri`
    /// lines, one-triangle cases).
    #[arg(long, requires = "shape")]
    single: bool,
    /// Write octree cell cases for `tetwalk box-exit` instead: the stress row of cells where rays
    /// leave as this says, at `--cell-place` (`box` lines; the cases `stress --family octree`
    /// judges).
    #[arg(long, value_parser = choice::<CellAim>(), conflicts_with_all = ["tet_shape", "rays", "offset", "with_entry", "shape", "row"])]
    cell_aim: Option<CellAim>,
    /// With `--cell-aim`: where the cells are placed.
    #[arg(long, value_parser = choice::<CellPlace>(), default_value = "origin", requires = "cell_aim")]
    cell_place: CellPlace,
    /// Every case at a power-of-two scale, as `stress --scale` takes it (`E`, or `E/D` for the
    /// direction at its own).
    #[arg(long, allow_hyphen_values = true, value_parser = Scale::parse, default_value = "0")]
    scale: Scale,
    /// With `--shape`: where the rays are aimed.
    #[arg(long, value_parser = choice::<TriAim>(), default_value = "edge", requires = "shape")]
    aim: TriAim,
    /// With `--shape`: where the mesh is placed.
    #[arg(long, value_parser = choice::<TriPlace>(), default_value = "origin", requires = "shape")]
    place: TriPlace,
    #[command(flatten)]
    contract: super::ContractArg,
    /// Also write what was generated (settings and count) as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default().output("--json", self.json.as_deref())
    }
}

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

/// The stress row `row` of family `F` under `rows`: its first `count` cases (the cases `stress` judges
/// there), each at `scale`, written as `line` makes them (`None`: a case it leaves out, such as a ray
/// that misses every triangle under `--single`); an error, with nothing written, when some of them
/// cannot be made (the oracle refuses one, or it rounds at `scale`), each made to hold `contract`.
/// The number of lines written.
fn row<F: Family>(
    rows: &F::Rows,
    row: F::Row,
    a: &Args,
    contract: &Contract,
    line: impl Fn(&F::Case, &F::Truth) -> Option<serde_json::Map<String, serde_json::Value>> + Sync,
) -> Result<usize, super::Error> {
    let case = |i: usize| -> Option<(F::Case, F::Truth)> {
        let (c, x) = F::case(rows, row, a.seed, i)?;
        if a.scale.is_one() {
            return Some((c, x));
        }
        F::scaled(&c, a.scale)
            .filter(crate::family::readable::<F>)
            .and_then(|c| Some((c, F::truth(&c).ok()?)))
    };
    // Every case made before a line is written: a short run writes nothing.
    let made = cases_within::<F>(contract, a.count, case);
    if made.len() < a.count {
        return Err(format!(
            "only {} of the row's first {} cases can be made at scale {}{} (the others round there, or the oracle refuses them; stress judges the same {}): nothing was written",
            made.len(),
            a.count,
            a.scale,
            if contract.is_default() { String::new() } else { format!(" within the contract ({})", contract.describe()) },
            made.len()
        )
        .into());
    }
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    let mut written = 0;
    for (c, x) in &made {
        if let Some(obj) = line(c, x) {
            writeln!(w, "{}", serde_json::Value::Object(obj))?;
            written += 1;
        }
    }
    w.flush()?;
    Ok(written)
}

pub fn run(a: Args) -> Status {
    let flatness = a
        .flatness
        .unwrap_or(if a.shape.is_some() || a.row.is_some() {
            1e-3
        } else {
            1.0
        });
    super::generator(flatness, a.ulps)?;
    if a.count > 100_000_000 {
        return Err(format!("--count {} is more than 100,000,000 cases", a.count).into());
    }
    if !a.offset.is_finite() {
        return Err(format!("--offset {} is not finite", a.offset).into());
    }
    let out = JsonOut::new(a.json.as_deref())?;
    // The contract, checked for the family of the cases written.
    let contract = if a.shape.is_some() {
        a.contract.contract::<Triangle>()?
    } else if a.cell_aim.is_some() {
        a.contract.contract::<OctreeCells>()?
    } else {
        a.contract.contract::<ExitFace>()?
    };
    let mut r = rng(a.seed);
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    if let Some(shape) = a.shape {
        let rows = TriRows {
            shapes: vec![shape],
            aims: vec![a.aim],
            places: vec![a.place],
            flatness,
            ulps: a.ulps,
        };
        let at = TriRow {
            shape,
            aim: a.aim,
            place: a.place,
        };
        let written = row::<Triangle>(&rows, at, &a, &contract, |c, x| {
            if !a.single {
                return Some(Triangle::case_json(c));
            }
            let first = x.first_crossing()?.holding[0] as usize;
            Some(Triangle::case_json(&HitCase::single(
                c.tris()[first],
                c.ray(),
            )))
        })?;
        out.finish(&serde_json::json!({
            "shape": shape, "aim": a.aim, "place": a.place, "flatness": flatness,
            "ulps": a.ulps, "seed": a.seed, "single": a.single, "scale": a.scale,
            "contract": contract, "written": written,
        }))?;
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(at) = a.row {
        let rows = ExitRows {
            rows: vec![at],
            flatness,
            ulps: a.ulps,
            offset: a.offset,
            ..ExitRows::default()
        };
        let written = row::<ExitFace>(&rows, ExitRow { row: at }, &a, &contract, |c, _| {
            Some(ExitFace::case_json(c))
        })?;
        out.finish(&serde_json::json!({
            "row": at, "flatness": flatness, "ulps": a.ulps, "offset": a.offset, "seed": a.seed, "scale": a.scale,
            "contract": contract, "written": written,
        }))?;
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(aim) = a.cell_aim {
        let rows = CellRows {
            aims: vec![aim],
            places: vec![a.cell_place],
            ulps: a.ulps,
        };
        let at = CellRow {
            aim,
            place: a.cell_place,
        };
        let written = row::<OctreeCells>(&rows, at, &a, &contract, |c, _| {
            Some(OctreeCells::case_json(c))
        })?;
        out.finish(&serde_json::json!({
            "cell_aim": aim, "cell_place": a.cell_place, "ulps": a.ulps, "seed": a.seed,
            "scale": a.scale, "contract": contract, "written": written,
        }))?;
        return Ok(ExitCode::SUCCESS);
    }
    let mut written = 0;
    for _ in 0..a.count.saturating_mul(100) {
        if written == a.count {
            break;
        }
        let generated = match a.rays {
            Rays::Stab => {
                let t = tets::tet(a.tet_shape, flatness, &mut r);
                Some((t, tets::stabbing_ray(&t, &mut r)))
            }
            Rays::Edge => tets::through(a.tet_shape, flatness, Target::Edge, &mut r),
            Rays::Vertex => tets::through(a.tet_shape, flatness, Target::Vertex, &mut r),
            Rays::NearEdge => tets::near(a.tet_shape, flatness, Target::Edge, a.ulps, &mut r),
            Rays::NearVertex => tets::near(a.tet_shape, flatness, Target::Vertex, a.ulps, &mut r),
        };
        let Some((t, ray)) =
            generated.and_then(|(t, ray)| tets::translated(&t, &ray, Vec3::splat(a.offset)))
        else {
            continue;
        };
        // Only cases `exit` can judge: finite, a direction, a tetrahedron that is not flat.
        if crate::exact::check_ray(&t, &ray).is_err() || crate::tet::orientation(&t) == 0 {
            continue;
        }
        let entry = if a.with_entry {
            classify(&t, &ray)
                .ok()
                .and_then(|c| c.entry.first())
                .map(|f| f as u8)
        } else {
            None
        };
        let case = Case {
            tet: t,
            org: ray.org,
            dir: ray.dir,
            entry,
        };
        // At another scale: kept where it still reads back and the oracle still judges it.
        let case = if a.scale.is_one() {
            case
        } else {
            match ExitFace::scaled(&case, a.scale)
                .filter(crate::family::readable::<ExitFace>)
                .filter(|c| ExitFace::truth(c).is_ok())
            {
                Some(c) => c,
                None => continue,
            }
        };
        // Within the contract: made to hold it, kept where it then does.
        let case = if contract.is_default() {
            case
        } else {
            match ExitFace::contracted(&contract, &case, written as u64)
                .filter(|c| ExitFace::truth(c).is_ok_and(|x| ExitFace::holds(&contract, c, &x)))
            {
                Some(c) => c,
                None => continue,
            }
        };
        writeln!(
            w,
            "{}",
            serde_json::Value::Object(ExitFace::case_json(&case))
        )?;
        written += 1;
    }
    w.flush()?;
    if written < a.count {
        return Err(format!(
            "only {written} of {} cases could be generated with these settings (in {} tries: the others' tetrahedra were flat in f32, their rays missed the edge or vertex, or left f32's range)",
            a.count,
            a.count.saturating_mul(100)
        )
        .into());
    }
    out.finish(&Generated {
        tet_shape: a.tet_shape,
        rays: a.rays,
        flatness,
        ulps: a.ulps,
        offset: a.offset,
        seed: a.seed,
        with_entry: a.with_entry,
        scale: a.scale,
        contract,
        written,
    })?;
    Ok(ExitCode::SUCCESS)
}
