//! Building a scene from a closed model: the model in a box, tetrahedralized by the installed TetGen
//! (Si 2015) as a constrained Delaunay tetrahedralization, with every point exactly an f32.

use super::SceneError;
use super::model::Surface;
use crate::child::ChildError;
use crate::mesh::{Mesh, load_tetgen};
use glam::Vec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

/// TetGen switches: a pure CDT keeping every input triangle as one face (`-pzAnYQ`), or a quality CDT
/// (`-pzAnYq1.414Q`).
pub(crate) fn switches(quality: bool) -> &'static str {
    if quality { "-pzAnYq1.414Q" } else { "-pzAnYQ" }
}

/// Largest coordinate magnitude a scene may have: TetGen's predicates square and cube coordinate
/// differences in f64, so stay far below its range (and the box needs room beyond the model).
pub(crate) const MAX_COORDINATE: f64 = 1e30;

/// The six faces of a box whose corner `k` has bit 0, 1 and 2 of `k` for its x, y and z (low or
/// high), each counterclockwise seen from outside.
pub const BOX_FACES: [[u32; 4]; 6] = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
];

/// The model moved by `offset` (each point rounded to f32 once), in an axis-aligned box three times its
/// half-diagonal away from its centre on every side: the points and triangles TetGen gets, box corners
/// last. Refused when the moved model or its box cannot be represented: a coordinate not finite or
/// beyond [`MAX_COORDINATE`], or a box that f32 cannot place strictly around the model.
pub(crate) fn boxed(model: &Surface, offset: Vec3) -> Result<Surface, SceneError> {
    let bad = |why: String| SceneError::Unrepresentable(why);
    if !offset.is_finite() {
        return Err(bad(format!("the offset {offset} is not finite")));
    }
    let points: Vec<Vec3> = model.points.iter().map(|&p| p + offset).collect();
    if let Some((i, p)) = points
        .iter()
        .enumerate()
        .find(|(_, p)| !p.is_finite() || p.abs().max_element() as f64 > MAX_COORDINATE)
    {
        return Err(bad(format!(
            "point {i} moved by the offset is {p}: coordinates must be finite and at most {MAX_COORDINATE:e} in magnitude"
        )));
    }
    let (lo, hi) = crate::mesh::bounds(&points);
    // In f64: a tiny model's half-diagonal underflows in f32.
    let (lo64, hi64) = (lo.as_dvec3(), hi.as_dvec3());
    let (c, r) = ((lo64 + hi64) * 0.5, (hi64 - lo64).length() * 0.5);
    let (blo, bhi) = ((c - 3.0 * r).as_vec3(), (c + 3.0 * r).as_vec3());
    let placed = blo.cmplt(lo).all()
        && bhi.cmpgt(hi).all()
        && blo.is_finite()
        && bhi.is_finite()
        && bhi.abs().max(blo.abs()).max_element() as f64 <= MAX_COORDINATE;
    if !placed {
        return Err(bad(format!(
            "f32 cannot place a box strictly around the model (bounds {lo} to {hi}; box {blo} to {bhi}): it is too small for its position, or too large"
        )));
    }
    let base = points.len() as u32;
    let mut out = Surface {
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
    for [a, b, c, d] in BOX_FACES {
        out.triangles.push([base + a, base + b, base + c]);
        out.triangles.push([base + a, base + c, base + d]);
    }
    Ok(out)
}

fn smesh(m: &Surface) -> String {
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

/// Run `tetgen ARGS scene.smesh` in `dir`, killed after `limit`: its status and everything it printed.
fn tetgen(
    dir: &Path,
    args: &str,
    limit: Duration,
) -> Result<(std::process::ExitStatus, String), SceneError> {
    let log = dir.join("tetgen.log");
    let file = std::fs::File::create(&log).map_err(SceneError::io(&log))?;
    let err = file.try_clone().map_err(SceneError::io(&log))?;
    let mut child = crate::child::spawn(
        Command::new("tetgen")
            .arg(args)
            .arg("scene.smesh")
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(file)
            .stderr(err),
    )
    .map_err(|e| match e {
        ChildError::Spawn(e) if e.kind() == std::io::ErrorKind::NotFound => SceneError::NoTetgen,
        ChildError::Spawn(e) | ChildError::Io(e) => SceneError::io(Path::new("tetgen"))(e),
        ChildError::TimedOut(_) => unreachable!("spawning has no time limit"),
    })?;
    let status = crate::child::wait(&mut child, limit).map_err(|e| match e {
        ChildError::TimedOut(_) => SceneError::TetgenTimeout {
            args: args.to_string(),
            seconds: limit.as_secs_f64(),
        },
        ChildError::Spawn(e) | ChildError::Io(e) => SceneError::io(Path::new("tetgen"))(e),
    })?;
    let text = std::fs::read(&log).map_err(SceneError::io(&log))?;
    Ok((status, String::from_utf8_lossy(&text).to_string()))
}

/// Run TetGen; when it fails, run its self-intersection check (`-d`) to say why.
fn run_tetgen(dir: &Path, args: &str, limit: Duration) -> Result<(), SceneError> {
    let (status, text) = tetgen(dir, args, limit)?;
    if status.success() && dir.join("scene.1.ele").exists() && !text.contains("terminate") {
        return Ok(());
    }
    let (_, check) = tetgen(dir, "-d", limit)?;
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

/// Rounds of rounding TetGen's added points to f32 and running it again with them before giving up.
const ROUNDS: usize = 6;

/// Build a scene from `model` and write it as TetGen files `out.{node,ele,neigh,face}`. Where TetGen
/// adds points (Steiner points) whose coordinates are not f32 values, they are rounded to f32, added to
/// its input as points, and TetGen is run again, until every point is exactly an f32; the mesh is loaded and
/// checked before anything is written. Fails, writing nothing, when that does not happen within a few
/// rounds, or TetGen fails or runs past `limit`.
pub(crate) fn build_scene(
    model: &Surface,
    quality: bool,
    offset: Vec3,
    out: &Path,
    limit: Duration,
) -> Result<Mesh, SceneError> {
    model.check_closed()?;
    let m = boxed(model, offset)?;
    // Removed when done, and by an interrupt (Ctrl-C, SIGTERM) too.
    let dir =
        crate::staged::WorkDir::new().map_err(SceneError::io(Path::new("temporary directory")))?;
    let smesh_path = dir.path().join("scene.smesh");
    std::fs::write(&smesh_path, smesh(&m)).map_err(SceneError::io(&smesh_path))?;
    run_tetgen(dir.path(), switches(quality), limit)?;
    let mut rounds = 0;
    loop {
        let (all, inexact) = inexact_points(&dir.path().join("scene.1.node"))?;
        if inexact == 0 {
            break;
        }
        if rounds == ROUNDS {
            return Err(SceneError::InexactPoints { inexact, rounds });
        }
        rounds += 1;
        // Every point TetGen added, rounded to f32, each once, made points of the input itself (which
        // TetGen tetrahedralizes before it recovers the boundary), and TetGen run again.
        let mut with = m.clone();
        for p in &all[m.points.len()..] {
            let q = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
            if !with.points.contains(&q) {
                with.points.push(q);
            }
        }
        std::fs::write(&smesh_path, smesh(&with)).map_err(SceneError::io(&smesh_path))?;
        run_tetgen(dir.path(), switches(quality), limit)?;
    }
    // Checked where it was made; only a mesh that loads is written.
    let mesh = load_tetgen(&dir.path().join("scene.1"))?;
    let mut staged = Vec::new();
    for ext in ["node", "ele", "neigh", "face"] {
        let mut to = out.as_os_str().to_owned();
        to.push(format!(".{ext}"));
        let to = PathBuf::from(to);
        let mut tmp = crate::staged::beside(&to).map_err(SceneError::io(&to))?;
        let from = dir.path().join(format!("scene.1.{ext}"));
        let mut src = std::fs::File::open(&from).map_err(SceneError::io(&from))?;
        std::io::copy(&mut src, &mut tmp).map_err(SceneError::io(&to))?;
        staged.push((tmp, to));
    }
    for (tmp, to) in staged {
        tmp.persist().map_err(SceneError::io(&to))?;
    }
    Ok(mesh)
}
