//! `tetwalk count`: wrong rays per image, per method, on a scene.

use super::{BackendArg, FailArg, JsonOut, Outcome, WgslArg};
use crate::registry::{by_name, parse_octree_list, parse_triangle_list};
use crate::report::count::{self, Settings};
use crate::report::octree as octree_report;
use crate::report::standing::Standings;
use crate::report::triangle;
use crate::report::wrong::WrongRay;
use crate::scenes::camera::Views;
use crate::tet::EVEN_PERMUTATIONS;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct Args {
    #[command(subcommand)]
    merge: Option<Merge>,
    /// Which family of methods: `exit-face` (walks through the tetrahedra, seed 000 Table 4) or
    /// `triangle` (each primary ray's nearest hit among the scene's constrained faces, every triangle
    /// tested, seed 004's methods; judged against the reference walk's exact first hit) or `octree`
    /// (each primary ray walked through seed 001's octree over those faces, judged the same way).
    #[arg(long, value_parser = ["exit-face", "triangle", "octree"], default_value = "exit-face")]
    family: String,
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
    #[arg(long, value_parser = ["1", "2", "4", "8"], default_value = "2")]
    packet: String,
    /// A built-in scene (bunny-quality, bunny-cdt, bunny-quality-far, bunny-far, kuhn, jitter, fan and
    /// their -far), or a TetGen stem.
    #[arg(long, default_value = "bunny-quality")]
    scene: String,
    /// Accept a TetGen scene without constrained faces (no `.face`, or an empty one): every ray then
    /// leaves the mesh.
    #[arg(long)]
    no_faces: bool,
    /// Viewpoints on a sphere around the model [default: 160, 16 with --family triangle, or 1282 with
    /// --preset paper].
    #[arg(long, allow_negative_numbers = true)]
    views: Option<usize>,
    /// Image size, WxH [default: 256x256 (128x128 with --family triangle), or 1024x1024 with
    /// --preset paper].
    #[arg(long)]
    size: Option<String>,
    /// Methods to judge (comma-separated, or all); the reference always runs.
    #[arg(long, default_value = "all")]
    methods: String,
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

#[derive(clap::Subcommand)]
enum Merge {
    /// Add up the JSON reports of a sharded count (`--shard I/N`, every I once) into one: walks
    /// through the tetrahedra or through the octree (`--family octree`), not both.
    Merge {
        /// The shards' reports (`count --shard I/N --json FILE`).
        #[arg(required = true)]
        reports: Vec<PathBuf>,
        /// Also write the merged report as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
}

fn merge(reports: &[PathBuf], json: Option<&std::path::Path>) -> Outcome {
    let out = JsonOut::new(json)?;
    // An octree count's report is the one with leaves.
    let (mut walks, mut octree) = (Vec::new(), Vec::new());
    let read: Vec<(String, serde_json::Value)> = super::read_reports(reports)?;
    for (file, r) in read {
        let named = |e: serde_path_to_error::Error<serde_json::Error>| {
            format!("{file}: {}: {}", e.path(), e.inner())
        };
        if r.get("leaves").is_some() {
            let report = serde_path_to_error::deserialize(r).map_err(named)?;
            octree.push((file, report));
        } else {
            let report = serde_path_to_error::deserialize(r).map_err(named)?;
            walks.push((file, report));
        }
    }
    let (text, merged) = match (walks.is_empty(), octree.is_empty()) {
        (false, true) => {
            let m: count::CountReport = count::merge(&walks)?;
            (m.markdown(), serde_json::to_value(&m)?)
        }
        (true, false) => {
            let m: octree_report::OctreeCountReport = count::merge(&octree)?;
            (m.markdown(), serde_json::to_value(&m)?)
        }
        _ => return Err("the reports count walks through the tetrahedra and through the octree: merge each family apart".into()),
    };
    print!("{text}");
    out.finish(&merged)?;
    Ok(ExitCode::SUCCESS)
}

/// `I/N` with `I < N`.
pub(super) fn shard(text: &str) -> Result<count::Shard, super::Error> {
    text.split_once('/')
        .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)))
        .filter(|&(i, n)| n >= 1 && i < n)
        .map(|(index, count)| count::Shard { index, count })
        .ok_or_else(|| format!("--shard {text} is not I/N with 0 <= I < N").into())
}

pub fn run(a: Args) -> Outcome {
    if let Some(Merge::Merge { reports, json }) = &a.merge {
        return merge(reports, json.as_deref());
    }
    let shard = shard(&a.shard)?;
    let reference = by_name(&a.reference)?;
    if a.family == "triangle" {
        return run_triangle(a);
    }
    if a.family == "octree" {
        return run_octree(a, shard);
    }
    if let Some(path) = &a.rays_out {
        return rays_out(&a, shard, path);
    }
    let fail = a.fail;
    let (backend, methods) = a.wgsl.open(a.backend, &a.methods)?;
    let methods: Vec<_> = methods
        .into_iter()
        .filter(|m| !m.reference && m.name != reference.name)
        .collect();
    let out = JsonOut::new(a.json.as_deref())?;
    let mut dump = Dump::new(a.dump.as_deref())?;
    let views = views(&a, 160, "256x256")?;
    held(shard, &views)?;
    let mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
    let settings = Settings {
        scene: a.scene,
        views,
        reference: reference.name.to_string(),
        audit: a.audit,
        shard,
    };
    let labellings: &[[usize; 4]] = if a.relabel.is_some() {
        &EVEN_PERMUTATIONS
    } else {
        &EVEN_PERMUTATIONS[..1]
    };
    let bar = super::progress((shard.held(views.views) * labellings.len()) as u64, "views");
    let mut write = |w: &WrongRay| dump.write(w);
    // The mesh's own labelling (the identity, first) gives the report and the dump.
    let mut report = count::run(
        &mesh,
        &settings,
        &methods,
        &backend,
        &|| bar.inc(1),
        Some(&mut write),
    )?;
    if labellings.len() > 1 {
        let mut wrong: Vec<[u64; 12]> =
            report.methods.iter().map(|m| [m.wrong_total; 12]).collect();
        for (k, p) in labellings.iter().enumerate().skip(1) {
            let relabelled = mesh.relabelled(*p)?;
            let r = count::run(
                &relabelled,
                &settings,
                &methods,
                &backend,
                &|| bar.inc(1),
                None,
            )?;
            for (w, m) in wrong.iter_mut().zip(&r.methods) {
                w[k] = m.wrong_total;
            }
        }
        for (m, w) in report.methods.iter_mut().zip(wrong) {
            m.relabelled = Some(w);
        }
    }
    bar.finish_and_clear();
    dump.finish()?;
    print!("{}", report.markdown());
    out.finish(&report)?;
    Ok(fail.status("count", &report.standings()))
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
    pub shard: count::Shard,
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
fn rays_out(a: &Args, shard: count::Shard, path: &std::path::Path) -> Outcome {
    if a.family == "triangle"
        || a.wgsl.wgsl.is_some()
        || a.relabel.is_some()
        || a.dump.is_some()
        || a.fail.fail_on.is_some()
    {
        return Err("--rays-out writes the inputs of an exit-face count and judges nothing: leave out --family triangle, --wgsl, --relabel, --dump and --fail-on".into());
    }
    let views = views(a, 160, "256x256")?;
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
    let (mut rays, mut counted) = (0u64, 0usize);
    for (v, cam, start) in count::located_views(&mesh, &views, |v| shard.holds(v), &|| ()) {
        counted += 1;
        for line in ray_lines(&views, v, &cam, start) {
            serde_json::to_writer(&mut w, &line)?;
            w.write_all(b"\n")?;
            rays += 1;
        }
    }
    if counted == 0 {
        return Err(count::CountError::NoView(views.views).into());
    }
    w.flush()?;
    drop(w);
    staged.finish()?;
    println!(
        "{}: {rays} rays of {counted} views of scene {} (walk them through `tetwalk scene export {}` and judge your answers with `tetwalk judge {} ANSWERS`)",
        path.display(),
        a.scene,
        a.scene,
        path.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// A shard that holds at least one of the views (`--shard 5/10` of 3 views holds none).
pub(super) fn held(shard: count::Shard, views: &Views) -> Result<(), super::Error> {
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
/// defaults given.
fn views(a: &Args, views: usize, size: &str) -> Result<Views, super::Error> {
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

/// `count --family octree`.
fn run_octree(a: Args, shard: count::Shard) -> Outcome {
    if a.relabel.is_some() || a.wgsl.wgsl.is_some() {
        return Err("--relabel and --wgsl are for --family exit-face".into());
    }
    let methods: Vec<_> = parse_octree_list(&a.methods)?
        .into_iter()
        .filter(|m| !m.reference)
        .collect();
    let octree = crate::octree::Settings {
        depth: a.depth,
        capacity: a.capacity,
    };
    octree
        .check()
        .map_err(|e| format!("--depth {} --capacity {}: {e}", a.depth, a.capacity))?;
    crate::registry::triangle_by_name(&a.triangle_method)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let views = views(&a, 16, "256x256")?;
    held(shard, &views)?;
    let mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
    let settings = octree_report::CountSettings {
        scene: a.scene,
        views,
        reference: a.reference,
        octree,
        triangle_method: a.triangle_method,
        audit: a.audit,
        shard,
    };
    let bar = super::progress(shard.held(views.views) as u64, "views");
    let backend = a.backend.open()?;
    let mut dump = Dump::new(a.dump.as_deref())?;
    let mut write = |w: &WrongRay| dump.write(w);
    let report = octree_report::count(
        &mesh,
        &settings,
        &methods,
        &backend,
        &|| bar.inc(1),
        Some(&mut write),
    )?;
    bar.finish_and_clear();
    dump.finish()?;
    print!("{}", report.markdown());
    out.finish(&report)?;
    Ok(a.fail.status("count", &report.standings()))
}

/// `count --family triangle`.
fn run_triangle(a: Args) -> Outcome {
    if a.relabel.is_some() || a.dump.is_some() || a.shard != "0/1" || a.wgsl.wgsl.is_some() {
        return Err("--relabel, --dump, --shard and --wgsl are for --family exit-face".into());
    }
    let methods = parse_triangle_list(&a.methods)?;
    let out = JsonOut::new(a.json.as_deref())?;
    let views = views(&a, 16, "128x128")?;
    let backend = a.backend.open()?;
    let mesh = crate::scenes::load(&a.scene, super::faces(a.no_faces))?;
    let settings = triangle::CountSettings {
        scene: a.scene,
        views,
        reference: a.reference,
        packet: a.packet.parse().expect("clap checked it"),
    };
    let bar = super::progress(views.views as u64, "views");
    let report = triangle::count(&mesh, &settings, &methods, &backend, &|| bar.inc(1))?;
    bar.finish_and_clear();
    print!("{}", report.markdown());
    out.finish(&report)?;
    Ok(a.fail.status("count", &report.standings()))
}
