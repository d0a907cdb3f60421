//! The family's command line (a file of the command line's layer in the family's folder): `tetwalk
//! exit`, which answers its cases, `render predicate`, and the flags of `stress` that choose its rows;
//! the commands flatten every family's.

use super::engine::predicate_grid;
use super::{ExitFace, ExitRows, TetRow};
use crate::backend::Backend;
use crate::cases::Case;
use crate::cli::answer::{Answered, Answering, Part};
use crate::cli::render::{
    Args as RenderArgs, Drawn, Maps, drawn_methods, finish, map_backends, square,
};
use crate::cli::stress::{Rows, Shape, or_all};
use crate::cli::{Status, WgslArg, choice};
use crate::family::{Kind, Walks};
use crate::methods::Model;
use crate::registry::{Method, Named, reference};
use crate::render;
use crate::scenes::tets::{self, Target};

/// Exit-face rows.
#[derive(clap::Args)]
pub struct StressFlags {
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
pub struct Args {
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
pub fn run(Args { common: a, wgsl }: Args) -> Status {
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
                    Box::new(Part::<ExitFace>::new(
                        Answered::Methods(&methods, &backend),
                        0.0,
                    )),
                    Box::new(Part::<Walks>::new(
                        Answered::Methods(&methods, &backend),
                        0.0,
                    )),
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
    let mut drawn = Drawn::default();
    square(&a.size, w, h)?;
    let target = if a.through == "edge" {
        Target::Edge
    } else {
        Target::Vertex
    };
    let (tet, ray) = tets::through(a.tet_shape, 1.0, target, &mut crate::scenes::rng(a.seed))
        .ok_or("no case could be generated")?;
    let case = Case {
        tet,
        org: ray.org,
        dir: ray.dir,
        entry: None,
    };
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let exact = render::face_image(&predicate_grid(&case, w, reference(), &cpu)?, w);
    let (backends, gpu_name) = map_backends();
    let heading = |m: &Method| {
        format!(
            "{}: exit face, origin moved {} ulps in x and y",
            m.name(),
            w / 2
        )
    };
    let panel =
        |m: &Method, b: &Backend| Ok(render::face_image(&predicate_grid(&case, w, m, b)?, w));
    let key = render::predicate_key();
    let maps = Maps {
        exact: &exact,
        backends: &backends,
        key: &key,
    };
    maps.write(&a.out, &d.methods, heading, panel, &mut drawn)?;
    drawn.legend = render::predicate_legend();
    println!(
        "each sheet: exact | cpu | cpu-fma{}; origin moved ±{} ulps in x (right) and y (up)",
        gpu_name.map_or(String::new(), |g| format!(" | {g}")),
        w / 2
    );
    finish(drawn, d.json)
}
