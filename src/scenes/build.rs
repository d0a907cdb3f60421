//! Building a scene from a closed model: the model in a box, tetrahedralized by the installed TetGen
//! (Si 2015) as a constrained Delaunay tetrahedralization, with every point exactly an f32.

use super::SceneError;
use super::model::Model;
use crate::mesh::{Mesh, load_tetgen};
use glam::Vec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// TetGen switches: a pure CDT keeping every input triangle as one face (`-pzAnYQ`), or a quality CDT
/// (`-pzAnYq1.414Q`).
pub fn switches(quality: bool) -> &'static str {
    if quality { "-pzAnYq1.414Q" } else { "-pzAnYQ" }
}

/// The model moved by `offset` (rounded to f32), in an axis-aligned box three times its half-diagonal
/// away from its centre on every side: the points and triangles TetGen gets, box corners last.
pub fn boxed(model: &Model, offset: Vec3) -> Model {
    let points: Vec<Vec3> = model.points.iter().map(|&p| p + offset).collect();
    let (lo, hi) = crate::mesh::bounds(&points);
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    let (blo, bhi) = (c - Vec3::splat(3.0 * r), c + Vec3::splat(3.0 * r));
    let base = points.len() as u32;
    let mut out = Model {
        points,
        triangles: model.triangles.clone(),
    };
    for k in 0..8 {
        out.points.push(Vec3::new(
            if k & 1 == 0 { blo.x } else { bhi.x },
            if k & 2 == 0 { blo.y } else { bhi.y },
            if k & 4 == 0 { blo.z } else { bhi.z },
        ));
    }
    for [a, b, c, d] in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ] {
        out.triangles.push([base + a, base + b, base + c]);
        out.triangles.push([base + a, base + c, base + d]);
    }
    out
}

fn smesh(m: &Model) -> String {
    let mut s = format!("{} 3 0 0\n", m.points.len());
    for (i, p) in m.points.iter().enumerate() {
        // f32 widened to f64 prints a decimal that reads back as exactly that value.
        let _ = writeln!(s, "{i} {:?} {:?} {:?}", p.x as f64, p.y as f64, p.z as f64);
    }
    let _ = writeln!(s, "{} 0", m.triangles.len());
    for t in &m.triangles {
        let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
    }
    s + "0\n0\n"
}

/// Run `tetgen ARGS scene.smesh` in `dir`: its status and everything it printed.
fn tetgen(dir: &Path, args: &str) -> Result<(std::process::ExitStatus, String), SceneError> {
    let out = Command::new("tetgen")
        .arg(args)
        .arg("scene.smesh")
        .current_dir(dir)
        .output()
        .map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                SceneError::NoTetgen
            } else {
                SceneError::io(Path::new("tetgen"))(e)
            }
        })?;
    Ok((
        out.status,
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr),
    ))
}

/// Run TetGen; when it fails, run its self-intersection check (`-d`) to say why.
fn run_tetgen(dir: &Path, args: &str) -> Result<(), SceneError> {
    let (status, text) = tetgen(dir, args)?;
    if status.success() && dir.join("scene.1.ele").exists() && !text.contains("terminate") {
        return Ok(());
    }
    let (_, check) = tetgen(dir, "-d")?;
    if let Some(line) = check.lines().find(|l| l.contains("intersecting")) {
        return Err(SceneError::SelfIntersecting(
            line.trim_matches(|c| c == '!' || c == ' ').to_string(),
        ));
    }
    Err(SceneError::Tetgen {
        args: args.to_string(),
        status: status.to_string(),
        output: text.trim().to_string(),
    })
}

/// Coordinates of TetGen's `.node` that are not exactly f32 values (Steiner points), rounded.
fn inexact_points(node: &Path) -> Result<(Vec<[f64; 3]>, usize), SceneError> {
    let text = std::fs::read_to_string(node).map_err(SceneError::io(node))?;
    let mut all = Vec::new();
    for line in text.lines().skip(1) {
        let w: Vec<f64> = line
            .split('#')
            .next()
            .unwrap_or("")
            .split_whitespace()
            .filter_map(|x| x.parse().ok())
            .collect();
        if w.len() >= 4 {
            all.push([w[1], w[2], w[3]]);
        }
    }
    let inexact = all
        .iter()
        .filter(|p| p.iter().any(|&x| (x as f32) as f64 != x))
        .count();
    Ok((all, inexact))
}

/// Build a scene from `model` and write it as TetGen files `out.{node,ele,neigh,face}`. Where TetGen
/// adds points (quality refinement) whose coordinates are not f32 values, they are rounded to f32 and
/// TetGen is run again inserting them (`-i`), so that the mesh is valid for its f32 coordinates exactly.
pub fn build_scene(
    model: &Model,
    quality: bool,
    offset: Vec3,
    out: &Path,
) -> Result<Mesh, SceneError> {
    model.check_closed()?;
    let m = boxed(model, offset);
    let dir = tempfile::tempdir().map_err(SceneError::io(Path::new("temporary directory")))?;
    let smesh_path = dir.path().join("scene.smesh");
    std::fs::write(&smesh_path, smesh(&m)).map_err(SceneError::io(&smesh_path))?;
    run_tetgen(dir.path(), switches(quality))?;
    for _ in 0..3 {
        let (all, inexact) = inexact_points(&dir.path().join("scene.1.node"))?;
        if inexact == 0 {
            break;
        }
        let extra: Vec<_> = all[m.points.len()..]
            .iter()
            .map(|p| p.map(|x| x as f32 as f64))
            .collect();
        let mut s = format!("{} 3 0 0\n", extra.len());
        for (i, p) in extra.iter().enumerate() {
            let _ = writeln!(s, "{i} {:?} {:?} {:?}", p[0], p[1], p[2]);
        }
        let node = dir.path().join("scene.a.node");
        std::fs::write(&node, s).map_err(SceneError::io(&node))?;
        run_tetgen(dir.path(), "-pzAnYiQ")?;
    }
    for ext in ["node", "ele", "neigh", "face"] {
        let mut to = out.as_os_str().to_owned();
        to.push(format!(".{ext}"));
        let to = PathBuf::from(to);
        std::fs::copy(dir.path().join(format!("scene.1.{ext}")), &to)
            .map_err(SceneError::io(&to))?;
    }
    Ok(load_tetgen(out)?)
}
