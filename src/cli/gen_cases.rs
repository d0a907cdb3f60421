//! `tetwalk gen-cases`: generated (tetrahedron, ray) cases as JSON Lines, for `tetwalk exit`, or, with
//! `--shape`, closed triangle meshes and rays for `tetwalk hit`.

use super::{JsonOut, Status, choice};
use crate::cases::{Case, HitCase};
use crate::exact::classify;
use crate::family::{ExitFace, Family, Triangle};
use crate::scenes::closed::{self, MeshShape, TriAim, TriPlace};
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
    /// Within k ulps of an edge.
    NearEdge,
    /// Within k ulps of a vertex.
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
    /// In (0, 1]; smaller is flatter.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    flatness: f32,
    /// Largest ulp offset for the near-* rays.
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
    /// Write ray–triangle cases for `tetwalk hit` instead: closed meshes of this shape (`tris` lines;
    /// the stress rows' generator), with `--aim`, `--place`, `--flatness` and `--ulps`.
    #[arg(long, value_parser = choice::<MeshShape>(), conflicts_with_all = ["tet_shape", "rays", "offset", "with_entry"])]
    shape: Option<MeshShape>,
    /// With `--shape`: where the rays are aimed.
    #[arg(long, value_parser = choice::<TriAim>(), default_value = "edge", requires = "shape")]
    aim: TriAim,
    /// With `--shape`: where the mesh is placed.
    #[arg(long, value_parser = choice::<TriPlace>(), default_value = "origin", requires = "shape")]
    place: TriPlace,
    /// Also write what was generated (settings and count) as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
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
    written: usize,
}

pub fn run(a: Args) -> Status {
    super::generator(a.flatness, a.ulps)?;
    if a.count > 100_000_000 {
        return Err(format!("--count {} is more than 100,000,000 cases", a.count).into());
    }
    if !a.offset.is_finite() {
        return Err(format!("--offset {} is not finite", a.offset).into());
    }
    let out = JsonOut::new(a.json.as_deref())?;
    let mut r = rng(a.seed);
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    if let Some(shape) = a.shape {
        for _ in 0..a.count {
            let (mesh, ray) = closed::case(shape, a.aim, a.place, a.flatness, a.ulps, &mut r);
            let case = HitCase::closed(&mesh, ray).map_err(|e| e.to_string())?;
            writeln!(
                w,
                "{}",
                serde_json::Value::Object(Triangle::case_json(&case))
            )?;
        }
        w.flush()?;
        out.finish(&serde_json::json!({
            "shape": shape, "aim": a.aim, "place": a.place, "flatness": a.flatness,
            "ulps": a.ulps, "seed": a.seed, "written": a.count,
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
                let t = tets::tet(a.tet_shape, a.flatness, &mut r);
                Some((t, tets::stabbing_ray(&t, &mut r)))
            }
            Rays::Edge => tets::through(a.tet_shape, a.flatness, Target::Edge, &mut r),
            Rays::Vertex => tets::through(a.tet_shape, a.flatness, Target::Vertex, &mut r),
            Rays::NearEdge => tets::near(a.tet_shape, a.flatness, Target::Edge, a.ulps, &mut r),
            Rays::NearVertex => tets::near(a.tet_shape, a.flatness, Target::Vertex, a.ulps, &mut r),
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
        flatness: a.flatness,
        ulps: a.ulps,
        offset: a.offset,
        seed: a.seed,
        with_entry: a.with_entry,
        written,
    })?;
    Ok(ExitCode::SUCCESS)
}
