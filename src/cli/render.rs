//! `tetwalk render`: shaded renders, failure maps, heat maps and predicate maps as PNG.

use super::{BackendArg, JsonOut, Status, choice};
use crate::backend::{Backend, BackendKind};
use crate::cases::Case;
use crate::choice::Choice;
use crate::family::{self, OctreeCells, Triangle, Walks};
use crate::methods::Model;
use crate::registry::{Method, Named, TriangleMethod, reference};
use crate::render::{self, Image};
use crate::scenes::camera::Views;
use crate::scenes::closed::{MeshShape, TriPlace};
use crate::scenes::tets::{self, Target, TetShape};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum What {
    /// Flat-shaded view of the scene.
    Shaded,
    /// Each method's wrong rays coloured by kind, and a sheet of all methods side by side.
    Failures,
    /// Tetrahedra traversed per pixel.
    Heat,
    /// Seed 001's octree cells traversed per pixel by the first octree method of `--methods` (each
    /// leaf's triangles tested with `mt`), the octree of depth 8 and leaf capacity 6.
    OctreeHeat,
    /// Exit faces over a grid of ulp steps of the ray origin, per method beside the exact answer.
    Predicate,
    /// Ray–triangle methods around a shared edge of a closed mesh (a case of the stress rows' `edge`
    /// row): which of its two triangles each reports (one, the other, both, or none of the mesh: a
    /// leak) for rays exactly through the edge at points along it (the middle row) and a few ulps
    /// beside it, per method beside the exact answer.
    Leak,
}

#[derive(clap::Args)]
pub struct Args {
    /// What to draw.
    #[arg(value_enum)]
    what: What,
    /// A built-in scene, a TetGen stem, or a Gmsh, VTK or MEDIT file (not for predicate maps).
    #[arg(long, default_value = "bunny-quality")]
    scene: String,
    /// Accept a scene without constrained faces (no TetGen `.face` or an empty one, no triangles in
    /// another format).
    #[arg(long)]
    no_faces: bool,
    /// Which of `--views` viewpoints, 0-based (placed as `tetwalk count` places them).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0)]
    view: usize,
    /// Viewpoints on the sphere around the model, as in `tetwalk count`.
    #[arg(long, allow_negative_numbers = true, default_value_t = 160)]
    views: usize,
    /// WxH for scenes; W for predicate maps (square).
    #[arg(long, default_value = "512x512")]
    size: String,
    /// Methods (comma-separated, or all).
    #[arg(long, default_value = "all")]
    methods: String,
    /// Where the methods run, for scenes (predicate and leak maps show every backend side by side,
    /// and take no other).
    #[command(flatten)]
    backend: BackendArg,
    /// Predicate maps: the tetrahedron's shape (`--family` is an older name for it).
    #[arg(long, alias = "family", value_parser = choice::<TetShape>(), default_value = "well")]
    tet_shape: TetShape,
    /// Predicate maps: what the ray goes exactly through.
    #[arg(long, value_parser = ["edge", "vertex"], default_value = "edge")]
    through: String,
    /// Leak maps: the closed mesh.
    #[arg(long, value_parser = choice::<MeshShape>(), default_value = "tetrahedron")]
    shape: MeshShape,
    /// Leak maps: where the mesh is placed.
    #[arg(long, value_parser = choice::<TriPlace>(), default_value = "embree")]
    place: TriPlace,
    /// Seed: of the viewpoints (as `tetwalk count --seed`), or of the predicate or leak map's case.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// Output PNG (per-method images are written beside it, suffixed with the method).
    #[arg(long, default_value = "tetwalk.png")]
    out: PathBuf,
    /// Also write what was drawn (files, wrong rays per method) as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default()
            .scene("--scene", &self.scene)
            .output("--out", Some(&self.out))
            .output("--json", self.json.as_deref())
    }
}

#[derive(Default, serde::Serialize)]
struct Drawn {
    files: Vec<String>,
    /// Failure maps: wrong rays per method.
    wrong: Vec<(String, usize)>,
    legend: String,
}

fn write(path: &Path, im: &Image, drawn: &mut Drawn) -> Result<(), super::Error> {
    let png = im.png()?;
    let mut staged = super::Staged::new("--out", path)?;
    staged.write_all(&png)?;
    staged.finish()?;
    println!("{} ({}x{})", path.display(), im.width, im.height);
    drawn.files.push(path.display().to_string());
    Ok(())
}

fn beside(out: &Path, suffix: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("tetwalk");
    out.with_file_name(format!("{stem}-{suffix}.png"))
}

pub fn run(a: Args) -> Status {
    // The place checked writable before any work (a probe staged there and removed).
    drop(super::Staged::new("--out", &a.out)?);
    if matches!(
        a.what,
        What::Shaded | What::Failures | What::Heat | What::OctreeHeat
    ) {
        super::view_count(a.views, "render")?;
    }
    if matches!(a.what, What::Leak | What::Predicate) && a.backend.backend != BackendKind::Cpu {
        return Err(format!(
            "--backend {}: a {} map shows every backend side by side (exact | cpu | cpu-fma | gpu when there is one); leave out --backend",
            a.backend.backend.name(),
            if a.what == What::Leak { "leak" } else { "predicate" }
        )
        .into());
    }
    if a.what == What::Leak {
        return leak(a);
    }
    if a.what == What::OctreeHeat {
        return octree_heat(a);
    }
    let methods: Vec<_> = family::parse_list::<Walks>(&a.methods)?
        .into_iter()
        .filter(|m| !m.is_reference())
        .collect();
    let json = JsonOut::new(a.json.as_deref())?;
    let (w, h) = super::size(&a.size, true, 65536)?;
    super::fits(
        &format!("--size {w}x{h}"),
        w as u128 * h as u128 * (super::BYTES_PER_PIXEL + methods.len() as u128),
    )?;
    if methods.is_empty() && matches!(a.what, What::Failures | What::Predicate) {
        return Err(format!(
            "--methods {}: nothing to draw, the reference is what the methods are drawn against",
            a.methods
        )
        .into());
    }
    let mut drawn = Drawn::default();
    match a.what {
        What::Predicate => {
            square(&a.size, w, h)?;
            let target = if a.through == "edge" {
                Target::Edge
            } else {
                Target::Vertex
            };
            let (tet, ray) =
                tets::through(a.tet_shape, 1.0, target, &mut crate::scenes::rng(a.seed))
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
            let exact =
                render::face_image(&render::predicate_grid(&case, w, reference(), &cpu)?, w);
            let (backends, gpu_name) = map_backends();
            let heading = |m: &Method| {
                format!(
                    "{}: exit face, origin moved {} ulps in x and y",
                    m.name(),
                    w / 2
                )
            };
            let panel = |m: &Method, b: &Backend| {
                Ok(render::face_image(
                    &render::predicate_grid(&case, w, m, b)?,
                    w,
                ))
            };
            let key = render::predicate_key();
            let maps = Maps {
                exact: &exact,
                backends: &backends,
                key: &key,
            };
            maps.write(&a.out, &methods, heading, panel, &mut drawn)?;
            drawn.legend = render::predicate_legend();
            println!(
                "each sheet: exact | cpu | cpu-fma{}; origin moved ±{} ulps in x (right) and y (up)",
                gpu_name.map_or(String::new(), |g| format!(" | {g}")),
                w / 2
            );
        }
        what => {
            let backend = a.backend.open()?;
            let mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
            let views = views_of(&a, w, h);
            let f = render::frame(&mesh, &views, a.view, &methods, &backend)?;
            match what {
                What::Shaded => write(&a.out, &f.shaded(), &mut drawn)?,
                What::Heat => {
                    write(&a.out, &f.heat(), &mut drawn)?;
                    drawn.legend = render::HEAT_LEGEND.into();
                }
                _ => {
                    let maps: Vec<Image> = (0..methods.len()).map(|i| f.failures(i)).collect();
                    for ((name, wrong), im) in f.wrong.iter().zip(&maps) {
                        let n = wrong.iter().flatten().count();
                        write(&beside(&a.out, name), im, &mut drawn)?;
                        println!("  {name}: {n} wrong rays");
                        drawn.wrong.push((name.clone(), n));
                    }
                    write(&a.out, &Image::sheet(&maps, 4), &mut drawn)?;
                    let kinds: Vec<_> = f
                        .wrong
                        .iter()
                        .flat_map(|(_, w)| w.iter().flatten())
                        .copied()
                        .collect();
                    drawn.legend = render::failure_legend(&kinds);
                    println!(
                        "sheet order: {}",
                        methods
                            .iter()
                            .map(|m| m.name())
                            .collect::<Vec<_>>()
                            .join(", ")
                    );
                }
            }
        }
    }
    print!("{}", drawn.legend);
    json.finish(&drawn)?;
    Ok(ExitCode::SUCCESS)
}

/// The backends a predicate or leak map is drawn on: the CPU plain and fused, and the GPU where there
/// is one (with its name).
fn map_backends() -> (Vec<Backend>, Option<String>) {
    let mut backends = vec![
        Backend::Cpu {
            model: Model::Plain,
        },
        Backend::Cpu {
            model: Model::Fused,
        },
    ];
    let gpu = Backend::open(BackendKind::Gpu).ok();
    let name = gpu.as_ref().map(|g| g.describe());
    backends.extend(gpu);
    (backends, name)
}

/// Predicate or leak maps: the exact panel, the backends each method is drawn on, the key.
struct Maps<'a> {
    exact: &'a Image,
    backends: &'a [Backend],
    key: &'a [(&'a str, [u8; 3])],
}

impl Maps<'_> {
    /// Each method's sheet (its heading, the exact panel and one per backend, each titled, and the
    /// key) written beside `out`, and all of them into `out`.
    fn write<M: Named>(
        &self,
        out: &Path,
        methods: &[&M],
        heading: impl Fn(&M) -> String,
        panel: impl Fn(&M, &Backend) -> Result<Image, render::RenderError>,
        drawn: &mut Drawn,
    ) -> Result<(), super::Error> {
        let mut sheets = Vec::new();
        for m in methods {
            let mut row = vec![("exact".to_string(), self.exact.clone())];
            for b in self.backends {
                row.push((render::backend_title(b), panel(m, b)?));
            }
            let sheet = render::sheet(&heading(m), &row, self.key);
            write(&beside(out, m.name()), &sheet, drawn)?;
            sheets.push(sheet);
        }
        write(out, &render::stacked(&sheets, 8), drawn)
    }
}

/// The views `--views` and `--seed` place, of `w × h` pixels, as `count` places them.
fn views_of(a: &Args, w: u32, h: u32) -> Views {
    Views {
        views: a.views,
        width: w,
        height: h,
        seed: a.seed,
        fov_deg: Views::FOV_DEG,
    }
}

/// A map that is square (predicate and leak maps) refuses `--size WxH` with `W ≠ H`.
fn square(text: &str, w: u32, h: u32) -> Result<(), super::Error> {
    if w != h {
        return Err(
            format!("--size {text}: this map is square, W by W pixels: give --size {w}").into(),
        );
    }
    Ok(())
}

/// `render octree-heat`: octree cells per pixel.
fn octree_heat(a: Args) -> Status {
    let names = if a.methods == "all" {
        "portalez16-direction"
    } else {
        &a.methods
    };
    let method = *family::parse_list::<OctreeCells>(names)?
        .first()
        .ok_or("--methods names no octree method")?;
    let json = JsonOut::new(a.json.as_deref())?;
    let (w, h) = super::size(&a.size, false, 4096)?;
    let mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
    let views = views_of(&a, w, h);
    let hit = family::by_name::<Triangle>("mt")?.hit(Model::Plain);
    let im = render::octree_heat(
        &mesh,
        &views,
        a.view,
        method,
        hit,
        crate::octree::Settings::PAPER,
    )?;
    let mut drawn = Drawn::default();
    write(&a.out, &im, &mut drawn)?;
    drawn.legend = render::OCTREE_HEAT_LEGEND.into();
    print!("{}", drawn.legend);
    json.finish(&drawn)?;
    Ok(ExitCode::SUCCESS)
}

/// `render leak`: a sheet per ray–triangle method, exact | cpu | cpu-fma (| gpu).
fn leak(a: Args) -> Status {
    let methods = family::parse_list::<Triangle>(&a.methods)?;
    let json = JsonOut::new(a.json.as_deref())?;
    let (w, h) = super::size(&a.size, true, 4096)?;
    square(&a.size, w, h)?;
    let (case, pair) = render::leak_case(a.shape, a.place, a.seed, &methods)
        .ok_or("no ray of the edge row crosses the surface between an edge's two triangles")?;
    let grid = render::LeakGrid::new(&case, pair, w);
    let exact = render::leak_image(grid.exact(), w);
    let (backends, gpu_name) = map_backends();
    let mut drawn = Drawn::default();
    let heading = |m: &TriangleMethod| format!("{}: hits through and beside an edge", m.name());
    let panel = |m: &TriangleMethod, b: &Backend| Ok(render::leak_image(&grid.of(m, b)?, w));
    let key = render::leak_key();
    let maps = Maps {
        exact: &exact,
        backends: &backends,
        key: &key,
    };
    maps.write(&a.out, &methods, heading, panel, &mut drawn)?;
    drawn.legend = render::leak_legend();
    println!(
        "each sheet: exact | cpu | cpu-fma{}; the {} {} edge row's first case a listed method leaks through (else its first): along x, rays exactly through the edge at points of its middle half; along y, the direction moved ±{} ulp steps off it",
        gpu_name.map_or(String::new(), |g| format!(" | {g}")),
        a.shape.name(),
        a.place.name(),
        w / 2
    );
    print!("{}", drawn.legend);
    json.finish(&drawn)?;
    Ok(ExitCode::SUCCESS)
}
