//! parry3d (f32) answering tetwalk's closed-mesh cases: reads `gen-cases --shape …` lines on standard
//! input, writes one answer per case for `tetwalk judge CASES ANSWERS`: `{"line": n, "tri": i, "t":
//! t}` for parry's nearest hit of the ray on the mesh's triangles (`TriMesh::cast_local_ray_and_get_normal`,
//! solid off: the surface, from either side), or `{"line": n, "tri": null}` for a miss.

use parry3d::math::{Point, Vector};
use parry3d::query::{Ray, RayCast};
use parry3d::shape::{FeatureId, TriMesh};
use serde_json::{Value, json};
use std::io::{BufRead, Write};

fn point(v: &Value) -> Point<f32> {
    let c = |i: usize| v[i].as_f64().expect("a case's coordinates are numbers") as f32;
    Point::new(c(0), c(1), c(2))
}

fn main() {
    let out = std::io::stdout();
    let mut out = std::io::BufWriter::new(out.lock());
    for (i, line) in std::io::stdin().lock().lines().enumerate() {
        let line = line.expect("standard input is text");
        if line.trim().is_empty() {
            continue;
        }
        let n = i + 1;
        let case: Value = serde_json::from_str(&line).expect("a case line is JSON");
        let tris = case["tris"]
            .as_array()
            .expect("a closed-mesh case (gen-cases --shape)");
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for t in tris {
            let k = vertices.len() as u32;
            for c in 0..3 {
                vertices.push(point(&t[c]));
            }
            indices.push([k, k + 1, k + 2]);
        }
        let mesh = TriMesh::new(vertices, indices);
        let org = point(&case["org"]);
        let d = point(&case["dir"]);
        let ray = Ray::new(org, Vector::new(d.x, d.y, d.z));
        let answer = match mesh.cast_local_ray_and_get_normal(&ray, f32::MAX, false) {
            // A back face's feature is its index plus the triangle count.
            Some(hit) => match hit.feature {
                FeatureId::Face(face) => {
                    json!({"line": n, "tri": face % tris.len() as u32, "t": hit.time_of_impact})
                }
                _ => json!({"line": n, "tri": null}),
            },
            None => json!({"line": n, "tri": null}),
        };
        writeln!(out, "{answer}").expect("standard output is writable");
    }
}
