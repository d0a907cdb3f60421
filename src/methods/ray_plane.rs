//! `ray-plane`: Lagae & Dutré 2008's first method (seed 000 §2.3.2, seed 003 §2.3), after Garrity 1990:
//! intersect the ray with the face planes it is leaving through and exit where `t` is smallest.

use super::{Arith, ExitMethod, each};
use crate::tet::{FACE_VERTICES, Ray, Tet};
use glam::Vec3;

/// Face `f`'s outward normal `n = (b - a) × (c - a)` and `n · d`, as this family of methods computes them.
#[inline(always)]
pub(super) fn face_plane<A: Arith>(tet: &Tet, f: usize, dir: Vec3) -> (Vec3, f32) {
    let [a, b, c] = each(FACE_VERTICES[f], |i| tet[i]);
    let n = A::cross(b - a, c - a);
    (n, A::dot(n, dir))
}

/// Reconstructed: for each of the four faces, `n` (2 vector subtractions, a cross product) and
/// `n · d`; where `n · d > 0` the ray leaves through the plane at `t = n · (a - o) / (n · d)`; the exit
/// face is the one with the smallest `t` (strictly smaller wins, so the lowest index on a tie). Per
/// tetrahedron: 4 × (6 sub + 9 cross + 5 dot) + up to 4 × (3 sub + 5 dot + 1 div) = 80 to 116 operations.
/// The entry face is not used. `None` when no face has `n · d > 0` (or every `t` is NaN).
pub struct RayPlane;

impl ExitMethod for RayPlane {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, _entry: Option<usize>) -> Option<usize> {
        let mut best: Option<(usize, f32)> = None;
        for f in 0..4 {
            let (n, nd) = face_plane::<A>(tet, f, ray.dir);
            if nd > 0.0 {
                let a = tet[FACE_VERTICES[f][0]];
                let t = A::dot(n, a - ray.org) / nd;
                if best.is_none_or(|(_, bt)| t < bt) {
                    best = Some((f, t));
                }
            }
        }
        best.map(|(f, _)| f)
    }
}
