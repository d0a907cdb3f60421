//! Locating the tetrahedron that holds a point, exactly, under the same symbolic perturbation of the
//! point as [`crate::exact::perturbed_exit`], so the answer is one tetrahedron even on shared faces.

use crate::exact::perturbed_orient;
use crate::mesh::{HULL, Mesh};
use crate::tet::FACE_VERTICES;
use glam::Vec3;

/// The point is in no tetrahedron of the mesh.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("the point {0:?} lies outside the mesh")]
pub struct LocateError(pub [f32; 3]);

/// Whether (perturbed) `p` is strictly beyond face `f` of tetrahedron `t`.
fn beyond(mesh: &Mesh, t: u32, f: usize, p: Vec3) -> bool {
    let [a, b, c] = FACE_VERTICES[f].map(|i| mesh.points[mesh.tets[t as usize][i] as usize]);
    perturbed_orient(a, b, c, p) < 0
}

/// The tetrahedron holding `p`: a visibility walk from `start` (faces tried in rotating order, which
/// keeps it from circling in non-Delaunay meshes), then, if that runs long or reaches the boundary of a
/// non-convex mesh, a scan of every tetrahedron.
pub fn locate(mesh: &Mesh, p: Vec3, start: u32) -> Result<u32, LocateError> {
    let n = mesh.tets.len() as u32;
    if n == 0 || !p.is_finite() {
        return Err(LocateError(p.to_array()));
    }
    let mut t = start.min(n - 1);
    let mut rot = 0usize;
    'walk: for _ in 0..4 * n.min(1 << 20) {
        for k in 0..4 {
            let f = (rot + k) % 4;
            if beyond(mesh, t, f, p) {
                let nb = mesh.neighbors[t as usize][f];
                if nb == HULL {
                    break 'walk;
                }
                t = nb;
                rot = rot.wrapping_mul(5).wrapping_add(f + 1);
                continue 'walk;
            }
        }
        return Ok(t);
    }
    (0..n)
        .find(|&t| (0..4).all(|f| !beyond(mesh, t, f, p)))
        .ok_or(LocateError(p.to_array()))
}
