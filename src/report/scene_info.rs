//! `tetwalk scene info`: what seed 000 Table 3 and seed 003 Table 4 report of a scene, and how flat
//! its tetrahedra are.

use crate::mesh::layout::Layout;
use crate::mesh::{HULL, Mesh};
use crate::tet::{EDGES, FACE_VERTICES};

/// Counts of a scene.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SceneInfo {
    pub points: usize,
    pub tetrahedra: usize,
    /// Distinct faces that are constrained (occlusive): model and box triangles.
    pub constrained_faces: usize,
    /// Distinct faces that are not.
    pub other_faces: usize,
    /// Bytes of the tetrahedra in each layout (Tet80 is Maria et al.'s), points not included.
    pub layout_bytes: Vec<(String, usize)>,
    /// Tetrahedra per minimum dihedral angle, in 5° bins from 0°.
    pub min_dihedral_deg_5: Vec<usize>,
    /// Tetrahedra per decade of volume / (longest edge)³: bin k holds [10^-(k+1), 10^-k).
    pub volume_ratio_decades: Vec<usize>,
}

/// The smallest dihedral angle of a tetrahedron, in degrees (f64).
pub fn min_dihedral(t: &crate::tet::Tet) -> f64 {
    let p = t.map(|v| v.as_dvec3());
    let normal = |f: usize| {
        let [a, b, c] = FACE_VERTICES[f].map(|i| p[i]);
        (b - a).cross(c - a).normalize()
    };
    // The dihedral angle at the edge (i, j) is between the two faces containing it, opposite k and l.
    EDGES
        .iter()
        .map(|&[i, j]| {
            let others: Vec<usize> = (0..4).filter(|&x| x != i && x != j).collect();
            let cos = -normal(others[0]).dot(normal(others[1]));
            cos.clamp(-1.0, 1.0).acos().to_degrees()
        })
        .fold(f64::INFINITY, f64::min)
}

impl SceneInfo {
    pub fn of(mesh: &Mesh) -> SceneInfo {
        let (mut constrained, mut other) = (0, 0);
        for t in 0..mesh.tets.len() as u32 {
            for f in 0..4 {
                let nb = mesh.neighbors[t as usize][f];
                if nb == HULL || nb > t {
                    if mesh.is_constrained(t, f) {
                        constrained += 1
                    } else {
                        other += 1
                    }
                }
            }
        }
        let mut dihedral = vec![0; 19];
        let mut decades = vec![0; 12];
        for t in 0..mesh.tets.len() as u32 {
            let tet = mesh.tet(t);
            dihedral[((min_dihedral(&tet) / 5.0) as usize).min(18)] += 1;
            let p = tet.map(|v| v.as_dvec3());
            let vol = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])).abs() / 6.0;
            let longest = EDGES
                .iter()
                .map(|&[i, j]| (p[j] - p[i]).length())
                .fold(0.0, f64::max);
            let ratio = vol / longest.powi(3);
            decades[((-ratio.log10()).floor().max(0.0) as usize).min(11)] += 1;
        }
        SceneInfo {
            points: mesh.points.len(),
            tetrahedra: mesh.tets.len(),
            constrained_faces: constrained,
            other_faces: other,
            layout_bytes: Layout::BYTES
                .iter()
                .map(|(n, b)| (n.to_string(), b * mesh.tets.len()))
                .collect(),
            min_dihedral_deg_5: dihedral,
            volume_ratio_decades: decades,
        }
    }

    pub fn markdown(&self) -> String {
        let mut s = format!(
            "| points | tetrahedra | constrained faces | other faces |\n|---|---|---|---|\n| {} | {} | {} | {} |\n\n",
            self.points, self.tetrahedra, self.constrained_faces, self.other_faces
        );
        s += "| layout | MB |\n|---|---|\n";
        for (n, b) in &self.layout_bytes {
            s += &format!("| {n} | {:.2} |\n", *b as f64 / 1e6);
        }
        s += "\n| min dihedral | tetrahedra |\n|---|---|\n";
        for (k, n) in self
            .min_dihedral_deg_5
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
        {
            s += &format!("| {}–{}° | {n} |\n", 5 * k, 5 * k + 5);
        }
        s += "\n| volume / longest edge³ | tetrahedra |\n|---|---|\n";
        for (k, n) in self
            .volume_ratio_decades
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
        {
            s += &format!("| 1e-{}–1e-{} | {n} |\n", k + 1, k);
        }
        s
    }
}
