//! A mesh as `tetwalk scene export` writes it (JSON, for programs outside tetwalk), with tetwalk's
//! conventions stated once: orientation, face numbering, neighbours, constrained faces.

use super::Mesh;

/// A mesh as `scene export` writes it.
#[derive(serde::Serialize)]
pub(crate) struct Exported<'a> {
    /// The scene's name.
    pub(crate) scene: &'a str,
    /// The conventions below, in words.
    pub(crate) convention: String,
    /// The points.
    pub(crate) points: Vec<[f32; 3]>,
    /// The tetrahedra, four point indices each, positively oriented.
    pub(crate) tets: &'a [[u32; 4]],
    /// The tetrahedron across each face, -1 on the boundary.
    pub(crate) neighbors: Vec<[i64; 4]>,
    /// Whether each face is a face of the scene, where a walk stops.
    pub(crate) constrained: Vec<[bool; 4]>,
}

impl<'a> Exported<'a> {
    /// `mesh`, the scene called `scene`, as `scene export` writes it.
    pub(crate) fn of(scene: &'a str, mesh: &'a Mesh) -> Exported<'a> {
        Exported {
            scene,
            convention: format!(
                "every tetrahedron [v0, v1, v2, v3] is positively oriented: Shewchuk's orient3d(v0, v1, v2, v3) > 0 (v3 below the plane of v0, v1, v2 seen counterclockwise from above); face i is opposite vertex i, its vertices {:?} (face 0 to 3) counterclockwise seen from outside; neighbors[t][i] is the tetrahedron across face i, -1 on the boundary; constrained[t][i]: face i is a face of the scene, where a walk stops (kind hit)",
                crate::tet::FACE_VERTICES
            ),
            points: mesh.points.iter().map(|p| p.to_array()).collect(),
            tets: &mesh.tets,
            neighbors: mesh
                .neighbors
                .iter()
                .map(|n| n.map(|x| if x == super::HULL { -1 } else { x as i64 }))
                .collect(),
            constrained: (0..mesh.tets.len() as u32)
                .map(|t| std::array::from_fn(|f| mesh.is_constrained(t, f)))
                .collect(),
        }
    }
}
