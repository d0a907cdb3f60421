//! A scene's surface as triangles: its constrained faces once each, facing the cameras' region (the
//! tetrahedra a camera sees without crossing a constrained face).

use super::{HULL, Mesh};
use crate::tet::Tri;

/// A scene's triangles, and the `(tetrahedron, face)` each came from.
pub(crate) type SceneTriangles = (Vec<Tri>, Vec<(u32, u8)>);

/// The scene's constrained faces once each as triangles facing `region` (the camera's, [`region_of`]):
/// a face between that region and another is seen from it, as a renderer's outward normal would have
/// it; with the `(tet, face)` each came from.
pub fn scene_triangles(mesh: &Mesh, region: &[bool]) -> SceneTriangles {
    let mut tris = Vec::new();
    let mut from = Vec::new();
    for t in 0..mesh.tets.len() as u32 {
        for f in 0..4 {
            let n = mesh.neighbors[t as usize][f];
            if !mesh.is_constrained(t, f) || (n != HULL && n < t) {
                continue;
            }
            // Counterclockwise seen from outside `t`: reversed when `t` is in the region.
            let [a, b, c] = mesh.face(t, f).map(|i| mesh.points[i as usize]);
            tris.push(if region[t as usize] {
                [a, c, b]
            } else {
                [a, b, c]
            });
            from.push((t, f as u8));
        }
    }
    (tris, from)
}

/// Both sides of each face of `from` (`(tetrahedron, face)`, the one on the other side next; a face
/// on the hull given twice): a walk names the face it hits from the side it comes from.
pub fn both_sides(mesh: &Mesh, from: &[(u32, u8)]) -> Vec<[(u32, u8); 2]> {
    from.iter()
        .map(|&(t, f)| {
            let n = mesh.neighbors[t as usize][f as usize];
            if n == HULL {
                [(t, f), (t, f)]
            } else {
                [(t, f), (n, mesh.mirror[t as usize][f as usize])]
            }
        })
        .collect()
}

/// The tetrahedra reached from `start` without crossing a constrained face.
pub fn region_of(mesh: &Mesh, start: u32) -> Vec<bool> {
    let mut seen = vec![false; mesh.tets.len()];
    let mut stack = vec![start];
    seen[start as usize] = true;
    while let Some(t) = stack.pop() {
        for f in 0..4 {
            let n = mesh.neighbors[t as usize][f];
            if n != HULL && !mesh.is_constrained(t, f) && !seen[n as usize] {
                seen[n as usize] = true;
                stack.push(n);
            }
        }
    }
    seen
}
