//! `tetwalk scene build`, `scene subdivide`, `scene export`, `scene check` and `scene info`.

use super::{JsonOut, Status};
use crate::engine::info::{SceneCheck, SceneInfo};
use crate::mesh::export::Exported;
use crate::scenes::build::build_scene;
use crate::scenes::model::Surface;
use glam::Vec3;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Subcommand)]
pub(crate) enum SceneCommand {
    /// Tetrahedralize a closed model (OFF, OBJ or ASCII PLY) in a box with the installed TetGen.
    Build {
        /// The closed model (.off, .obj or ASCII .ply).
        model: PathBuf,
        /// A quality CDT (-q1.414) instead of a pure one.
        #[arg(long)]
        quality: bool,
        /// Move the model this far along (1, 1, 1) first (rounded to f32).
        #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
        offset: f32,
        /// Output stem (writes OUT.node, OUT.ele, OUT.neigh, OUT.face); the model's stem by default.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Stop TetGen after this many seconds (each run).
        #[arg(long, allow_negative_numbers = true, default_value_t = 600.0)]
        tetgen_seconds: f64,
        /// Also write the built scene's info as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Loop-subdivide a closed model (each new point computed in f64 and rounded once to f32) and
    /// write it as OFF: the same model gives the same file, byte for byte.
    Subdivide {
        /// The closed model (.off, .obj or ASCII .ply).
        model: PathBuf,
        /// How many levels (each quadruples the triangles).
        #[arg(long, default_value_t = 1)]
        levels: u32,
        /// Where to write the OFF model (written whole, or not at all).
        #[arg(long)]
        out: PathBuf,
        /// Also write what was written (model, levels, out, points, triangles) as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Write a scene's mesh for another program's kernel (`count --rays-out` gives the rays, `judge`
    /// judges the walks): one JSON object in tetwalk's conventions (stated in its `convention` field).
    Export {
        /// A built-in scene name, a TetGen stem, or a Gmsh, VTK or MEDIT file.
        scene: String,
        /// Accept a scene without constrained faces (no TetGen `.face` or an empty one, no triangles in
        /// another format).
        #[arg(long)]
        no_faces: bool,
        /// Where to write it (written whole, or not at all).
        out: PathBuf,
    },
    /// Check a mesh as a tetrahedralization, exactly, as every command that loads one does (no overlap,
    /// fold or crack; neighbours, counts and the boundary as docs/scenes.md states): exit status 0 when
    /// it is one, 1 when it is not (what is wrong, and where, printed).
    Check {
        /// A built-in scene name, a TetGen stem, or a Gmsh, VTK or MEDIT file.
        scene: String,
        /// Accept a scene without constrained faces (no TetGen `.face` or an empty one, no triangles in
        /// another format).
        #[arg(long)]
        no_faces: bool,
        /// Also write the verdict (and, for a tetrahedralization, its counts) as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Counts, memory per layout and flatness of a scene, and seed 001's octree over its constrained
    /// faces (leaves with and without the regularity constraint, bytes per cell, the four arrays).
    Info {
        /// A built-in scene name, a TetGen stem, or a Gmsh, VTK or MEDIT file.
        scene: String,
        /// The octree's deepest level.
        #[arg(long, default_value_t = 8)]
        depth: u32,
        /// Split an octree node while it holds more triangles than this.
        #[arg(long, default_value_t = 6)]
        capacity: usize,
        /// Accept a scene without constrained faces (no TetGen `.face` or an empty one, no triangles in
        /// another format).
        #[arg(long)]
        no_faces: bool,
        /// Also write the info as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
    },
}

impl super::Io for SceneCommand {
    fn io(&self) -> super::Files {
        let none = super::Files::default();
        match self {
            SceneCommand::Build {
                model, out, json, ..
            } => {
                let stem = out.clone().unwrap_or_else(|| model.with_extension(""));
                crate::mesh::tetgen_files(&stem)
                    .iter()
                    .fold(none.input("MODEL", Some(model)), |f, p| {
                        f.output("--out", Some(p))
                    })
                    .output("--json", json.as_deref())
            }
            SceneCommand::Subdivide {
                model, out, json, ..
            } => none
                .input("MODEL", Some(model))
                .output("--out", Some(out))
                .output("--json", json.as_deref()),
            SceneCommand::Export { scene, out, .. } => {
                none.scene("SCENE", scene).output("OUT", Some(out))
            }
            SceneCommand::Check { scene, json, .. } | SceneCommand::Info { scene, json, .. } => {
                none.scene("SCENE", scene).output("--json", json.as_deref())
            }
        }
    }
}

pub(crate) fn run(s: SceneCommand) -> Status {
    match s {
        SceneCommand::Check {
            scene,
            no_faces,
            json,
        } => {
            let json = JsonOut::new(json.as_deref())?;
            // Nothing to check (no such file, a folder) is an error, not an invalid mesh.
            crate::scenes::readable(&scene)?;
            let check =
                SceneCheck::of(&scene, crate::scenes::load(&scene, super::faces(no_faces)))?;
            println!("{}", check.line());
            json.finish(&check)?;
            Ok(if check.valid {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }
        SceneCommand::Build {
            model,
            quality,
            offset,
            out,
            tetgen_seconds,
            json,
        } => {
            if !(tetgen_seconds > 0.0 && tetgen_seconds <= 1e6) {
                return Err(format!("--tetgen-seconds {tetgen_seconds} is not in (0, 1e6]").into());
            }
            let json = JsonOut::new(json.as_deref())?;
            let m = Surface::read(&model)?;
            let out = out.unwrap_or_else(|| model.with_extension(""));
            let text = out.to_string_lossy();
            if out.is_dir() || text.ends_with('/') || out.file_name().is_none() {
                return Err(format!(
                    "--out {text}: a stem names the files STEM.node, STEM.ele, STEM.neigh and STEM.face, not a folder (give, say, {}/scene)",
                    text.trim_end_matches('/')
                )
                .into());
            }
            let mesh = build_scene(
                &m,
                quality,
                Vec3::splat(offset),
                &out,
                std::time::Duration::from_secs_f64(tetgen_seconds),
            )?;
            println!("{}: {} tetrahedra", out.display(), mesh.tets.len());
            let info = SceneInfo::of(&mesh, crate::octree::Settings::PAPER);
            json.done(&info.markdown(), &info)
        }
        SceneCommand::Subdivide {
            model,
            levels,
            out,
            json,
        } => {
            if !(1..=4).contains(&levels) {
                return Err(format!("--levels {levels} is not 1 to 4").into());
            }
            let json = JsonOut::new(json.as_deref())?;
            let mut m = Surface::read(&model)?;
            for _ in 0..levels {
                m = m.loop_subdivided()?;
            }
            let mut staged = super::Staged::new("scene subdivide --out", &out)?;
            std::io::Write::write_all(&mut staged, m.off_text().as_bytes())?;
            staged.finish()?;
            println!(
                "{}: {} points, {} triangles",
                out.display(),
                m.points.len(),
                m.triangles.len()
            );
            json.finish(&serde_json::json!({
                "model": model,
                "levels": levels,
                "out": out,
                "points": m.points.len(),
                "triangles": m.triangles.len(),
            }))?;
            Ok(ExitCode::SUCCESS)
        }
        SceneCommand::Export {
            scene,
            no_faces,
            out,
        } => {
            let s = crate::scenes::load(&scene, super::faces(no_faces))?;
            let mut staged = super::Staged::new("scene export", &out)?;
            serde_json::to_writer(&mut staged, &Exported::of(&s.name, &s.mesh))?;
            staged.finish()?;
            println!(
                "{}: scene {}, {} points, {} tetrahedra",
                out.display(),
                s.name,
                s.mesh.points.len(),
                s.mesh.tets.len()
            );
            Ok(ExitCode::SUCCESS)
        }
        SceneCommand::Info {
            scene,
            depth,
            capacity,
            no_faces,
            json,
        } => {
            if depth > crate::octree::MAX_DEPTH || capacity == 0 {
                return Err(format!(
                    "--depth {depth} --capacity {capacity}: the depth is at most {} and the capacity at least 1",
                    crate::octree::MAX_DEPTH
                )
                .into());
            }
            let json = JsonOut::new(json.as_deref())?;
            let s = crate::scenes::load(&scene, super::faces(no_faces))?;
            let info = SceneInfo::of(&s.mesh, crate::octree::Settings { depth, capacity });
            println!("scene {}\n", s.name);
            json.done(&info.markdown(), &info)
        }
    }
}
