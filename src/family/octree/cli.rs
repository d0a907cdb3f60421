//! The family's command line (a file of the command line's layer in the family's folder): `tetwalk
//! box-exit`, which answers its cases, `render octree-heat`, the flags of `stress` that choose its
//! rows and those of `count`; the commands flatten every family's.

use super::CellRow;
use super::engine::cells_per_pixel;
use super::{CellRows, OctreeCells, OctreeCountSettings};
use crate::choice::Model;
use crate::cli::answer::{Answering, methods_part};
use crate::cli::count::{FamilyFlags, Flags};
use crate::cli::gen_cases::{Args as GenArgs, Start, generated, row, start};
use crate::cli::render::{Args as RenderArgs, Drawn, finish, write};
use crate::cli::stress::{Rows, Shape, or_all};
use crate::cli::{JsonOut, size};
use crate::cli::{Status, choice, registered};
use crate::family::Family;
use crate::family::{self, Kind, Triangle};
use crate::registry::{ByName, Named, TriangleMethod};
use crate::render;
use crate::scenes::cells::{CellAim, CellPlace};

/// Octree rows.
#[derive(clap::Args)]
#[group(skip)]
pub(crate) struct StressFlags {
    /// Octree rows: where rays leave the cell (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<CellAim>(), value_delimiter = ',')]
    cell_aims: Vec<CellAim>,
    /// Octree rows: where cells are placed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<CellPlace>(), value_delimiter = ',')]
    cell_places: Vec<CellPlace>,
}

impl Rows for OctreeCells {
    type Flags = StressFlags;
    fn own(all: &crate::cli::stress::RowFlags) -> &StressFlags {
        &all.octree
    }
    fn given(f: &StressFlags) -> Vec<&'static str> {
        [
            ("--cell-aims", !f.cell_aims.is_empty()),
            ("--cell-places", !f.cell_places.is_empty()),
        ]
        .into_iter()
        .filter_map(|(flag, given)| given.then_some(flag))
        .collect()
    }
    fn chosen(f: &StressFlags, s: Shape) -> CellRows {
        CellRows {
            aims: or_all(&f.cell_aims),
            places: or_all(&f.cell_places),
            ulps: s.ulps,
        }
    }
}

/// `count --family octree`'s flags.
#[derive(clap::Args)]
#[group(skip)]
pub(crate) struct CountFlags {
    /// `--family octree`: the octree's deepest level (seed 001: 8 for the bunny).
    #[arg(long, default_value_t = 8)]
    depth: u32,
    /// `--family octree`: split a node while it holds more triangles than this.
    #[arg(long, default_value_t = 6)]
    capacity: usize,
    /// `--family octree`: the ray–triangle method testing each leaf's triangles.
    #[arg(long, value_parser = registered::<TriangleMethod>(), default_value = "mt")]
    triangle_method: ByName<TriangleMethod>,
}

impl Flags for OctreeCells {
    type Flags = CountFlags;
    fn own(all: &FamilyFlags) -> &CountFlags {
        &all.octree
    }
    fn settings(f: &CountFlags) -> OctreeCountSettings {
        OctreeCountSettings {
            octree: crate::octree::Settings {
                depth: f.depth,
                capacity: f.capacity,
            },
            triangle_method: f.triangle_method,
        }
    }
}

/// The exit face and quarter of octree cells (seed 001), each method's beside the exact ones.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// A method name, a comma-separated list, or `all`.
    #[arg(long, default_value = "all")]
    method: String,
    #[command(flatten)]
    backend: crate::cli::BackendArg,
    #[command(flatten)]
    fail: crate::cli::FailArg,
    /// Also write a summary (lines, errors, per method right / wrong / lines not crossing the open
    /// box) as JSON here.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
    /// JSON Lines file of cases `{"box": [[lx, ly, lz], [hx, hy, hz]], "org", "dir"}` (found cases
    /// too); standard input when absent.
    file: Option<std::path::PathBuf>,
}

impl crate::cli::Io for Args {
    fn io(&self) -> crate::cli::Files {
        crate::cli::Files::default()
            .input("FILE", self.file.as_deref())
            .output("--json", self.json.as_deref())
    }
}

/// `tetwalk box-exit`: the cases read, answered by each method (or `--answerer`) and judged.
pub(crate) fn run(a: Args) -> Status {
    let methods = crate::family::parse_list::<OctreeCells>(&a.method)?;
    let backend = a.backend.open()?;
    Answering::own::<OctreeCells>(
        "box-exit",
        &methods,
        &backend,
        crate::cli::answer::Input {
            file: a.file.as_deref(),
            json: a.json.as_deref(),
            fail: a.fail,
        },
    )
    .missing()
    .by_parts(
        || {
            vec![Box::new(methods_part::<OctreeCells>(
                &methods, &backend, 0.0,
            ))]
        },
        refuse,
    )
}

/// `box-exit` answers octree cell cases only.
fn refuse(_: Kind) -> String {
    "not an octree cell case: box-exit answers {\"box\", \"org\", \"dir\"}".into()
}

/// `render octree-heat`: octree cells per pixel ([`super::engine::cells_per_pixel`]).
pub(crate) fn render(a: RenderArgs) -> Status {
    let names = if a.methods == "all" {
        "portalez16-direction"
    } else {
        &a.methods
    };
    let method = *family::parse_list::<OctreeCells>(names)?
        .first()
        .ok_or("--methods names no octree method")?;
    let json = JsonOut::new(a.json.as_deref())?;
    let (w, h) = size(&a.size, false, 4096)?;
    let scene = a.scene.load()?;
    let views = crate::scenes::camera::Views::new(a.views, w, h, a.seed);
    let hit = family::by_name::<Triangle>("mt")?.hit(Model::Plain);
    let cells = cells_per_pixel(
        &scene.mesh,
        &views,
        a.view,
        method,
        hit,
        crate::octree::Settings::PAPER,
    )?;
    let im = render::octree_heat(w, h, &cells, method.name());
    let mut drawn = Drawn::default();
    write(&a.out, &im, &mut drawn)?;
    drawn.legend = render::OCTREE_HEAT_LEGEND.into();
    finish(drawn, json)
}

/// `gen-cases`' octree flags.
#[derive(clap::Args)]
#[group(id = "octree")]
pub(crate) struct GenFlags {
    /// Write octree cell cases for `tetwalk box-exit` instead: the stress row of cells where rays
    /// leave as this says, at `--cell-place` (`box` lines; the cases `stress --family octree`
    /// judges).
    #[arg(long, value_parser = choice::<CellAim>())]
    cell_aim: Option<CellAim>,
    /// With `--cell-aim`: where the cells are placed.
    #[arg(long, value_parser = choice::<CellPlace>(), default_value = "origin", requires = "cell_aim")]
    cell_place: CellPlace,
}

/// `gen-cases --cell-aim`: an octree stress row's cells; none without `--cell-aim`.
pub(crate) fn gen_cases(a: &GenArgs, f: &GenFlags) -> Option<Status> {
    Some(stress_row(a, f, f.cell_aim?))
}

/// `gen-cases --cell-aim AIM`: the row of cells where rays leave as `aim` says, at `--cell-place`.
fn stress_row(a: &GenArgs, f: &GenFlags, aim: CellAim) -> Status {
    let Start { out, contract, .. } = start::<OctreeCells>(a, 1.0, || Ok(()))?;
    let rows = CellRows {
        aims: vec![aim],
        places: vec![f.cell_place],
        ulps: a.ulps,
    };
    let at = CellRow {
        aim,
        place: f.cell_place,
    };
    let written = row::<OctreeCells>(&rows, at, a, &contract, |c, _| {
        Some(OctreeCells::case_json(c))
    })?;
    generated(
        out,
        &serde_json::json!({
            "cell_aim": aim, "cell_place": f.cell_place, "ulps": a.ulps, "seed": a.seed,
            "scale": a.scale, "contract": contract, "written": written,
        }),
    )
}
