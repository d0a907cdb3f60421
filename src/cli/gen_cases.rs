//! `tetwalk gen-cases`: generated (tetrahedron, ray) cases as JSON Lines, for `tetwalk exit`.

use crate::cases::Case;
use crate::exact::classify;
use crate::scenes::rng;
use crate::scenes::tets::{self, Family, Target};
use glam::Vec3;
use std::io::Write;
use std::process::ExitCode;

/// How the ray meets the tetrahedron.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
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
    #[arg(long, value_enum, default_value = "well")]
    family: Family,
    #[arg(long, value_enum, default_value = "stab")]
    rays: Rays,
    /// In (0, 1]; smaller is flatter.
    #[arg(long, default_value_t = 1.0)]
    flatness: f32,
    /// Largest ulp offset for the near-* rays.
    #[arg(long, default_value_t = 4)]
    ulps: i32,
    /// Move each case this far from the origin along (1, 1, 1) (rounded to f32).
    #[arg(long, default_value_t = 0.0)]
    offset: f32,
    #[arg(long, default_value_t = 100)]
    count: usize,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Give each case its exact entry face (the lowest one) when it has one.
    #[arg(long)]
    with_entry: bool,
}

pub fn run(a: Args) -> Result<ExitCode, String> {
    if !(a.flatness > 0.0 && a.flatness <= 1.0) {
        return Err(format!("--flatness {} is not in (0, 1]", a.flatness));
    }
    let mut r = rng(a.seed);
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    let mut written = 0;
    for _ in 0..a.count.saturating_mul(100) {
        if written == a.count {
            break;
        }
        let generated = match a.rays {
            Rays::Stab => {
                let t = tets::tet(a.family, a.flatness, &mut r);
                Some((t, tets::stabbing_ray(&t, &mut r)))
            }
            Rays::Edge => tets::through(a.family, a.flatness, Target::Edge, &mut r),
            Rays::Vertex => tets::through(a.family, a.flatness, Target::Vertex, &mut r),
            Rays::NearEdge => tets::near(a.family, a.flatness, Target::Edge, a.ulps, &mut r),
            Rays::NearVertex => tets::near(a.family, a.flatness, Target::Vertex, a.ulps, &mut r),
        };
        let Some((t, ray)) =
            generated.and_then(|(t, ray)| tets::translated(&t, &ray, Vec3::splat(a.offset)))
        else {
            continue;
        };
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
        let line = serde_json::to_string(&case).map_err(|e| e.to_string())?;
        writeln!(w, "{line}").map_err(|e| e.to_string())?;
        written += 1;
    }
    if written < a.count {
        return Err(format!(
            "only {written} of {} cases could be generated with these settings",
            a.count
        ));
    }
    Ok(ExitCode::SUCCESS)
}
