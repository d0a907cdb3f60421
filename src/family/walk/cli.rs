//! The walk family on the command line (a file of the command line's layer in the family's folder):
//! the `stress` flags that choose its rows, what `count` asks of it (an answerer asked step by step,
//! `--rays-out`), and the rays file `judge` reads back.

use super::{WalkRows, WalkScene, Walks};
use crate::cli::choice;
use crate::cli::count::{Args, FamilyFlags, Flags, held, views};
use crate::cli::stress::{Rows, Shape, or_all};
use crate::cli::{AnswererArg, Error, Status};
use crate::engine::answerer::Answerer;
use crate::engine::count::{GivenWalks, Shard, located_views};
use crate::family::ExitFace;
use crate::family::count::CountError;
use crate::mesh::Mesh;
use crate::scenes::camera::Views;
use crate::tet::Ray;
use std::io::Write;
use std::process::ExitCode;

/// Walk rows.
#[derive(clap::Args)]
pub struct StressFlags {
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
pub struct CountFlags {}

impl Flags for Walks {
    type Flags = CountFlags;
    fn own(all: &FamilyFlags) -> &CountFlags {
        &all.walk
    }
    fn settings(_: &CountFlags) {}
    const ASKS: bool = true;
    /// Started for exit-face cases: each step of a walk is one.
    fn start(a: &AnswererArg) -> Result<Option<Answerer>, Error> {
        a.start::<ExitFace>(&Default::default())
    }
    /// Every step of every walk asked of the answerer, a view's unfinished walks in one batch.
    fn asking<'a>(x: &'a Answerer, mesh: &'a Mesh) -> Option<Box<GivenWalks<'a>>> {
        Some(Box::new(move |_, rays: &[Ray], start, max| {
            crate::walk::walks_asking(mesh, rays, start, max, |cases| x.answers::<ExitFace>(cases))
                .map_err(|e| CountError::Given(e.to_string()))
        }))
    }
    /// `count --rays-out FILE`: every ray of the views the shard holds whose camera is inside the mesh,
    /// with its view, pixel and starting tetrahedron.
    fn rays_out(a: &Args, shard: Shard, path: &std::path::Path) -> Status {
        let views = views::<Walks>(a)?;
        held(shard, &views)?;
        let mesh = crate::scenes::load(&a.scene, crate::cli::faces(a.no_faces))?;
        let mut staged = crate::cli::Staged::new("--rays-out", path)?;
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
}

/// The header line of `count --rays-out`, which `tetwalk judge` reads back.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct RaysHeader {
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
pub fn ray_lines(
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
