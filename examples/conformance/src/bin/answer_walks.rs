//! A user's walker outside tetwalk, as a C++ or CUDA program would be: it reads the mesh that `tetwalk
//! scene export` wrote and the rays that `tetwalk count --rays-out` wrote, walks every ray with one of
//! this crate's exit tests, and prints one answer per ray for `tetwalk judge`.
//!
//! Usage: answer-walks exact|f32 MESH.json RAYS.jsonl > ANSWERS.jsonl

use serde_json::{Value, json};
use std::io::{BufRead, Write};
use tetwalk::kit::prelude::*;
use tetwalk_conformance_example::{ExactPlucker, F32Plucker};

/// The exported mesh, as this program keeps it.
struct Mesh {
    points: Vec<Vec3>,
    tets: Vec<[usize; 4]>,
    neighbors: Vec<[i64; 4]>,
    constrained: Vec<[bool; 4]>,
}

fn read_mesh(path: &str) -> Result<Mesh, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
    fn field<T: serde::de::DeserializeOwned>(v: &Value, path: &str, k: &str) -> Result<T, String> {
        serde_json::from_value(v[k].clone()).map_err(|e| format!("{path}: {k}: {e}"))
    }
    let points: Vec<[f32; 3]> = field(&v, path, "points")?;
    Ok(Mesh {
        points: points.into_iter().map(Vec3::from).collect(),
        tets: field(&v, path, "tets")?,
        neighbors: field(&v, path, "neighbors")?,
        constrained: field(&v, path, "constrained")?,
    })
}

/// Walk `ray` from `start` with exit test `M` until it stops on a constrained face, leaves the mesh,
/// finds no exit face, or comes back to a state it was in (Brent's cycle detection on tetrahedron and
/// entry face); capped at 8 steps per tetrahedron.
fn walk<M: ExitMethod>(mesh: &Mesh, ray: &Ray, start: usize) -> Value {
    let r = M::prepare::<Plain>(ray);
    let (mut tet, mut entry) = (start, None);
    let (mut saved, mut power, mut lam) = ((tet, entry), 1u32, 0u32);
    let limit = 8 * mesh.tets.len() as u32 + 64;
    for steps in 1..=limit {
        let t: Tet = mesh.tets[tet].map(|i| mesh.points[i]);
        let Some(f) = M::exit_face::<Plain>(&t, &r, entry) else {
            return json!({"kind": "no_exit_face", "tet": tet, "steps": steps});
        };
        if mesh.constrained[tet][f] {
            return json!({"kind": "hit", "tet": tet, "face": f, "steps": steps});
        }
        let next = mesh.neighbors[tet][f];
        if next < 0 {
            return json!({"kind": "left_mesh", "tet": tet, "face": f, "steps": steps});
        }
        let next = next as usize;
        entry = mesh.neighbors[next].iter().position(|&n| n == tet as i64);
        tet = next;
        lam += 1;
        if (tet, entry) == saved {
            return json!({"kind": "cycle", "tet": tet, "period": lam, "steps": steps});
        }
        if lam == power {
            (saved, power, lam) = ((tet, entry), power * 2, 0);
        }
    }
    json!({"kind": "step_limit", "tet": tet, "steps": limit})
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let [_, method, mesh, rays] = &args[..] else {
        return Err("usage: answer-walks exact|f32 MESH.json RAYS.jsonl".into());
    };
    let walk: fn(&Mesh, &Ray, usize) -> Value = match method.as_str() {
        "exact" => walk::<ExactPlucker>,
        "f32" => walk::<F32Plucker>,
        other => return Err(format!("{other}: not exact or f32")),
    };
    let mesh = read_mesh(mesh)?;
    let file = std::fs::File::open(rays).map_err(|e| format!("{rays}: {e}"))?;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    // The first line is the header (scene, views); every other line is one ray.
    for (n, line) in std::io::BufReader::new(file).lines().enumerate().skip(1) {
        let line = line.map_err(|e| format!("{rays}:{}: {e}", n + 1))?;
        let r: Value = serde_json::from_str(&line).map_err(|e| format!("{rays}:{}: {e}", n + 1))?;
        let v3 = |k: &str| -> Result<Vec3, String> {
            serde_json::from_value::<[f32; 3]>(r[k].clone())
                .map(Vec3::from)
                .map_err(|e| format!("{rays}:{}: {k}: {e}", n + 1))
        };
        let ray = Ray {
            org: v3("org")?,
            dir: v3("dir")?,
        };
        let start = r["start"]
            .as_u64()
            .ok_or(format!("{rays}:{}: start", n + 1))? as usize;
        let mut a = walk(&mesh, &ray, start);
        a["view"] = r["view"].clone();
        a["pixel"] = r["pixel"].clone();
        writeln!(out, "{a}").map_err(|e| e.to_string())?;
    }
    out.flush().map_err(|e| e.to_string())
}
