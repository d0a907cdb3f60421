//! `tetwalk count`: wrong rays per image, per method, on a scene, for every family that counts one.

use super::{BackendArg, Error, FailArg, JsonOut, Status, WgslArg};
use crate::choice::Choice;
use crate::engine::count::{self, Answerer, CountReport, CountSettings, Shard, located_views};
use crate::engine::standing::Standings;
use crate::family::CountKind;
use crate::family::count::{CountError, Counted};
use crate::family::octree::OctreeCountSettings;
use crate::family::triangle::TriCountSettings;
use crate::family::wrong::WrongRay;
use crate::family::{OctreeCells, Triangle, Walks};
use crate::registry::Named;
use crate::report::count::CountFormats;
use crate::scenes::camera::Views;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct Args {
    #[command(subcommand)]
    merge: Option<Merge>,
    /// Which family: `walk` (the exit-face methods' walks through the tetrahedra, seed 000 Table 4;
    /// `exit-face` says the same), `triangle` (each primary ray's nearest hit among the scene's
    /// constrained faces, every triangle tested, seed 004's methods) or `octree` (each primary ray
    /// walked through seed 001's octree over those faces); each judged against the reference walk's
    /// exact first hit.
    #[arg(long, value_parser = count_family(), default_value = "walk")]
    family: CountKind,
    /// `--family octree`: the octree's deepest level (seed 001: 8 for the bunny).
    #[arg(long, default_value_t = 8)]
    depth: u32,
    /// `--family octree`: split a node while it holds more triangles than this.
    #[arg(long, default_value_t = 6)]
    capacity: usize,
    /// `--family octree`: the ray–triangle method testing each leaf's triangles.
    #[arg(long, default_value = "mt")]
    triangle_method: String,
    /// `--family triangle`: primary rays per packet side (1, 2, 4 or 8: packets of 1, 4, 16 or 64
    /// rays sharing the camera's origin).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=8), default_value_t = 2)]
    packet: u32,
    /// `--family triangle`: test every triangle per ray (brute force), not each tile's candidates (the
    /// counts are the same; the candidates are derived in `src/family/triangle/bins.rs` and audited).
    #[arg(long)]
    brute_force: bool,
    /// A built-in scene (bunny-quality, bunny-cdt, bunny-quality-far, bunny-far, bunny-paper once built
    /// by corpora/scenes/bunny-paper.sh, kuhn, jitter, fan and their -far), a TetGen stem, or a Gmsh `.msh` (4.1 or 2.2), VTK `.vtk` / `.vtu` or MEDIT `.mesh`
    /// file (its triangles the constrained faces).
    #[arg(long, default_value = "bunny-quality")]
    scene: String,
    /// Accept a scene without constrained faces (no TetGen `.face` or an empty one, no triangles in
    /// another format): every ray then leaves the mesh.
    #[arg(long)]
    no_faces: bool,
    /// Viewpoints on a sphere around the model [default: 160, 16 with --family triangle or octree, or
    /// 1282 with --preset paper].
    #[arg(long, allow_negative_numbers = true)]
    views: Option<usize>,
    /// Image size, WxH [default: 256x256 (128x128 with --family triangle), or 1024x1024 with
    /// --preset paper].
    #[arg(long)]
    size: Option<String>,
    /// Methods to judge (comma-separated, or all); the reference always runs [default: all; none
    /// beside an --answerer].
    #[arg(long)]
    methods: Option<String>,
    #[command(flatten)]
    answerer: super::AnswererArg,
    /// The walk every method is judged against: `exact`, or `certified` (proven to end where `exact`
    /// ends, step for step, and several times faster).
    #[arg(long, value_parser = ["exact", "certified"], default_value = "certified")]
    reference: String,
    /// Re-judge about this many rays, chosen by the seed, with the full `exact` walk; a disagreement
    /// with the reference is an error that stops the count.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1000)]
    audit: u64,
    #[command(flatten)]
    backend: BackendArg,
    #[command(flatten)]
    wgsl: WgslArg,
    #[command(flatten)]
    fail: FailArg,
    /// Seed of the viewpoints' rotation (`render` places views the same way for the same seed).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1)]
    seed: u64,
    /// `paper`: seed 000's 1,282 views of 1024x1024.
    #[arg(long, value_parser = ["paper"])]
    preset: Option<String>,
    /// Count only views `v` with `v % N == I` (`I/N`, 0-based): one of N disjoint slices, whose reports
    /// `tetwalk count merge` adds up to the whole count's exactly.
    #[arg(long, default_value = "0/1")]
    shard: String,
    /// `all`: count again under each of the 12 orientation-preserving relabellings of the tetrahedra
    /// (the same for the whole mesh), 12 times the work, and give each method's wrong rays with the
    /// mesh's own labelling beside their min / median / max.
    #[arg(long, value_parser = ["all"])]
    relabel: Option<String>,
    /// Also write the report as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Instead of counting, write the exact inputs of every ray the count would walk, for another
    /// program's kernel: a header line (scene, views, shard), then per ray `{"view", "pixel": [x, y],
    /// "org", "dir", "start"}` (`start`: the tetrahedron holding the camera). `tetwalk scene export`
    /// writes the mesh; `tetwalk judge FILE ANSWERS` judges the walks.
    #[arg(long, value_name = "FILE")]
    rays_out: Option<PathBuf>,
    /// Write every wrong ray here, one JSON line each (view, pixel, the ray, where the method and the
    /// `exact` walk stopped, the first wrong step, the distance from the edge); `tetwalk replay` reads it.
    #[arg(long)]
    dump: Option<PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        match &self.merge {
            Some(Merge::Merge { reports, json }) => super::Files::default()
                .inputs("REPORTS", reports)
                .output("--json", json.as_deref()),
            None => super::Files::default()
                .scene("--scene", &self.scene)
                .input("--wgsl", self.wgsl.wgsl.as_deref())
                .output("--json", self.json.as_deref())
                .output("--dump", self.dump.as_deref())
                .output("--rays-out", self.rays_out.as_deref()),
        }
    }
}

#[derive(clap::Subcommand)]
enum Merge {
    /// Add up the JSON reports of a sharded count (`--shard I/N`, every I once) into one, of one
    /// family.
    Merge {
        /// The shards' reports (`count --shard I/N --json FILE`).
        #[arg(required = true)]
        reports: Vec<PathBuf>,
        /// Also write the merged report as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
}

/// `count --family`: a counted family's name, `exit-face` an alias of `walk`.
fn count_family() -> impl clap::builder::TypedValueParser<Value = CountKind> {
    use clap::builder::TypedValueParser;
    let names: Vec<&str> = CountKind::ALL.iter().map(|k| k.name()).collect();
    clap::builder::PossibleValuesParser::new(names.into_iter().chain(["exit-face"]))
        .map(|s| CountKind::from_name(&s).unwrap_or(CountKind::Walk))
}

fn merge(reports: &[PathBuf], json: Option<&std::path::Path>) -> Status {
    let out = JsonOut::new(json)?;
    let read: Vec<(String, serde_json::Value)> = super::read_reports(reports)?;
    let mut kind = None;
    for (file, r) in &read {
        let named = r
            .get("family")
            .and_then(|f| f.as_str())
            .and_then(CountKind::from_name)
            .ok_or_else(|| {
                format!("{file}: family: not a count report's family (walk, triangle or octree)")
            })?;
        match kind {
            Some(k) if k != named => {
                return Err(format!(
                    "{file}: counts {} where {} counts {}: merge each family apart",
                    named.name(),
                    read[0].0,
                    CountKind::name(k)
                )
                .into());
            }
            _ => kind = Some(named),
        }
    }
    let kind = kind.ok_or("nothing to merge")?;
    crate::with_counted!(kind, F => merged::<F>(read, out))
}

/// The shards of a count of family `F`, added up.
fn merged<F: CountFormats>(read: Vec<(String, serde_json::Value)>, out: JsonOut) -> Status {
    let mut shards: Vec<(String, CountReport<F>)> = Vec::new();
    for (file, r) in read {
        let report = serde_path_to_error::deserialize(r)
            .map_err(|e| format!("{file}: {}: {}", e.path(), e.inner()))?;
        shards.push((file, report));
    }
    let m = count::merge(&shards)?;
    print!("{}", F::count_table(&m));
    out.finish(&m)?;
    Ok(ExitCode::SUCCESS)
}

/// `I/N` with `I < N`.
pub(super) fn shard(text: &str) -> Result<Shard, Error> {
    text.split_once('/')
        .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)))
        .filter(|&(i, n)| n >= 1 && i < n)
        .map(|(index, count)| Shard { index, count })
        .ok_or_else(|| format!("--shard {text} is not I/N with 0 <= I < N").into())
}

/// What a counted family's flags set.
trait Flags: CountFormats {
    fn settings(a: &Args) -> Self::CountSettings;
}

impl Flags for Walks {
    fn settings(_: &Args) {}
}

impl Flags for Triangle {
    fn settings(a: &Args) -> TriCountSettings {
        TriCountSettings {
            packet: a.packet,
            brute_force: a.brute_force,
        }
    }
}

impl Flags for OctreeCells {
    fn settings(a: &Args) -> OctreeCountSettings {
        OctreeCountSettings {
            octree: crate::octree::Settings {
                depth: a.depth,
                capacity: a.capacity,
            },
            triangle_method: a.triangle_method.clone(),
        }
    }
}

pub fn run(a: Args) -> Status {
    if let Some(Merge::Merge { reports, json }) = &a.merge {
        return merge(reports, json.as_deref());
    }
    let shard = shard(&a.shard)?;
    crate::registry::by_name(&a.reference)?;
    if let Some(path) = &a.rays_out {
        return rays_out(&a, shard, path);
    }
    crate::with_counted!(a.family, F => counted::<F>(a, shard))
}

/// The count of family `F`.
fn counted<F: Flags>(a: Args, shard: Shard) -> Status {
    let family = F::settings(&a);
    F::check(&family)?;
    let fail = a.fail;
    let asked = a.answerer.answerer.is_some();
    if asked && F::NAME != <Walks as crate::family::Family>::NAME {
        return Err(format!(
            "--answerer walks the tetrahedra step by step (--family walk); {} counts have no exit faces to ask",
            F::NAME
        )
        .into());
    }
    if asked && a.relabel.is_some() {
        return Err("--relabel walks relabelled meshes; an --answerer is asked about the scene's own: leave out --relabel".into());
    }
    let list = match (&a.methods, asked) {
        (Some(m), _) => m.clone(),
        (None, false) => "all".into(),
        (None, true) => "none".into(),
    };
    let (backend, methods) = a
        .wgsl
        .open::<F>(a.backend, if list == "none" { "all" } else { &list })?;
    let methods = if list == "none" { Vec::new() } else { methods };
    let methods: Vec<_> = methods
        .into_iter()
        .filter(|m| !m.is_reference() && m.name() != a.reference)
        .collect();
    let out = JsonOut::new(a.json.as_deref())?;
    let mut dump = Dump::new(a.dump.as_deref())?;
    let views = views::<F>(&a)?;
    held(shard, &views)?;
    let mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
    let settings = CountSettings::<F> {
        scene: a.scene,
        views,
        reference: a.reference,
        family,
        audit: a.audit,
        shard,
    };
    let labellings = if a.relabel.is_some() {
        crate::tet::EVEN_PERMUTATIONS.len()
    } else {
        1
    };
    let bar = super::progress(
        "count",
        (shard.held(views.views) * labellings) as u64,
        "views",
    );
    let outside = a
        .answerer
        .start::<crate::family::ExitFace>(&Default::default())?;
    // Every step of every walk asked of the answerer, a view's unfinished walks in one batch.
    let asking = |_: usize, rays: &[crate::tet::Ray], start: u32, max: u32| {
        let x = outside.as_ref().expect("asked only with an answerer");
        crate::walk::walks_asking(&mesh, rays, start, max, |cases| {
            x.answers::<crate::family::ExitFace>(cases)
        })
        .map_err(|e| CountError::Given(e.to_string()))
    };
    let mut answerers: Vec<Answerer<F>> = Vec::new();
    if let Some(x) = &outside {
        answerers.push(Answerer::Given(&x.name, &asking));
    }
    answerers.extend(methods.iter().map(|m| Answerer::Method(*m)));
    let mut write = |w: &WrongRay| dump.write(w);
    // The mesh's own labelling gives the report and the dump.
    let mut report = count::run(
        &mesh,
        &settings,
        &answerers,
        &backend,
        &|| bar.inc(1),
        Some(&mut write),
    )?;
    if labellings > 1 {
        count::relabel_all(&mut report, &mesh, &answerers, &backend, &|| bar.inc(1))?;
    }
    bar.finish_and_clear();
    dump.finish()?;
    print!("{}", F::count_table(&report));
    out.finish(&report)?;
    let mut standings = report.standings();
    if let Some(x) = &outside {
        let wrong = standings
            .iter()
            .find(|s| s.method == x.name)
            .map_or(0, |s| s.wrong);
        x.claim::<crate::family::ExitFace>(&mut standings, wrong);
    }
    Ok(fail.status("count", &standings))
}

/// `--dump FILE`: every wrong ray, one JSON line each, the file complete or absent.
pub(super) struct Dump(Option<super::Staged>);

impl Dump {
    pub(super) fn new(path: Option<&std::path::Path>) -> Result<Dump, super::Error> {
        Ok(Dump(
            path.map(|p| super::Staged::new("--dump", p)).transpose()?,
        ))
    }

    pub(super) fn write(&mut self, w: &WrongRay) -> std::io::Result<()> {
        let Some(d) = self.0.as_mut() else {
            return Ok(());
        };
        serde_json::to_writer(&mut *d, w)?;
        d.write_all(b"\n")
    }

    pub(super) fn finish(self) -> Result<(), super::Error> {
        self.0.map_or(Ok(()), |d| d.finish())
    }
}

/// The header line of `count --rays-out`, which `tetwalk judge` reads back.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct RaysHeader {
    pub scene: String,
    pub views: Views,
    pub shard: Shard,
    pub tetrahedra: usize,
    /// Loaded with `--no-faces`.
    #[serde(default)]
    pub no_faces: bool,
}

/// The lines of `count --rays-out` for view `v` (camera `cam`, starting tetrahedron `start`): each
/// ray's view, pixel, origin, direction and start.
pub(super) fn ray_lines(
    views: &Views,
    v: usize,
    cam: &crate::scenes::camera::Camera,
    start: u32,
) -> impl Iterator<Item = serde_json::Value> {
    let width = views.width;
    views.rays(cam).into_iter().enumerate().map(move |(i, r)| {
        serde_json::json!({
            "view": v, "pixel": [i as u32 % width, i as u32 / width],
            "org": r.org.to_array(), "dir": r.dir.to_array(), "start": start,
        })
    })
}

/// `count --rays-out FILE`: every ray of the views the shard holds whose camera is inside the mesh,
/// with its view, pixel and starting tetrahedron.
fn rays_out(a: &Args, shard: Shard, path: &std::path::Path) -> Status {
    if a.family != CountKind::Walk
        || a.wgsl.wgsl.is_some()
        || a.relabel.is_some()
        || a.dump.is_some()
        || a.fail.fail_on.is_some()
    {
        return Err("--rays-out writes the inputs of a walk count and judges nothing: leave out --family triangle or octree, --wgsl, --relabel, --dump and --fail-on".into());
    }
    let views = views::<Walks>(a)?;
    held(shard, &views)?;
    let mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
    let mut staged = super::Staged::new("--rays-out", path)?;
    let header = RaysHeader {
        scene: a.scene.clone(),
        views,
        shard,
        tetrahedra: mesh.tets.len(),
        no_faces: a.no_faces,
    };
    let mut w = std::io::BufWriter::new(&mut staged);
    serde_json::to_writer(&mut w, &header)?;
    w.write_all(b"\n")?;
    let (mut rays, mut counted_views) = (0u64, 0usize);
    for (v, cam, start) in located_views(&mesh, &views, |v| shard.holds(v), &|| ()) {
        counted_views += 1;
        for line in ray_lines(&views, v, &cam, start) {
            serde_json::to_writer(&mut w, &line)?;
            w.write_all(b"\n")?;
            rays += 1;
        }
    }
    if counted_views == 0 {
        return Err(crate::family::count::CountError::NoView(views.views).into());
    }
    w.flush()?;
    drop(w);
    staged.finish()?;
    println!(
        "{}: {} of {} of scene {} (walk them through `tetwalk scene export {}` and judge your answers with `tetwalk judge {} ANSWERS`)",
        path.display(),
        crate::report::counted(rays, "ray", "rays"),
        crate::report::counted(counted_views as u64, "view", "views"),
        a.scene,
        a.scene,
        path.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// A shard that holds at least one of the views (`--shard 5/10` of 3 views holds none).
pub(super) fn held(shard: Shard, views: &Views) -> Result<(), super::Error> {
    if shard.held(views.views) == 0 {
        return Err(format!(
            "--shard {}/{} holds no view of the {} (views v with v % {} == {})",
            shard.index, shard.count, views.views, shard.count, shard.index
        )
        .into());
    }
    Ok(())
}

/// The views a count asks for: `--views` and `--size`, else seed 000's with `--preset paper`, else the
/// family's.
fn views<F: Counted>(a: &Args) -> Result<Views, super::Error> {
    let (views, size) = F::DEFAULT_VIEWS;
    let paper = a.preset.is_some();
    let views = super::view_count(a.views.unwrap_or(if paper { 1282 } else { views }), "count")?;
    let size = a
        .size
        .clone()
        .unwrap_or_else(|| if paper { "1024x1024" } else { size }.into());
    let (width, height) = super::size(&size, false, 65536)?;
    super::fits(
        &format!("--size {width}x{height}"),
        width as u128 * height as u128 * super::BYTES_PER_PIXEL,
    )?;
    Ok(Views {
        views,
        width,
        height,
        seed: a.seed,
        fov_deg: Views::FOV_DEG,
    })
}
